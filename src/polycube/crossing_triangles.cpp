// crossing_triangles(): the intersection guard of pseudo_polycube(). A surface-only
// deformation (unlike Gregson et al.'s volumetric one) has nothing that keeps a valley
// from closing into a slit or a fan from folding over, so every step is checked; the
// exact search behind check_surface() (CGAL boxes and predicates over every triangle)
// costs more than the deformation step itself. Here cheap floating-point tests that can
// only err towards "maybe" clear almost every triangle, and the exact search runs on the
// rest:
//  - pairs sharing a vertex v can only overlap if the fan of v is not a graph over the
//    plane orthogonal to its mean normal d: if every fan triangle has n . d > 0 and the
//    projected angles at v sum to one turn, the projection is injective on the fan, so
//    two fan triangles meet only where their projections do (v and the shared edges);
//  - pairs sharing no vertex are found by a uniform grid of bounding boxes (a pair is
//    handled in the cell holding the low corner of the intersection of the two boxes)
//    and cleared by a separating axis (the normals, the edge cross products and the
//    in-plane edge normals) with a margin far above rounding.
// Written by hand because the exact predicates are check_surface()'s own (so the guard
// agrees with the validity test the result is held to) and no library offers the filter.
#include "polycube/crossing_triangles.hpp"

#include "check/self_intersections.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

namespace structmesh::polycube_detail {

namespace {

// Whether the fan of v (its triangles, outward-oriented) projects injectively along its
// mean normal; false when unsure.
bool fan_is_graph(const std::vector<Vec3>& points, const std::vector<std::array<Index, 3>>& triangles,
                  std::span<const Index> fan, Index v) {
  Vec3 d = Vec3::Zero();
  for (const Index t : fan) {
    const auto& tri = triangles[t];
    d += (points[tri[1]] - points[tri[0]]).cross(points[tri[2]] - points[tri[0]]);
  }
  const double length = d.norm();
  if (!(length > 0)) return false;
  d /= length;
  // Edges far shorter than the coordinates are too rounded to judge.
  const double magnitude = points[v].cwiseAbs().maxCoeff();
  double turn = 0;
  for (const Index t : fan) {
    const auto& tri = triangles[t];
    const int k = tri[0] == v ? 0 : tri[1] == v ? 1 : 2;
    const Vec3 x = points[tri[(k + 1) % 3]] - points[v], y = points[tri[(k + 2) % 3]] - points[v];
    // The d-component of a cross product depends only on the projections, so the
    // projected angle at v has sine (x cross y) . d and cosine px . py.
    if (!(std::min(x.norm(), y.norm()) > 1e-8 * magnitude)) return false;
    const Vec3 normal = x.cross(y);
    const double sine = normal.dot(d);
    if (!(sine > 1e-3 * normal.norm())) return false;
    turn += std::atan2(sine, (x - x.dot(d) * d).dot(y - y.dot(d) * d));
  }
  return std::abs(turn - 2 * std::numbers::pi) < std::numbers::pi;
}

// Whether the triangles p and q are certainly disjoint: some axis separates their
// projections by far more than the rounding of the projections.
bool separated(const std::array<Vec3, 3>& p_in, const std::array<Vec3, 3>& q_in) {
  // Coordinates relative to one corner keep the projections' rounding local; the
  // subtraction itself is off by at most an ulp of the largest coordinate.
  const Vec3 origin = p_in[0];
  std::array<Vec3, 3> p, q;
  double extent = 0, magnitude = 0;
  for (int k = 0; k < 3; ++k) {
    p[k] = p_in[k] - origin;
    q[k] = q_in[k] - origin;
    extent = std::max({extent, p[k].cwiseAbs().maxCoeff(), q[k].cwiseAbs().maxCoeff()});
    magnitude = std::max({magnitude, p_in[k].cwiseAbs().maxCoeff(), q_in[k].cwiseAbs().maxCoeff()});
  }
  const std::array<Vec3, 3> ep{p[1] - p[0], p[2] - p[1], p[0] - p[2]};
  const std::array<Vec3, 3> eq{q[1] - q[0], q[2] - q[1], q[0] - q[2]};
  const Vec3 np = ep[0].cross(p[2] - p[0]), nq = eq[0].cross(q[2] - q[0]);
  const auto splits = [&](const Vec3& axis) {
    const double norm = axis.norm();
    if (!(norm > 1e-150)) return false;
    const double margin = norm * (1e-10 * extent + 1e-13 * magnitude);
    const double p0 = axis.dot(p[0]), p1 = axis.dot(p[1]), p2 = axis.dot(p[2]);
    const double q0 = axis.dot(q[0]), q1 = axis.dot(q[1]), q2 = axis.dot(q[2]);
    return std::max({p0, p1, p2}) + margin < std::min({q0, q1, q2}) ||
           std::max({q0, q1, q2}) + margin < std::min({p0, p1, p2});
  };
  // Nearby triangles of one flat chart (the common case on a pseudo-polycube) are
  // separated by an edge normal in their plane; those axes go first.
  if (splits(np) || splits(nq)) return true;
  for (int k = 0; k < 3; ++k)
    if (splits(np.cross(ep[k])) || splits(nq.cross(eq[k]))) return true;
  for (const Vec3& a : ep)
    for (const Vec3& b : eq)
      if (splits(a.cross(b))) return true;
  return false;
}

bool shares_vertex(const std::array<Index, 3>& a, const std::array<Index, 3>& b) {
  for (const Index u : a)
    if (u == b[0] || u == b[1] || u == b[2]) return true;
  return false;
}

}  // namespace

std::vector<Index> crossing_triangles(const std::vector<Vec3>& points,
                                      const std::vector<std::array<Index, 3>>& triangles,
                                      const CompressedRows& vertex_triangles) {
  const std::size_t count = triangles.size();
  std::vector<std::uint8_t> unsure(count, 0);
  std::vector<Index> result;

  std::vector<Vec3> low(count), high(count);
  double mean_extent = 0;
  for (std::size_t t = 0; t < count; ++t) {
    const auto& tri = triangles[t];
    low[t] = points[tri[0]].cwiseMin(points[tri[1]]).cwiseMin(points[tri[2]]);
    high[t] = points[tri[0]].cwiseMax(points[tri[1]]).cwiseMax(points[tri[2]]);
    const double extent = (high[t] - low[t]).maxCoeff();
    mean_extent += extent / static_cast<double>(count);
    // Zero area, check_surface()'s exact test, where the cross product is too small to
    // rule it out.
    const Vec3 normal = (points[tri[1]] - points[tri[0]]).cross(points[tri[2]] - points[tri[0]]);
    if (!(normal.norm() > 1e-10 * extent * extent) && detail::collinear(points[tri[0]], points[tri[1]], points[tri[2]]))
      result.push_back(Index(t));
  }

  const std::size_t vertex_count = vertex_triangles.row_count();
  std::vector<std::uint8_t> folded(vertex_count, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertex_count, 1024), [&](const auto& range) {
    for (std::size_t v = range.begin(); v < range.end(); ++v) {
      const auto fan = vertex_triangles.row(v);
      folded[v] = !fan.empty() && !fan_is_graph(points, triangles, fan, Index(v)) ? 1 : 0;
    }
  });
  for (std::size_t v = 0; v < vertex_count; ++v)
    if (folded[v])
      for (const Index t : vertex_triangles.row(v)) unsure[t] = 1;

  // Grid cells as large as the mean box extent, at most 2^20 per axis (21-bit keys).
  const BoundingBox3 box = bounding_box(points);
  double cell = std::max(mean_extent, (box.max - box.min).maxCoeff() / double(1 << 20));
  if (!(cell > 0)) cell = 1;
  const auto coordinate = [&](double x, int axis) {
    return static_cast<std::uint64_t>(std::floor((x - box.min[axis]) / cell));
  };
  const auto cell_key = [&](const Vec3& corner) {
    return coordinate(corner.x(), 0) << 42 | coordinate(corner.y(), 1) << 21 | coordinate(corner.z(), 2);
  };
  std::vector<std::pair<std::uint64_t, Index>> entries;
  entries.reserve(2 * count);
  for (std::size_t t = 0; t < count; ++t)
    for (std::uint64_t x = coordinate(low[t].x(), 0); x <= coordinate(high[t].x(), 0); ++x)
      for (std::uint64_t y = coordinate(low[t].y(), 1); y <= coordinate(high[t].y(), 1); ++y)
        for (std::uint64_t z = coordinate(low[t].z(), 2); z <= coordinate(high[t].z(), 2); ++z)
          entries.emplace_back(x << 42 | y << 21 | z, Index(t));
  std::sort(entries.begin(), entries.end());
  std::vector<std::size_t> runs;
  for (std::size_t k = 0; k < entries.size(); ++k)
    if (k == 0 || entries[k].first != entries[k - 1].first) runs.push_back(k);
  runs.push_back(entries.size());
  tbb::enumerable_thread_specific<std::vector<Index>> found_pairs;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, runs.size() - 1, 256), [&](const auto& range) {
    std::vector<Index>& found = found_pairs.local();
    for (std::size_t r = range.begin(); r < range.end(); ++r)
      for (std::size_t i = runs[r]; i < runs[r + 1]; ++i)
        for (std::size_t j = i + 1; j < runs[r + 1]; ++j) {
          const Index f = entries[i].second, g = entries[j].second;
          if (unsure[f] && unsure[g]) continue;
          if (shares_vertex(triangles[f], triangles[g])) continue;  // the fans' business
          if ((high[f].array() < low[g].array()).any() || (high[g].array() < low[f].array()).any()) continue;
          if (cell_key(low[f].cwiseMax(low[g])) != entries[i].first) continue;  // handled in another cell
          const auto& a = triangles[f];
          const auto& b = triangles[g];
          if (separated({points[a[0]], points[a[1]], points[a[2]]}, {points[b[0]], points[b[1]], points[b[2]]}))
            continue;
          found.push_back(f);
          found.push_back(g);
        }
  });
  for (const std::vector<Index>& found : found_pairs)
    for (const Index t : found) unsure[t] = 1;

  std::vector<Index> subset;
  for (std::size_t t = 0; t < count; ++t)
    if (unsure[t]) subset.push_back(Index(t));
  if (!subset.empty()) {
    std::vector<std::array<Index, 3>> chosen;
    chosen.reserve(subset.size());
    for (const Index t : subset) chosen.push_back(triangles[t]);
    const detail::SelfIntersections found = detail::find_self_intersections(points, chosen, {}, true);
    for (const auto& pairs : {found.disjoint_pairs, found.adjacent_overlaps})
      for (const auto& pair : pairs)
        for (const Index k : pair) result.push_back(subset[k]);
  }
  std::sort(result.begin(), result.end());
  result.erase(std::unique(result.begin(), result.end()), result.end());
  return result;
}

}  // namespace structmesh::polycube_detail
