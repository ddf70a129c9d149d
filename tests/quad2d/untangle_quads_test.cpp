// untangle_quads(): folded grids whose valid placements are known to exist come out with
// every corner positive, fixed points stay bit-identical, and an impossible zone is
// reported as such instead of being claimed valid.
#include "quad2d/untangle_quads.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace structmesh {
namespace {

using Quads = std::vector<std::array<Index, 4>>;

/// An n x n grid of unit quads on [0, n]² (point (i, j) at index j (n + 1) + i).
struct Grid {
  int n;
  std::vector<Vec2> points;
  Quads quads;
  std::vector<Index> interior;
  explicit Grid(int size) : n(size) {
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        if (i > 0 && j > 0 && i < n && j < n) interior.push_back(id(i, j));
        points.emplace_back(i, j);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  }
  Index id(int i, int j) const { return static_cast<Index>(j * (n + 1) + i); }
};

double cross(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }

/// The smallest corner cross product of the quads.
double smallest_corner(const std::vector<Vec2>& p, const Quads& quads) {
  double smallest = INFINITY;
  for (const auto& q : quads)
    for (int i = 0; i < 4; ++i)
      smallest = std::min(smallest, cross(p[q[(i + 1) % 4]] - p[q[i]], p[q[(i + 3) % 4]] - p[q[i]]));
  return smallest;
}

TEST(UntangleQuads, PointThrownOutsideTheSquareComesBack) {
  Grid g(6);
  const std::vector<Vec2> before = g.points;
  g.points[g.id(2, 2)] = Vec2(10, -3);  // far outside: folds the 4 quads around it
  g.points[g.id(4, 3)] = Vec2(1, 5);
  ASSERT_LT(smallest_corner(g.points, g.quads), 0);
  const paving::UntangleResult r = paving::untangle_quads(g.points, g.quads, g.interior, 1.0);
  EXPECT_TRUE(r.valid);
  EXPECT_LT(r.min_det_before, 0);
  EXPECT_GT(r.min_det_after, 0);
  EXPECT_GT(smallest_corner(g.points, g.quads), 0);
  for (int j = 0; j <= 6; ++j)
    for (int i = 0; i <= 6; ++i)
      if (i == 0 || j == 0 || i == 6 || j == 6) {
        EXPECT_EQ(g.points[g.id(i, j)].x(), before[g.id(i, j)].x());
        EXPECT_EQ(g.points[g.id(i, j)].y(), before[g.id(i, j)].y());
      }
}

TEST(UntangleQuads, FullyScrambledInteriorOfAGridIsUntangled) {
  // Every interior point at a random place in the square: most quads fold. A convex
  // boundary with grid connectivity always has a valid placement (the grid itself).
  Grid g(10);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(0.0, 10.0);
  for (const Index p : g.interior) g.points[p] = Vec2(coordinate(random), coordinate(random));
  ASSERT_LT(smallest_corner(g.points, g.quads), 0);
  const paving::UntangleResult r = paving::untangle_quads(g.points, g.quads, g.interior, 1.0);
  EXPECT_TRUE(r.valid);
  EXPECT_GT(smallest_corner(g.points, g.quads), 0);
}

TEST(UntangleQuads, OnlyTheListedPointsMove) {
  Grid g(6);
  g.points[g.id(3, 3)] = Vec2(4.5, 4.6);  // past (4, 4): the quads around (3, 3) fold
  ASSERT_LT(smallest_corner(g.points, g.quads), 0);
  const std::vector<Vec2> before = g.points;
  // Free: the folded point and its 8 neighbours; (1, 1) must stay where it is.
  std::vector<Index> free;
  for (int j = 2; j <= 4; ++j)
    for (int i = 2; i <= 4; ++i) free.push_back(g.id(i, j));
  const paving::UntangleResult r = paving::untangle_quads(g.points, g.quads, free, 1.0);
  EXPECT_TRUE(r.valid);
  EXPECT_GT(smallest_corner(g.points, g.quads), 0);
  EXPECT_EQ(g.points[g.id(1, 1)], before[g.id(1, 1)]);
  EXPECT_EQ(g.points[g.id(5, 5)], before[g.id(5, 5)]);
}

TEST(UntangleQuads, ImpossibleCornerIsReportedNotClaimed) {
  // The corner at point 0 is inverted by its two fixed neighbours: no place for the one
  // free point helps.
  std::vector<Vec2> points{{0, 0}, {1, 0}, {1, 1}, {1, -0.5}};
  const Quads quads{{0, 1, 2, 3}};
  const std::vector<Index> free{2};
  const paving::UntangleResult r = paving::untangle_quads(points, quads, free, 1.0);
  EXPECT_FALSE(r.valid);
  EXPECT_LE(r.min_det_after, 0);
  EXPECT_TRUE(std::isfinite(points[2].x()) && std::isfinite(points[2].y()));
}

TEST(UntangleQuads, ValidInputStaysValidAndSkippedQuadsAreIgnored) {
  Grid g(4);
  g.quads.push_back({kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex});  // removed quad
  const paving::UntangleResult r = paving::untangle_quads(g.points, g.quads, g.interior, 1.0);
  EXPECT_TRUE(r.valid);
  g.quads.pop_back();
  EXPECT_GT(smallest_corner(g.points, g.quads), 0.5);  // the perfect grid stays near perfect
}

TEST(UntangleQuads, DeterministicBits) {
  Grid a(8), b(8);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> coordinate(0.0, 8.0);
  for (const Index p : a.interior) a.points[p] = b.points[p] = Vec2(coordinate(random), coordinate(random));
  paving::untangle_quads(a.points, a.quads, a.interior, 1.0);
  paving::untangle_quads(b.points, b.quads, b.interior, 1.0);
  for (std::size_t k = 0; k < a.points.size(); ++k) EXPECT_EQ(a.points[k], b.points[k]);
}

}  // namespace
}  // namespace structmesh
