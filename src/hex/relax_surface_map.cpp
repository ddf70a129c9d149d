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
//
// No fold is not yet one-to-one: a point's ring can wind twice around it with every triangle
// facing out (a branch point; the orientation test measures a triangle against the mean
// normal of its points, which near P's edges does not see the sheet turn over). The bunny's
// relaxed map had no fold but 143 such points, and the volumetric map 57 flipped tets around
// them; with the branch points laid out afresh (below), 17. surface_map_defects() counts them.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/polycube.hpp"

#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace structmesh {

namespace {

// The branch points' layout afresh (relax_surface_map()): up to this many attempts, the
// region doubling from 2 rings, each this many sweeps of barycentric positions.
constexpr int kUnwindAttempts = 4;
constexpr int kUnwindSweeps = 200;

// Adds to the flagged points `rings` rings of their neighbours (over `triangles`).
void grow_by_rings(std::vector<std::uint8_t>& flagged, const std::vector<std::array<Index, 3>>& triangles, int rings) {
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<std::uint8_t> grown = flagged;
    for (const auto& tri : triangles)
      if (flagged[tri[0]] || flagged[tri[1]] || flagged[tri[2]])
        for (Index v : tri) grown[v] = 1;
    flagged.swap(grown);
  }
}

struct Relaxation {
  const TriMesh& source;
  std::vector<Vec3>& image;
  const SurfaceProjection& onto_target;
  std::vector<int> facet_label;    // per target triangle: its axis label (-1: degenerate)
  double touching = 0;             // distance within which a point lies on a facet
  std::vector<Vec3> point_normal;  // per image point: the target's unit normal there
  CompressedRows triangles_of;
  std::vector<double> least_area;  // per source triangle: the image area it should keep

  Relaxation(const TriMesh& source_, std::vector<Vec3>& image_, const TriMesh& target,
             const SurfaceProjection& onto_target_)
      : source(source_),
        image(image_),
        onto_target(onto_target_),
        triangles_of(build_vertex_elements(source_.triangles, image_.size())) {
    facet_label.resize(target.triangles.size());
    for (std::size_t t = 0; t < target.triangles.size(); ++t) {
      const auto& tri = target.triangles[t];
      const Vec3 normal =
          (target.points[tri[1]] - target.points[tri[0]]).cross(target.points[tri[2]] - target.points[tri[0]]);
      facet_label[t] = normal.squaredNorm() > 0 ? nearest_axis_label(normal) : -1;
    }
    Eigen::AlignedBox3d bounds;
    for (const Vec3& p : target.points) bounds.extend(p);
    touching = 1e-9 * bounds.diagonal().norm();
    least_area.resize(source.triangles.size());
    for (std::size_t t = 0; t < source.triangles.size(); ++t) {
      const auto& tri = source.triangles[t];
      least_area[t] =
          0.05 * 0.5 *
          (source.points[tri[1]] - source.points[tri[0]]).cross(source.points[tri[2]] - source.points[tri[0]]).norm();
    }
    point_normal.resize(image.size());
    tbb::parallel_for(std::size_t{0}, image.size(), [&](std::size_t v) { project(image[v], point_normal[v]); });
  }

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

  // How many times the image of the point's ring winds around it, seen along the target's
  // normal there: the signed angles its triangles span at it, in the plane across that
  // normal, summed (0 for a point without a normal or triangles, counted as once).
  long winding(Index point) const {
    const Vec3& normal = point_normal[point];
    if (triangles_of.row(point).empty() || !(normal.squaredNorm() > 0)) return 1;
    double turn = 0;
    for (const Index t : triangles_of.row(point)) {
      const auto& tri = source.triangles[t];
      const int k = tri[0] == point ? 0 : tri[1] == point ? 1 : 2;
      Vec3 a = image[tri[(k + 1) % 3]] - image[point], b = image[tri[(k + 2) % 3]] - image[point];
      a -= a.dot(normal) * normal;
      b -= b.dot(normal) * normal;
      turn += std::atan2(a.cross(b).dot(normal), a.dot(b));
    }
    return std::lround(turn / (2 * std::numbers::pi));
  }

  double worst_around(Index point) const {
    double worst = 1;
    for (Index t : triangles_of.row(point)) worst = std::min(worst, orientation(t));
    return worst;
  }

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
    Index triangle = 0;
    Vec3 barycentric;
    const Vec3 q = onto_target.closest_point(p, &triangle, &barycentric);
    // Inside a triangle of the target (not on its edges): on that facet alone, without the
    // second query (the triangles near q) that finds the facets of an edge or corner point.
    if (barycentric.minCoeff() > 1e-6 && facet_label[triangle] >= 0) {
      normal = axis_of_label(facet_label[triangle]);
      return q;
    }
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

std::size_t count_set(const std::vector<std::uint8_t>& flags) {
  return static_cast<std::size_t>(std::count(flags.begin(), flags.end(), 1));
}

// Per source triangle: whether its image faces into the target (its orientation <= 0).
std::vector<std::uint8_t> folded_flags(const Relaxation& r) {
  std::vector<std::uint8_t> folded(r.source.triangles.size());
  tbb::parallel_for(std::size_t{0}, folded.size(), [&](std::size_t t) { folded[t] = r.orientation(t) <= 0; });
  return folded;
}

// Per point: its image ring winds around it other than once.
std::vector<std::uint8_t> branched_points(const Relaxation& r) {
  std::vector<std::uint8_t> flag(r.image.size(), 0);
  tbb::parallel_for(std::size_t{0}, r.image.size(),
                    [&](std::size_t v) { flag[v] = r.winding(static_cast<Index>(v)) != 1; });
  return flag;
}

// Branch points: a point whose ring winds twice around it with every triangle facing out
// (and the points of winding 0 or -1 that balance it) is invisible to the orientation test,
// yet the map covers P twice there and the tets under it must invert (measured: the bunny's
// relaxed map had no fold but 143 such points, and the volumetric map 57 flipped tets around
// them). No move that keeps every triangle facing out undoes a branch point, so its region
// is laid out afresh: the points within `rings` rings of the `branched` ones go to the
// projection onto P of their neighbours' centroid, sweep after sweep with the region's rim
// held (Tutte's barycentric embedding, on P), which winds once; what that folds (a rim that
// is not convex) the fold relaxation unfolds afterwards. Sets `moved` for the points it
// moves (if given) and returns the region's points.
std::vector<Index> lay_out_afresh(Relaxation& r, const std::vector<std::uint8_t>& branched, int rings,
                                  std::vector<std::uint8_t>* moved) {
  const auto& triangles = r.source.triangles;
  std::vector<std::uint8_t> region = branched;
  grow_by_rings(region, triangles, rings);
  std::vector<Index> points;
  for (std::size_t v = 0; v < region.size(); ++v)
    if (region[v] && !r.triangles_of.row(static_cast<Index>(v)).empty()) points.push_back(static_cast<Index>(v));
  // Gauss-Seidel sweeps in index order: the same result on any number of threads.
  for (int sweep = 0; sweep < kUnwindSweeps; ++sweep)
    for (const Index v : points) {
      Vec3 centroid = Vec3::Zero();
      int neighbours = 0;
      for (Index t : r.triangles_of.row(v))
        for (Index u : triangles[t])
          if (u != v) centroid += r.image[u], ++neighbours;
      r.image[v] = r.project(centroid / neighbours, r.point_normal[v]);
    }
  if (moved)
    for (const Index v : points) (*moved)[v] = 1;
  return points;
}

}  // namespace

SurfaceMapRelaxation relax_surface_map(const TriMesh& source, std::vector<Vec3>& image, const TriMesh& target,
                                       const SurfaceProjection& onto_target, int max_sweeps) {
  SurfaceMapRelaxation result;
  Relaxation r(source, image, target, onto_target);
  std::vector<std::uint8_t> free(image.size(), 0), moved(image.size(), 0), stuck(image.size(), 0);
  // Per triangle: folded or not, recomputed only for the triangles of points that moved (the
  // orientation of a triangle across an edge of P costs a closest-point query).
  std::vector<std::uint8_t> folded_flag = folded_flags(r);
  auto count_folded = [&] { return count_set(folded_flag); };
  // Points of folded triangles and `rings` rings around them.
  auto mark_free = [&](int rings) {
    std::fill(free.begin(), free.end(), 0);
    for (std::size_t t = 0; t < source.triangles.size(); ++t)
      if (folded_flag[t])
        for (Index v : source.triangles[t]) free[v] = 1;
    grow_by_rings(free, source.triangles, rings);
  };
  result.folded_before = count_folded();
  result.folded_after = result.folded_before;
  // The fold relaxation: sweeps over the points of folded triangles and rings around them.
  auto relax_folds = [&] {
    int sweeps_left = max_sweeps, rings = 1, stalled = 0;
    constexpr int kMaxRings = 12;
    for (; sweeps_left > 0 && result.folded_after > 0; --sweeps_left) {
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
  };
  relax_folds();
  // Then the branch points (lay_out_afresh()), the region doubling while some stay. An
  // attempt is kept only if it leaves fewer folds and branch points together: on fertility,
  // regions of 16 rings across P's edges folded more than the relaxation could unfold
  // (130 branch points and 0 folds became 150 and 129).
  std::vector<std::uint8_t> branched = branched_points(r);
  auto count_branched = [&] { return count_set(branched); };
  result.branched_before = count_branched();
  // A map still folded on more than 2% of its triangles is beyond this (polycube_hex_mesh()
  // drops such a merged-plane map for the unmerged retry): laying out its thousands of branch
  // points took the dog's hopeless map 45 s.
  const bool hopeless = static_cast<double>(result.folded_after) > 0.02 * static_cast<double>(source.triangles.size());
  for (int attempt = 0, rings = 2; !hopeless && attempt < kUnwindAttempts && count_branched() > 0;
       ++attempt, rings *= 2) {
    const std::size_t defects_before = result.folded_after + count_branched();
    const std::vector<Vec3> kept_image = image, kept_normal = r.point_normal;
    const std::vector<std::uint8_t> kept_folded = folded_flag, kept_moved = moved, kept_branched = branched;
    const int kept_sweeps = result.sweeps;
    for (const Index v : lay_out_afresh(r, branched, rings, &moved))
      for (Index t : r.triangles_of.row(v)) folded_flag[t] = r.orientation(t) <= 0;
    std::fill(stuck.begin(), stuck.end(), 0);
    result.folded_after = count_folded();
    relax_folds();
    branched = branched_points(r);
    if (result.folded_after + count_branched() < defects_before) {
      ++result.unwound_regions;
      continue;
    }
    image = kept_image, r.point_normal = kept_normal;  // worse or no better: undone
    folded_flag = kept_folded, moved = kept_moved, branched = kept_branched;
    result.folded_after = count_folded(), result.sweeps = kept_sweeps;
  }
  result.branched_after = count_branched();
  result.moved_points = count_set(moved);
  return result;
}

SurfaceMapUnwinding unwind_surface_map(const TriMesh& source, std::vector<Vec3>& image, const TriMesh& target,
                                       const SurfaceProjection& onto_target, int rings) {
  if (source.points.size() != image.size())
    throw InputError("unwind_surface_map: the source has " + std::to_string(source.points.size()) +
                     " points, the image " + std::to_string(image.size()));
  if (rings < 0) throw InputError("unwind_surface_map: " + std::to_string(rings) + " rings");
  SurfaceMapUnwinding result;
  Relaxation r(source, image, target, onto_target);
  const std::vector<std::uint8_t> branched = branched_points(r);
  result.branched_before = count_set(branched);
  if (result.branched_before > 0) result.moved_points = lay_out_afresh(r, branched, rings, nullptr).size();
  result.branched_after = count_set(branched_points(r));
  return result;
}

namespace {

// The measures below read a map without moving it: Relaxation works on a mutable image, so
// they give it a copy.
std::vector<Vec3> image_to_measure(const char* function, const TriMesh& source, const std::vector<Vec3>& image) {
  if (source.points.size() != image.size())
    throw InputError(std::string(function) + ": the source has " + std::to_string(source.points.size()) +
                     " points, the image " + std::to_string(image.size()));
  return image;
}

}  // namespace

std::size_t folded_triangles(const TriMesh& source, const std::vector<Vec3>& image, const TriMesh& target,
                             const SurfaceProjection& onto_target) {
  std::vector<Vec3> copy = image_to_measure("folded_triangles", source, image);
  return count_set(folded_flags(Relaxation(source, copy, target, onto_target)));
}

SurfaceMapDefects surface_map_defects(const TriMesh& source, const std::vector<Vec3>& image, const TriMesh& target,
                                      const SurfaceProjection& onto_target) {
  std::vector<Vec3> copy = image_to_measure("surface_map_defects", source, image);
  const Relaxation r(source, copy, target, onto_target);
  SurfaceMapDefects defects;
  defects.folded = count_set(folded_flags(r));
  double image_area = 0, target_area = 0;
  for (const auto& tri : source.triangles)
    image_area += 0.5 * (image[tri[1]] - image[tri[0]]).cross(image[tri[2]] - image[tri[0]]).norm();
  for (const auto& tri : target.triangles)
    target_area +=
        0.5 *
        (target.points[tri[1]] - target.points[tri[0]]).cross(target.points[tri[2]] - target.points[tri[0]]).norm();
  defects.area_excess = target_area > 0 ? image_area / target_area - 1 : 0.0;
  defects.branched_points = count_set(branched_points(r));
  return defects;
}

// smooth_surface_map(): what the relaxation leaves is fold-free but far from a good map. Where
// Q's chart border runs a few voxels off P's edge, the projection along the charts' axes
// sends a thin strip of Q onto a whole band of P, and the triangles across the edge cover the
// rest (the screwdriver: 1% of the boundary triangles stretched over 6.6 times their share
// of the area, 0.1% over 44 times, and 1% shrunk below 1/50). The volumetric map keeps that
// boundary, so the tets under it come out squashed by 10^-3 and some flip.
//
// Each point slides on P (steps in the plane of its facet or of a neighbour's, projected back
// onto P, so it may cross P's edges) to lower a distortion energy of its triangles measured against their
// shapes on the input, per triangle of reference area A and Jacobian J (2x2, from the
// reference triangle onto its image's plane, det J signed along P's outward normal there):
//   A * [ (1 - lambda) |J|^2 / (2 det J) + lambda (det J / d + d / det J) / 2 ],
// the first term the MIPS conformal energy, the second an area term around d = the image's
// total area over the reference's (so each triangle keeps its share of P), both 1 at best,
// lambda = 1/2. Both terms grow without bound as det J -> 0, so a step that would fold a
// triangle is never taken, and points of triangles that are still folded stay put (the
// relaxation above owns those). A per-triangle energy needs no linear solve (the hard
// constraint "on P" makes a global one piecewise), and points coloured so that no two of a
// colour share a triangle move in parallel, the same way on any number of threads.
SurfaceMapSmoothing smooth_surface_map(const TriMesh& reference, std::vector<Vec3>& image, const TriMesh& target,
                                       const SurfaceProjection& onto_target, int max_sweeps) {
  if (reference.points.size() != image.size())
    throw InputError("smooth_surface_map: the reference has " + std::to_string(reference.points.size()) +
                     " points, the image " + std::to_string(image.size()));
  SurfaceMapSmoothing result;
  Relaxation r(reference, image, target, onto_target);
  const std::size_t triangles = reference.triangles.size();
  // Per triangle: reference area and the cotangents of its angles (the Dirichlet energy
  // A |J|^2 = 1/2 sum_i cot_i |image edge opposite i|^2).
  std::vector<double> reference_area(triangles);
  std::vector<std::array<double, 3>> cotangent(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    const auto& tri = reference.triangles[t];
    const double twice_area = (reference.points[tri[1]] - reference.points[tri[0]])
                                  .cross(reference.points[tri[2]] - reference.points[tri[0]])
                                  .norm();
    reference_area[t] = 0.5 * twice_area;
    for (int k = 0; k < 3; ++k) {
      const Vec3& at = reference.points[tri[k]];
      const double dot = (reference.points[tri[(k + 1) % 3]] - at).dot(reference.points[tri[(k + 2) % 3]] - at);
      cotangent[t][k] = twice_area > 0 ? dot / twice_area : 0.0;
    }
  }
  constexpr double kAreaWeight = 0.5;  // lambda
  const double inf = std::numeric_limits<double>::infinity();
  // A triangle's image area, signed along P's outward normal o there: its full area while
  // its normal is within 60 degrees of o, then its area along o (twice that, to be
  // continuous), so that it still falls to zero as the triangle turns edge-on and the energy
  // below stays a barrier. (The area along o alone shrank the triangles of a facet that touch
  // P's edges, whose o leans 45 degrees off the facet's axis, by 30%.) With its gradient with
  // respect to the triangle's point k, if asked.
  auto image_area = [&](const std::array<Index, 3>& tri, int k, Vec3* gradient) {
    const Vec3 outward = r.outward(tri);
    const Vec3 normal = (image[tri[1]] - image[tri[0]]).cross(image[tri[2]] - image[tri[0]]);
    const double along = normal.dot(outward), length = normal.norm();
    const bool full = along >= 0.5 * length && length > 0;
    if (gradient) {
      const Vec3 edge = image[tri[(k + 2) % 3]] - image[tri[(k + 1) % 3]];
      *gradient = full ? Vec3(0.5 * (normal / length).cross(edge)) : Vec3(outward.cross(edge));
    }
    return full ? 0.5 * length : along;
  };
  auto signed_image_area = [&](std::size_t t) { return image_area(reference.triangles[t], 0, nullptr); };
  double total_image = 0, total_reference = 0;
  for (std::size_t t = 0; t < triangles; ++t) {
    total_image += std::abs(signed_image_area(t));
    total_reference += reference_area[t];
  }
  if (!(total_reference > 0) || !(total_image > 0)) return result;
  const double share = total_image / total_reference;  // d
  // The energy of triangle t, and (if asked) its gradient with respect to its point `point`.
  auto triangle_energy = [&](std::size_t t, Index point, Vec3* gradient) {
    const auto& tri = reference.triangles[t];
    if (!(reference_area[t] > 0)) return 0.0;
    const Vec3 &p0 = image[tri[0]], &p1 = image[tri[1]], &p2 = image[tri[2]];
    const int k = tri[0] == point ? 0 : tri[1] == point ? 1 : 2;
    Vec3 d_area;
    const double area = image_area(tri, k, gradient ? &d_area : nullptr);
    if (!(area > 0)) return inf;
    const auto& cot = cotangent[t];
    const double dirichlet =
        0.5 * (cot[0] * (p2 - p1).squaredNorm() + cot[1] * (p0 - p2).squaredNorm() + cot[2] * (p1 - p0).squaredNorm());
    const double det = area / reference_area[t];
    const double energy =
        (1 - kAreaWeight) * dirichlet / (2 * det) + kAreaWeight * reference_area[t] * 0.5 * (det / share + share / det);
    if (gradient) {
      const Vec3& p = image[point];
      const Vec3& next = image[tri[(k + 1) % 3]];
      const Vec3& after = image[tri[(k + 2) % 3]];
      const Vec3 d_dirichlet = -cot[(k + 1) % 3] * (after - p) - cot[(k + 2) % 3] * (next - p);
      const Vec3 d_det = d_area / reference_area[t];
      *gradient += (1 - kAreaWeight) * (d_dirichlet / (2 * det) - dirichlet / (2 * det * det) * d_det) +
                   kAreaWeight * reference_area[t] * 0.5 * (1 / share - share / (det * det)) * d_det;
    }
    return energy;
  };
  auto point_energy = [&](Index point, Vec3* gradient) {
    double sum = 0;
    if (gradient) gradient->setZero();
    for (const Index t : r.triangles_of.row(point)) sum += triangle_energy(t, point, gradient);
    return sum;
  };
  auto total_energy = [&] {
    double sum = 0;
    for (std::size_t t = 0; t < triangles; ++t) {
      const double energy = triangle_energy(t, reference.triangles[t][0], nullptr);
      if (std::isfinite(energy)) sum += energy;  // folded triangles are not this function's
    }
    return sum;
  };
  auto worst_area_ratio = [&] {
    double worst = 1;
    for (std::size_t t = 0; t < triangles; ++t) {
      if (!(reference_area[t] > 0)) continue;
      const double det = signed_image_area(t) / reference_area[t] / share;
      if (det > 0) worst = std::max({worst, det, 1 / det});
    }
    return worst;
  };
  result.energy_before = total_energy() / total_reference;
  result.worst_area_ratio_before = worst_area_ratio();

  // Colours: greedy, no two points within two rings of each other alike, so that a moving
  // point's ring and its neighbours' rings (whose windings a step must keep) hold no other
  // point that moves at the same time.
  std::vector<int> colour(image.size(), -1);
  int colours = 0;
  {
    std::vector<int> used;
    for (std::size_t v = 0; v < image.size(); ++v) {
      used.clear();
      for (const Index t : r.triangles_of.row(static_cast<Index>(v)))
        for (const Index u : reference.triangles[t])
          for (const Index t2 : r.triangles_of.row(u))
            for (const Index w : reference.triangles[t2])
              if (colour[w] >= 0) used.push_back(colour[w]);
      int c = 0;
      while (std::find(used.begin(), used.end(), c) != used.end()) ++c;
      colour[v] = c;
      colours = std::max(colours, c + 1);
    }
  }
  std::vector<std::vector<Index>> by_colour(static_cast<std::size_t>(colours));
  for (std::size_t v = 0; v < image.size(); ++v)
    if (r.triangles_of.row(static_cast<Index>(v)).size() > 0)
      by_colour[static_cast<std::size_t>(colour[v])].push_back(static_cast<Index>(v));

  constexpr double kSettled = 1.05;
  std::vector<double> point_area(image.size(), 0.0);
  for (std::size_t t = 0; t < triangles; ++t)
    for (const Index v : reference.triangles[t]) point_area[v] += reference_area[t];
  // Per point: the step length that last worked (grown after a success, halved per failure).
  std::vector<double> step(image.size(), 0.0);
  std::vector<std::uint8_t> moved(image.size(), 0);
  // A point that found no step is tried again only after a neighbour moved (in this sweep
  // or the last: moved_in_sweep holds the parity of the sweep it last moved in, 2 = never).
  std::vector<std::uint8_t> stuck(image.size(), 0), moved_in_sweep(image.size(), 2);
  int sweep_parity = 0;
  auto neighbour_moved = [&](Index point) {
    for (const Index t : r.triangles_of.row(point))
      for (const Index u : reference.triangles[t])
        if (u != point && moved_in_sweep[u] != 2) return true;
    return false;
  };
  double energy = result.energy_before * total_reference;
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    sweep_parity = sweep & 1;
    // Forget the moves of two sweeps ago.
    for (std::uint8_t& m : moved_in_sweep)
      if (m == sweep_parity) m = 2;
    for (const auto& points : by_colour)
      tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
        const Index point = points[i];
        Vec3 gradient;
        const double before = point_energy(point, &gradient);
        if (!std::isfinite(before)) return;  // a folded triangle: the relaxation's
        // Most of the map is close to the energy's minimum, where a step gains little and
        // costs closest-point queries on P: only points whose triangles are 5% above it move.
        if (before < kSettled * point_area[point] || (stuck[point] && !neighbour_moved(point))) return;
        if (!(gradient.squaredNorm() > 0)) return;
        // Steps up to half the longest edge at the point: the barrier, not the step, keeps a
        // triangle from folding (a step past an edge is rejected), and a point of a sliver
        // limited by its shortest edge crept by 1e-3 of an edge per sweep (the bunny).
        double longest = 0, sum = 0;
        int edges = 0;
        // The planes the point may slide in: its facet's, and those of the facets its
        // neighbours lie on. A point on an edge of P (or a hair off it) reaches the facet
        // across the edge only in that facet's plane: in its own, a strip of the bunny
        // collapsed onto an edge of P stayed there.
        std::array<Vec3, 8> planes;
        std::size_t plane_count = 0;
        auto add_plane = [&](const Vec3& normal) {
          for (std::size_t i = 0; i < plane_count; ++i)
            if ((planes[i] - normal).squaredNorm() < 1e-12) return;
          if (plane_count < planes.size()) planes[plane_count++] = normal;
        };
        add_plane(r.point_normal[point]);
        for (const Index t : r.triangles_of.row(point))
          for (const Index u : reference.triangles[t]) {
            if (u == point) continue;
            const double edge = (image[u] - image[point]).norm();
            longest = std::max(longest, edge), sum += edge, ++edges;
            const Vec3& normal = r.point_normal[u];
            for (int axis = 0; axis < 3; ++axis)  // the facets of an edge or corner point, one by one
              if (std::abs(normal[axis]) > 0.3) add_plane(Vec3::Unit(axis) * (normal[axis] > 0 ? 1.0 : -1.0));
          }
        // A step must not wind a ring twice around its point (a branch point, which the
        // barrier does not see where a triangle crosses an edge of P): of the point's and its
        // neighbours' rings, no more may wind around their point other than once than before.
        auto wound_wrongly = [&] {
          int count = r.winding(point) != 1;
          for (const Index t : r.triangles_of.row(point))
            for (const Index u : reference.triangles[t])
              if (u != point) count += r.winding(u) != 1;
          return count;
        };
        int wound_wrongly_before = -1;  // counted at the old place when a step first lowers the energy
        double& length_to_try = step[point];
        if (!(length_to_try > 0)) length_to_try = 0.1 * sum / std::max(edges, 1);
        length_to_try = std::min(length_to_try, 0.5 * longest);
        const Vec3 old_position = image[point];
        for (std::size_t plane = 0; plane < plane_count; ++plane) {
          const Vec3& normal = planes[plane];
          const Vec3 along = gradient - gradient.dot(normal) * normal;
          if (!(along.squaredNorm() > 1e-24 * gradient.squaredNorm())) continue;
          const Vec3 direction = -along.normalized();
          double length = plane == 0 ? length_to_try : std::min(0.5 * longest, 4 * length_to_try);
          for (int attempt = 0; attempt < (plane == 0 ? 10 : 6); ++attempt, length *= 0.5) {
            const Vec3 candidate = old_position + length * direction;
            Vec3 new_normal;
            const Vec3 projected = r.project(candidate, new_normal);
            if ((projected - candidate).norm() > length) continue;  // onto another sheet
            image[point] = projected;
            std::swap(r.point_normal[point], new_normal);
            const bool lower = point_energy(point, nullptr) < before;
            if (lower && wound_wrongly_before < 0) {
              image[point] = old_position;  // the old place's count, with its normal
              std::swap(r.point_normal[point], new_normal);
              wound_wrongly_before = wound_wrongly();
              image[point] = projected;
              std::swap(r.point_normal[point], new_normal);
            }
            if (lower && wound_wrongly() <= wound_wrongly_before) {
              moved[point] = 1, moved_in_sweep[point] = static_cast<std::uint8_t>(sweep_parity);
              stuck[point] = 0;
              length_to_try = 2 * length;
              return;
            }
            image[point] = old_position;
            std::swap(r.point_normal[point], new_normal);
          }
        }
        length_to_try *= 0.5;  // nothing helped: smaller first steps next time
        stuck[point] = 1;      // and no more tries until a neighbour has moved
      });
    ++result.sweeps;
    const double now = total_energy();
    const bool stalled = energy - now < 1e-4 * energy;
    energy = now;
    if (stalled) break;
  }
  result.energy_after = energy / total_reference;
  result.worst_area_ratio_after = worst_area_ratio();
  result.moved_points = count_set(moved);
  return result;
}

}  // namespace structmesh
