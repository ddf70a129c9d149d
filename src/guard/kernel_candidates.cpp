// kernel_candidates(): see kernel_candidates.hpp. The two small linear programs per pair
// (4 and 6 unknowns, one row per face; lp/small_lp.hpp) are solved by COIN-OR CLP, the LP
// solver under CBC.
#include "guard/kernel_candidates.hpp"

#include "lp/small_lp.hpp"

#include <CoinFinite.hpp>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace structmesh::guard_detail {

namespace {

using lp::chebyshev_centre;
using lp::least_violating_point;
using lp::Plane;
using lp::point_in_box;
using lp::SmallLp;

// The point p of {n_f . p <= offset_f - margin} within [lo, hi] nearest to `target` in L1.
bool nearest_kernel_point(const std::vector<Plane>& planes, double margin, const Vec3& lo, const Vec3& hi,
                          const Vec3& target, Vec3& point) {
  SmallLp lp = point_in_box(lo, hi);
  for (int k = 0; k < 3; ++k) lp.add_column(0, COIN_DBL_MAX, 1);  // t_k >= |p_k - target_k|
  for (const Plane& plane : planes) lp.add_plane_row(plane, -1, 0, plane.offset - margin);
  for (int k = 0; k < 3; ++k) {
    lp.add_row({k, 3 + k}, {1.0, -1.0}, target[k]);    // p - t <= target
    lp.add_row({k, 3 + k}, {-1.0, -1.0}, -target[k]);  // -p - t <= -target
  }
  const std::vector<double> x = lp.solve();
  if (x.empty()) return false;
  point = Vec3(x[0], x[1], x[2]);
  return true;
}

// The LPs (chebyshev_centre, nearest_kernel_point, least_violating_point) have one row per face: up to 10k on a pair of
// a 50k-face model, 0.2 s for CLP each. Few rows bind at the optimum, so each LP is solved on a subset (kStartRows
// spread over the list), and the rows its answer violates are added, the worst
// kAddedRows at a time, until it violates none (or after kRounds: the answer is a
// candidate only, which the caller's visibility test decides).
// `solve(subset, point, depth)`; `slack(depth)`: how far inside every plane the answer must be.
template <class Solve, class Slack>
bool solve_with_row_generation(const std::vector<Plane>& planes, Solve&& solve, Slack&& slack, Vec3& point,
                               double& depth) {
  constexpr std::size_t kStartRows = 200, kAddedRows = 200;
  constexpr int kRounds = 8;
  std::vector<std::uint8_t> in(planes.size(), 0);
  std::vector<Plane> subset;
  const std::size_t stride = std::max<std::size_t>(1, planes.size() / kStartRows);
  for (std::size_t i = 0; i < planes.size(); i += stride) in[i] = 1, subset.push_back(planes[i]);
  std::vector<std::pair<double, std::size_t>> violated;
  for (int round = 0; round < kRounds; ++round) {
    if (!solve(subset, point, depth)) return false;
    const double needed = slack(depth), tolerance = 1e-9 * (1 + point.norm());
    violated.clear();
    for (std::size_t i = 0; i < planes.size(); ++i)
      if (!in[i]) {
        const double excess = planes[i].normal.dot(point) - planes[i].offset + needed;
        if (excess > tolerance) violated.emplace_back(-excess, i);
      }
    if (violated.empty()) return true;
    const std::size_t take = std::min(kAddedRows, violated.size());
    std::partial_sort(violated.begin(), violated.begin() + static_cast<std::ptrdiff_t>(take), violated.end());
    for (std::size_t k = 0; k < take; ++k) in[violated[k].second] = 1, subset.push_back(planes[violated[k].second]);
  }
  return true;
}

}  // namespace

std::vector<Vec3> kernel_candidates(const TriMesh& surface, const CompressedRows& sets,
                                    std::span<const Vec3> candidates, std::span<const Index> chosen) {
  const std::size_t faces = surface.triangles.size();
  // Which chosen guards see each face (up to 2 kept; `count` has all).
  std::vector<std::uint32_t> count(faces, 0);
  std::vector<std::array<Index, 2>> seers(faces, {kInvalidIndex, kInvalidIndex});
  for (std::size_t g = 0; g < chosen.size(); ++g)
    for (const Index f : sets.row(chosen[g])) {
      if (count[f] < 2) seers[f][count[f]] = static_cast<Index>(g);
      ++count[f];
    }
  // Pairs: guards with a face only they see, next to a face only the other sees, or one
  // face that exactly the two of them see.
  std::vector<std::array<Index, 2>> pairs;
  const EdgeAdjacency edges = build_edges(surface);
  auto owner = [&](Index f) { return count[f] == 1 ? seers[f][0] : kInvalidIndex; };
  for (std::size_t e = 0; e < edges.edges.size(); ++e) {
    const auto around = edges.edge_elements.row(e);
    if (around.size() != 2) continue;
    const Index a = owner(around[0]), b = owner(around[1]);
    if (a != kInvalidIndex && b != kInvalidIndex && a != b) pairs.push_back({std::min(a, b), std::max(a, b)});
  }
  for (std::size_t f = 0; f < faces; ++f)
    if (count[f] == 2) pairs.push_back({std::min(seers[f][0], seers[f][1]), std::max(seers[f][0], seers[f][1])});
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());

  // Faces per guard that at most two chosen guards see, for the pairs' plane lists.
  std::vector<std::vector<Index>> alone(chosen.size()), shared(chosen.size());
  for (std::size_t f = 0; f < faces; ++f) {
    if (count[f] == 1) alone[seers[f][0]].push_back(static_cast<Index>(f));
    if (count[f] == 2) shared[seers[f][0]].push_back(static_cast<Index>(f));  // seers[f][0] < seers[f][1]
  }
  auto plane_of = [&](Index f) {
    const auto& t = surface.triangles[f];
    const Vec3& a = surface.points[t[0]];
    Vec3 n = (surface.points[t[1]] - a).cross(surface.points[t[2]] - a);
    const double area = n.norm() / 2;
    n.normalize();
    return Plane{n, n.dot(a), area};
  };
  std::vector<Vec3> points;
  std::vector<Plane> planes;
  for (const auto& [a, b] : pairs) {
    planes.clear();
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    auto take = [&](Index f) {
      const Plane plane = plane_of(f);
      if (!plane.normal.allFinite()) return;
      planes.push_back(plane);
      for (const Index v : surface.triangles[f])
        lo = lo.cwiseMin(surface.points[v]), hi = hi.cwiseMax(surface.points[v]);
    };
    for (const Index f : alone[a]) take(f);
    for (const Index f : alone[b]) take(f);
    for (const Index f : shared[a])
      if (seers[f][1] == b) take(f);
    if (planes.empty()) continue;
    lo = lo.cwiseMin(candidates[chosen[a]]).cwiseMin(candidates[chosen[b]]);
    hi = hi.cwiseMax(candidates[chosen[a]]).cwiseMax(candidates[chosen[b]]);
    // The LPs run in the box's frame, its centre at the origin and its diagonal 1, so that
    // CLP's absolute tolerances and the row generation's are relative to the pair's box
    // whatever the model's units and position (CLP also scales its rows itself: a test
    // with the L 5,000 km from the origin passes either way).
    const Vec3 origin = 0.5 * (lo + hi);
    const double scale = (hi - lo).norm();
    if (!(scale > 0)) continue;
    for (Plane& plane : planes) {
      plane.offset = (plane.offset - plane.normal.dot(origin)) / scale;
      plane.weight /= scale * scale;
    }
    const Vec3 world_midpoint = 0.5 * (candidates[chosen[a]] + candidates[chosen[b]]);
    const auto to_world = [&](const Vec3& x) { return Vec3(origin + scale * x); };
    lo = (lo - origin) / scale, hi = (hi - origin) / scale;
    Vec3 centre;
    double depth = 0;
    const auto chebyshev = [&](const std::vector<Plane>& rows, Vec3& x, double& r) {
      return chebyshev_centre(rows, lo, hi, x, r);
    };
    if (!solve_with_row_generation(
            planes, chebyshev, [](double r) { return r; }, centre, depth))
      continue;
    if (!(depth > 1e-9 * (hi - lo).norm())) {
      // No room: the point on the wrong side of the least face area instead.
      const double margin = 1e-4 * (hi - lo).norm();
      const auto least = [&](const std::vector<Plane>& rows, Vec3& x, double&) {
        return least_violating_point(rows, margin, lo, hi, x);
      };
      double unused = 0;
      if (solve_with_row_generation(
              planes, least, [&](double) { return margin; }, centre, unused))
        points.push_back(to_world(centre));
      continue;
    }
    points.push_back(to_world(centre));
    const Vec3 midpoint = (world_midpoint - origin) / scale;
    const double margin = 0.25 * depth;
    const auto nearest = [&](const std::vector<Plane>& rows, Vec3& x, double&) {
      return nearest_kernel_point(rows, margin, lo, hi, midpoint, x);
    };
    Vec3 near;
    double unused = 0;
    if (solve_with_row_generation(
            planes, nearest, [&](double) { return margin; }, near, unused))
      points.push_back(to_world(near));
  }
  return points;
}

}  // namespace structmesh::guard_detail
