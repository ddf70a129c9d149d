// clean_up_quads(): analytic cases whose optimum is known (a grid with one rotated
// edge, a split vertex), and properties on raw paved meshes (boundary kept
// bit-identical, conforming, never inverted, no worse than the guard, fewer
// irregular points, deterministic).
#include "quad2d/quad_cleanup.hpp"
#include "quad2d/paving.hpp"

#include "structmesh/error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

namespace structmesh {
namespace {

using Quads = std::vector<std::array<Index, 4>>;

/// An n x n grid of unit quads on [0, n]²: the boundary points first (counter-
/// clockwise from the origin), then the interior points row by row.
struct Grid {
  int n;
  std::vector<Vec2> points;
  Quads quads;
  std::map<std::pair<int, int>, Index> id;
  Index fixed = 0;
  explicit Grid(int size) : n(size) {
    auto add = [&](int i, int j) {
      id[{i, j}] = static_cast<Index>(points.size());
      points.emplace_back(i, j);
    };
    for (int i = 0; i < n; ++i) add(i, 0);
    for (int j = 0; j < n; ++j) add(n, j);
    for (int i = n; i > 0; --i) add(i, n);
    for (int j = n; j > 0; --j) add(0, j);
    fixed = static_cast<Index>(points.size());
    for (int j = 1; j < n; ++j)
      for (int i = 1; i < n; ++i) add(i, j);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) quads.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  }
  Index at(int i, int j) const { return id.at({i, j}); }
};

std::vector<int> quad_counts(std::size_t points, const Quads& quads) {
  std::vector<int> c(points, 0);
  for (const auto& q : quads)
    for (const Index v : q) ++c[v];
  return c;
}

int irregular_interior(std::size_t points, const Quads& quads, Index fixed) {
  const auto c = quad_counts(points, quads);
  int count = 0;
  for (std::size_t p = fixed; p < points; ++p) count += c[p] != 4;
  return count;
}

double min_quality(const std::vector<Vec2>& P, const Quads& quads) {
  double worst = 1;
  for (const auto& q : quads) worst = std::min(worst, paving::scaled_jacobian(P[q[0]], P[q[1]], P[q[2]], P[q[3]]));
  return worst;
}

/// Conformity: every directed edge at most once; an edge without its reverse is a
/// boundary edge, and the boundary edges are exactly `boundary` (directed).
void expect_conforming(const Quads& quads, const std::vector<std::pair<Index, Index>>& boundary) {
  std::map<std::pair<Index, Index>, int> directed;
  for (const auto& q : quads)
    for (int j = 0; j < 4; ++j) ++directed[{q[j], q[(j + 1) % 4]}];
  std::vector<std::pair<Index, Index>> open;
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " used " << count << " times";
    if (!directed.count({edge.second, edge.first})) open.push_back(edge);
  }
  auto expected = boundary;
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(open, expected);
}

/// The directed edges of a loop of the first `count` points, in order.
std::vector<std::pair<Index, Index>> loop_edges(Index count) {
  std::vector<std::pair<Index, Index>> b;
  for (Index i = 0; i < count; ++i) b.emplace_back(i, (i + 1) % count);
  return b;
}

TEST(QuadCleanup, PerfectGridIsLeftAlone) {
  Grid g(6);
  const auto points = g.points;
  const auto quads = g.quads;
  const auto stats = paving::clean_up_quads(g.points, g.quads, g.fixed, 1.0);
  EXPECT_EQ(stats.irregular_before, 0U);
  EXPECT_EQ(stats.swaps + stats.collapses + stats.doublets, 0U);
  EXPECT_EQ(g.quads, quads);
  for (std::size_t p = 0; p < points.size(); ++p) EXPECT_EQ(g.points[p], points[p]);
}

TEST(QuadCleanup, RotatedEdgeGoesBackToTheGrid) {
  // Rotate the edge (2,2)-(2,3) of a 6 x 6 grid: (2,2) and (2,3) get 3 quads, (1,3) and
  // (3,2) get 5. The straight angles it leaves at (2,2) and (2,3) are opened by moving
  // those points 0.3 out so that the input is valid.
  Grid g(6);
  const Index u = g.at(2, 2), v = g.at(2, 3);
  Index qa = 0, qb = 0;
  for (Index id = 0; id < g.quads.size(); ++id) {
    if (g.quads[id] == std::array<Index, 4>{g.at(1, 2), u, v, g.at(1, 3)}) qa = id;
    if (g.quads[id] == std::array<Index, 4>{u, g.at(3, 2), g.at(3, 3), v}) qb = id;
  }
  g.quads[qa] = {g.at(1, 3), g.at(1, 2), u, g.at(3, 2)};
  g.quads[qb] = {g.at(3, 2), g.at(3, 3), v, g.at(1, 3)};
  g.points[u].y() -= 0.3;
  g.points[v].y() += 0.3;
  ASSERT_GT(min_quality(g.points, g.quads), 0);
  ASSERT_EQ(irregular_interior(g.points.size(), g.quads, g.fixed), 4);

  const auto boundary = std::vector<Vec2>(g.points.begin(), g.points.begin() + g.fixed);
  const auto stats = paving::clean_up_quads(g.points, g.quads, g.fixed, 1.0);
  EXPECT_EQ(stats.irregular_before, 4U);
  EXPECT_EQ(stats.irregular_after, 0U);
  EXPECT_EQ(irregular_interior(g.points.size(), g.quads, g.fixed), 0);
  EXPECT_EQ(g.quads.size(), 36U);
  EXPECT_EQ(g.points.size(), 49U);
  for (Index p = 0; p < g.fixed; ++p) EXPECT_EQ(g.points[p], boundary[p]) << "boundary point " << p << " moved";
  expect_conforming(g.quads, loop_edges(g.fixed));
  EXPECT_GT(min_quality(g.points, g.quads), 0.8);
}

TEST(QuadCleanup, SplitVertexCollapsesBack) {
  // Split the grid point m = (3,3) into a = (3, 3.25) and c = (3, 2.75) with a new quad
  // (b, c, d, a) between its left and right neighbours: a and c have 3 quads, b and d
  // 5. The diagonal collapse a-c is the inverse.
  Grid g(6);
  const Index m = g.at(3, 3), b = g.at(2, 3), d = g.at(4, 3);
  const auto c = static_cast<Index>(g.points.size());
  g.points.emplace_back(3, 2.75);
  g.points[m] = Vec2(3, 3.25);
  for (auto& q : g.quads) {
    double y = 0;
    for (const Index v : q) y += g.points[v].y();
    if (y / 4 < 3)
      for (Index& v : q)
        if (v == m) v = c;
  }
  g.quads.push_back({b, c, d, m});
  ASSERT_GT(min_quality(g.points, g.quads), 0);
  ASSERT_EQ(irregular_interior(g.points.size(), g.quads, g.fixed), 4);

  const auto stats = paving::clean_up_quads(g.points, g.quads, g.fixed, 1.0);
  EXPECT_GE(stats.collapses, 1U);
  EXPECT_EQ(irregular_interior(g.points.size(), g.quads, g.fixed), 0);
  EXPECT_EQ(g.quads.size(), 36U);
  EXPECT_EQ(g.points.size(), 49U);
  expect_conforming(g.quads, loop_edges(g.fixed));
  EXPECT_GT(min_quality(g.points, g.quads), 0.8);
}

/// Deterministic pseudo-random numbers in [0, 1) (SplitMix64).
double next_random(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return static_cast<double>((z ^ (z >> 31)) >> 11) * (1.0 / 9007199254740992.0);
}

/// A star-shaped wobbly polygon of n points (even), radius about 20.
Polygon2 wobbly(int n, std::uint64_t seed) {
  std::uint64_t s = seed;
  std::array<double, 4> phase{}, amp{};
  for (int k = 0; k < 4; ++k) {
    phase[k] = 2 * std::numbers::pi * next_random(s);
    amp[k] = 0.15 * next_random(s) / (1 + k);
  }
  std::vector<Vec2> ring;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n;
    double r = 1;
    for (int k = 0; k < 4; ++k) r += amp[k] * std::sin((k + 2) * t + phase[k]);
    ring.emplace_back(20 * r * std::cos(t), 20 * r * std::sin(t));
  }
  Polygon2 poly;
  poly.add_ring(ring);
  return poly;
}

TEST(QuadCleanup, PavedShapesKeepBoundaryValidityAndGetMoreRegular) {
  std::size_t before = 0, after = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const Polygon2 poly = wobbly(2 * (30 + static_cast<int>(seed) * 5), seed * 7919);
    paving::Paver paver(poly, {});
    PavedPart part = paver.run();
    const auto fixed = static_cast<Index>(poly.points.size());
    const double worst_before = min_quality(part.points, part.quads);
    const int irregular_before = irregular_interior(part.points.size(), part.quads, fixed);

    auto points = part.points;
    auto quads = part.quads;
    const auto stats = paving::clean_up_quads(points, quads, fixed, paver.size());
    for (Index p = 0; p < fixed; ++p) {
      EXPECT_EQ(points[p].x(), poly.points[p].x()) << "seed " << seed << ": boundary point " << p << " moved";
      EXPECT_EQ(points[p].y(), poly.points[p].y()) << "seed " << seed << ": boundary point " << p << " moved";
    }
    expect_conforming(quads, loop_edges(fixed));
    const double worst_after = min_quality(points, quads);
    EXPECT_GT(worst_after, 0) << "seed " << seed;
    EXPECT_GE(worst_after, std::min(worst_before, 0.5) - 1e-12) << "seed " << seed;
    for (const int count : quad_counts(points.size(), quads)) EXPECT_GT(count, 0) << "unused point left";
    const int irregular_after = irregular_interior(points.size(), quads, fixed);
    EXPECT_LE(irregular_after, irregular_before) << "seed " << seed;
    EXPECT_LE(stats.irregular_after, stats.irregular_before);
    before += static_cast<std::size_t>(irregular_before);
    after += static_cast<std::size_t>(irregular_after);

    // Same input, same bits.
    auto points2 = part.points;
    auto quads2 = part.quads;
    paving::clean_up_quads(points2, quads2, fixed, paver.size());
    EXPECT_EQ(quads2, quads) << "seed " << seed;
    ASSERT_EQ(points2.size(), points.size());
    for (std::size_t p = 0; p < points.size(); ++p) {
      EXPECT_EQ(points2[p].x(), points[p].x());
      EXPECT_EQ(points2[p].y(), points[p].y());
    }
  }
  std::printf("[cleanup] wobbly shapes: %zu irregular interior points before, %zu after\n", before, after);
  // The cleanup must do real work on paved meshes, not just keep them valid.
  EXPECT_LT(static_cast<double>(after), 0.8 * static_cast<double>(before));
}

TEST(QuadCleanup, PassCapStopsEarlyAndStillKeepsTheMeshValid) {
  // The bands of large parts get fewer passes (grid_interior.cpp): a capped cleanup must stop
  // at its cap, keep the boundary and validity, and still make the mesh more regular.
  const Polygon2 poly = wobbly(2 * 80, 104729);
  paving::Paver paver(poly, {});
  const PavedPart part = paver.run();
  const auto fixed = static_cast<Index>(poly.points.size());
  auto full_points = part.points;
  auto full_quads = part.quads;
  const auto full = paving::clean_up_quads(full_points, full_quads, fixed, paver.size());
  ASSERT_GT(full.passes, 2) << "the shape needs more passes than the cap below, else the cap is not exercised";
  auto points = part.points;
  auto quads = part.quads;
  const auto capped = paving::clean_up_quads(points, quads, fixed, paver.size(), 2);
  EXPECT_EQ(capped.passes, 2);
  EXPECT_LT(capped.irregular_after, capped.irregular_before);
  expect_conforming(quads, loop_edges(fixed));
  EXPECT_GT(min_quality(points, quads), 0);
  for (Index p = 0; p < fixed; ++p) EXPECT_EQ(points[p], poly.points[p]) << "boundary point " << p << " moved";
  auto again = part.points;
  auto again_quads = part.quads;
  EXPECT_THROW(paving::clean_up_quads(again, again_quads, fixed, paver.size(), 0), InputError);
}

}  // namespace
}  // namespace structmesh
