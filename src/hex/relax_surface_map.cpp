// relax_surface_map(): §5.2.1's local relaxation of the surface map Q -> P.
//
// Q's points are first projected onto the polycube P along their charts' axes (see
// polycube_hex_mesh.cpp). Where Q's chart borders do not run along P's edges (the window
// optimisation and the plane merging of chapter 4 move P's facets by up to a few voxels),
// neighbouring points land on different facets, or in the wrong order on one facet, and some
// of Q's triangles come out folded on P. A folded boundary triangle pins an inverted boundary
// tet in the volumetric map: no interior point can unfold it (measured: of the rocker arm's
// 1,624 tets inverted before untangling, 1,273 touch one of its 1,018 folded triangles).
//
// The relaxation moves the points of folded triangles, and rings of points around them, on P.
// A triangle's orientation is measured against P's outward normal where its image lies: the
// mean of its points' normals, a point's normal being the sum of the axes of the facets it
// lies on (two on an edge of P, three at a corner). Folded means its image's normal does not
// point out (a degenerate image counts as folded). Each
// free point first takes Gauss-Newton steps, in the plane of its facet and projected back onto
// P, on Knupp's untangling function of its triangles, sum (A_min - A_t)^2 over the triangles
// whose signed image area A_t (along the outward normal) is below A_min = 5% of the source
// triangle's area: the surface analogue of the tet untangling in volumetric_map.cpp. A_t is
// linear in the point, so a step solves the active triangles' least squares. If that does not
// lower the function, the point tries the projection of the centroid of its neighbours (a full
// step, a half, a quarter) and keeps the first that raises the worst orientation of its
// triangles without raising the function. When three sweeps unfold nothing, one more ring of
// points around the folds is set free. Centroid steps alone (the first version) left 76 of the
// hand's 303 folds and 252 of the rocker arm's 758; with the Gauss-Newton steps, none.
#include "structmesh/hex.hpp"
#include "structmesh/polycube.hpp"

#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <vector>

namespace structmesh {

namespace {

struct Relaxation {
  const TriMesh& source;
  std::vector<Vec3>& image;
  const SurfaceProjection& onto_target;
  std::vector<int> facet_label;    // per target triangle: its axis label (-1: degenerate)
  double touching = 0;             // distance within which a point lies on a facet
  std::vector<Vec3> point_normal;  // per image point: the target's unit normal there
  CompressedRows triangles_of;

  // The target's outward normal where the image of triangle `tri` lies: the mean of its
  // points' normals.
  Vec3 outward(const std::array<Index, 3>& tri) const {
    const Vec3 sum = point_normal[tri[0]] + point_normal[tri[1]] + point_normal[tri[2]];
    return sum.squaredNorm() > 0 ? Vec3(sum.normalized()) : Vec3::Zero();
  }

  double orientation(std::size_t t) const {
    const auto& tri = source.triangles[t];
    const Vec3 normal = (image[tri[1]] - image[tri[0]]).cross(image[tri[2]] - image[tri[0]]);
    const Vec3 reference = outward(tri);
    const double length = normal.norm() * reference.norm();
    return length > 0 ? normal.dot(reference) / length : 0.0;
  }

  double worst_around(Index point) const {
    double worst = 1;
    for (Index t : triangles_of.row(point)) worst = std::min(worst, orientation(t));
    return worst;
  }

  std::vector<double> least_area;  // per source triangle: the image area it should keep

  // Knupp's untangling function on the surface: sum over the point's triangles of
  // (least area - signed area along the reference normal)^2 where positive, and (when asked)
  // the Gauss-Newton normal equations; the signed area is linear in the point.
  double untangle_energy(Index point, Eigen::Matrix3d* normal, Vec3* rhs) const {
    double energy = 0;
    if (normal) normal->setZero(), rhs->setZero();
    for (Index t : triangles_of.row(point)) {
      const auto& tri = source.triangles[t];
      const Vec3 reference = outward(tri);
      const double area = 0.5 * (image[tri[1]] - image[tri[0]]).cross(image[tri[2]] - image[tri[0]]).dot(reference);
      const double gap = least_area[t] - area;
      if (!(gap > 0)) continue;
      energy += gap * gap;
      if (normal) {
        const int local = tri[0] == point ? 0 : tri[1] == point ? 1 : 2;
        const Vec3& b = image[tri[(local + 1) % 3]];
        const Vec3& c = image[tri[(local + 2) % 3]];
        const Vec3 gradient = 0.5 * reference.cross(c - b);
        *normal += gradient * gradient.transpose();
        *rhs += gap * gradient;
      }
    }
    return energy;
  }

  // The closest point of the target, and the target's normal there: the sum of the axes of
  // the facets it lies on (two on an edge of a polycube, three at a corner), so that a
  // triangle of one facet with points on two of its edges is still measured against it.
  Vec3 project(const Vec3& p, Vec3& normal) const {
    const Vec3 q = onto_target.closest_point(p);
    thread_local std::vector<Index> near;
    near.clear();
    onto_target.triangles_near(q, touching, near);
    unsigned labels = 0;
    for (const Index t : near) labels |= facet_label[t] >= 0 ? 1u << facet_label[t] : 0u;
    normal.setZero();
    for (int label = 0; label < kAxisLabels; ++label)
      if (labels & (1u << label)) normal += axis_of_label(label);
    if (normal.squaredNorm() > 0) normal.normalize();
    return q;
  }
};

}  // namespace

SurfaceMapRelaxation relax_surface_map(const TriMesh& source, std::vector<Vec3>& image, const TriMesh& target,
                                       const SurfaceProjection& onto_target, int max_sweeps) {
  SurfaceMapRelaxation result;
  Relaxation r{source, image, onto_target, {}, 0.0, {}, build_vertex_elements(source.triangles, image.size()), {}};
  r.facet_label.resize(target.triangles.size());
  for (std::size_t t = 0; t < target.triangles.size(); ++t) {
    const auto& tri = target.triangles[t];
    const Vec3 normal =
        (target.points[tri[1]] - target.points[tri[0]]).cross(target.points[tri[2]] - target.points[tri[0]]);
    r.facet_label[t] = normal.squaredNorm() > 0 ? nearest_axis_label(normal) : -1;
  }
  Eigen::AlignedBox3d bounds;
  for (const Vec3& p : target.points) bounds.extend(p);
  r.touching = 1e-9 * bounds.diagonal().norm();
  r.least_area.resize(source.triangles.size());
  for (std::size_t t = 0; t < source.triangles.size(); ++t) {
    const auto& tri = source.triangles[t];
    r.least_area[t] =
        0.05 * 0.5 *
        (source.points[tri[1]] - source.points[tri[0]]).cross(source.points[tri[2]] - source.points[tri[0]]).norm();
  }
  r.point_normal.resize(image.size());
  tbb::parallel_for(std::size_t{0}, image.size(), [&](std::size_t v) { r.project(image[v], r.point_normal[v]); });

  std::vector<std::uint8_t> free(image.size(), 0), moved(image.size(), 0), stuck(image.size(), 0);
  // Per triangle: folded or not, recomputed only for the triangles of points that moved (the
  // orientation of a triangle across an edge of P costs a closest-point query).
  std::vector<std::uint8_t> folded_flag(source.triangles.size());
  tbb::parallel_for(std::size_t{0}, source.triangles.size(),
                    [&](std::size_t t) { folded_flag[t] = r.orientation(t) <= 0; });
  auto count_folded = [&] { return static_cast<std::size_t>(std::count(folded_flag.begin(), folded_flag.end(), 1)); };
  // Points of folded triangles and `rings` rings around them.
  auto mark_free = [&](int rings) {
    std::fill(free.begin(), free.end(), 0);
    for (std::size_t t = 0; t < source.triangles.size(); ++t)
      if (folded_flag[t])
        for (Index v : source.triangles[t]) free[v] = 1;
    for (int ring = 0; ring < rings; ++ring) {
      std::vector<std::uint8_t> grown = free;
      for (const auto& tri : source.triangles)
        if (free[tri[0]] || free[tri[1]] || free[tri[2]])
          for (Index v : tri) grown[v] = 1;
      free.swap(grown);
    }
  };
  result.folded_before = count_folded();
  result.folded_after = result.folded_before;
  int rings = 1, stalled = 0;
  constexpr int kMaxRings = 12;
  for (int sweep = 0; sweep < max_sweeps && result.folded_after > 0; ++sweep) {
    mark_free(rings);
    for (std::size_t v = 0; v < image.size(); ++v) {
      if (!free[v] || stuck[v]) continue;
      const auto point = static_cast<Index>(v);
      Vec3 centroid = Vec3::Zero();
      int neighbours = 0;
      for (Index t : r.triangles_of.row(point))
        for (Index u : source.triangles[t])
          if (u != point) centroid += image[u], ++neighbours;
      if (neighbours == 0) continue;
      centroid /= neighbours;
      const double before = r.worst_around(point);
      const Vec3 old_position = image[v], old_normal = r.point_normal[v];
      bool kept = false;
      Eigen::Matrix3d normal;
      Vec3 rhs;
      const double energy = r.untangle_energy(point, &normal, &rhs);
      if (energy > 0) {
        // Gauss-Newton in the plane of the point's facet, then back onto the target.
        const Eigen::Matrix3d tangent = Eigen::Matrix3d::Identity() - old_normal * old_normal.transpose();  // unit
        const Eigen::Matrix3d reduced = tangent * normal * tangent;
        Vec3 step =
            (reduced + (1e-6 * reduced.trace() + 1e-300) * Eigen::Matrix3d::Identity()).ldlt().solve(tangent * rhs);
        for (int attempt = 0; attempt < 12 && step.allFinite(); ++attempt, step *= 0.5) {
          image[v] = r.project(old_position + step, r.point_normal[v]);
          if (r.untangle_energy(point, nullptr, nullptr) < energy) {
            kept = true;
            break;
          }
        }
      }
      for (const double step : {1.0, 0.5, 0.25}) {
        if (kept) break;
        image[v] = r.project(old_position + step * (centroid - old_position), r.point_normal[v]);
        if (r.worst_around(point) > before + 1e-9 && r.untangle_energy(point, nullptr, nullptr) <= energy) {
          kept = true;
          break;
        }
      }
      if (kept) {
        moved[v] = 1;
        for (Index t : r.triangles_of.row(point)) {
          folded_flag[t] = r.orientation(t) <= 0;
          for (Index u : source.triangles[t]) stuck[u] = 0;
        }
      } else  // tried again only once a neighbour has moved
        image[v] = old_position, r.point_normal[v] = old_normal, stuck[v] = 1;
    }
    ++result.sweeps;
    const std::size_t folded = count_folded();
    if (folded < result.folded_after)
      stalled = 0;
    else if (++stalled >= 3) {
      if (rings == kMaxRings) break;  // the widest ring unfolded nothing for three sweeps
      ++rings, stalled = 0;
    }
    result.folded_after = folded;
  }
  result.moved_points = static_cast<std::size_t>(std::count(moved.begin(), moved.end(), 1));
  return result;
}

}  // namespace structmesh
