#include "quad2d/interval_assignment.hpp"
#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>

namespace structmesh {
namespace {

// A regular k-gon of circumradius 1 with `per_side` segments on every side.
Polygon2 regular_polygon(int k, int per_side) {
  std::vector<Vec2> ring;
  for (int i = 0; i < k; ++i) {
    const double a = 2 * std::numbers::pi * i / k, b = 2 * std::numbers::pi * (i + 1) / k;
    const Vec2 p(std::cos(a), std::sin(a)), q(std::cos(b), std::sin(b));
    for (int j = 0; j < per_side; ++j) ring.push_back(p + (q - p) * (static_cast<double>(j) / per_side));
  }
  Polygon2 polygon;
  polygon.add_ring(ring);
  return polygon;
}

// Blocks of a regular k-gon with an even number of segments per side: split in the
// middle, every chord per_side / 2 segments.
PolarBlocks regular_blocks(int k, int per_side) {
  PolarBlocks blocks;
  for (int i = 0; i < k; ++i) {
    blocks.corners.push_back(i * per_side);
    blocks.splits.push_back(i * per_side + per_side / 2);
    blocks.chord_segments.push_back(static_cast<Index>(per_side / 2));
  }
  return blocks;
}

void expect_valid_blocks(const Polygon2& polygon, const PavedPart& part, std::size_t singular);

void expect_valid_polar(const Polygon2& polygon, const PavedPart& part, int k) {
  // The centre is the only interior singular vertex (none when k = 4).
  expect_valid_blocks(polygon, part, k == 4 ? 0U : 1U);
}

void expect_valid_blocks(const Polygon2& polygon, const PavedPart& part, std::size_t singular) {
  // Input points first, bit-identical.
  for (std::size_t i = 0; i < polygon.points.size(); ++i) ASSERT_EQ(part.points[i], polygon.points[i]);
  QuadMesh mesh;
  for (const Vec2& p : part.points) mesh.points.emplace_back(p.x(), p.y(), 0.0);
  mesh.quads = part.quads;
  const QuadQuality quality = quad_quality(mesh);
  EXPECT_EQ(quality.inverted, 0U);
  EXPECT_GT(quality.scaled_jacobian_stats.min, 0.3);
  EXPECT_EQ(quality.singular_vertices, singular);
  const EdgeAdjacency edges = build_edges(mesh);
  std::size_t boundary = 0;
  for (std::size_t e = 0; e < edges.edges.size(); ++e) {
    const std::size_t uses = edges.edge_elements.row(e).size();
    ASSERT_TRUE(uses == 1 || uses == 2);
    if (uses == 1) {
      ++boundary;
      // Every boundary edge is an input edge.
      const auto [a, b] = edges.edges[e];
      const std::size_t n = polygon.points.size();
      ASSERT_TRUE(a < n && b < n && (b == a + 1 || (a == 0 && b == n - 1))) << a << " " << b;
    }
  }
  EXPECT_EQ(boundary, polygon.points.size());
  EXPECT_NEAR(quad_mesh_area(mesh), area(polygon), 1e-9 * area(polygon));
}

TEST(PolarMesh, RegularPolygonsHaveOneSingularCentre) {
  for (const int k : {3, 4, 5, 6, 8}) {
    SCOPED_TRACE(k);
    const Polygon2 polygon = regular_polygon(k, 8);
    const std::optional<PavedPart> part = polar_mesh(polygon, regular_blocks(k, 8));
    ASSERT_TRUE(part.has_value());
    expect_valid_polar(polygon, *part, k);
    EXPECT_EQ(part->quads.size(), static_cast<std::size_t>(k) * 16U);
  }
}

TEST(PolarMesh, RejectsInconsistentBlocks) {
  const Polygon2 polygon = regular_polygon(5, 8);
  PolarBlocks blocks = regular_blocks(5, 8);
  blocks.chord_segments[2] = 3;  // side 1 would need 4 + 3 segments, it has 8
  EXPECT_THROW(polar_mesh(polygon, blocks), InputError);
  blocks = regular_blocks(5, 8);
  blocks.splits[0] = blocks.corners[0];
  EXPECT_THROW(polar_mesh(polygon, blocks), InputError);
  blocks = regular_blocks(5, 8);
  blocks.corners.pop_back();
  EXPECT_THROW(polar_mesh(polygon, blocks), InputError);
}

TEST(PolarMesh, CentreOutsideGivesNothing) {
  // A thin crescent-like pentagon whose centroid lies outside it.
  std::vector<Vec2> ring;
  const int per_side = 6;
  const std::vector<Vec2> corners{{0, 0}, {4, 0}, {4, 4}, {3.9, 0.1}, {0, 0.1}};
  for (std::size_t i = 0; i < corners.size(); ++i)
    for (int j = 0; j < per_side; ++j)
      ring.push_back(corners[i] + (corners[(i + 1) % corners.size()] - corners[i]) * (double(j) / per_side));
  Polygon2 polygon;
  polygon.add_ring(ring);
  ASSERT_GT(signed_area(polygon.ring(0)), 0);
  const std::optional<PavedPart> part = polar_mesh(polygon, regular_blocks(5, per_side));
  if (part) expect_valid_polar(polygon, *part, 5);  // if meshed at all, then validly
}

// A polygon through `corners` (counter-clockwise) with counts[i] segments on side i.
Polygon2 sampled_polygon(const std::vector<Vec2>& corners, const std::vector<int>& counts) {
  std::vector<Vec2> ring;
  for (std::size_t i = 0; i < corners.size(); ++i)
    for (int j = 0; j < counts[i]; ++j)
      ring.push_back(corners[i] + (corners[(i + 1) % corners.size()] - corners[i]) * (double(j) / counts[i]));
  Polygon2 polygon;
  polygon.add_ring(ring);
  return polygon;
}

// Every layout's counts hold: side i has r_{i-1} + r_{i+1} points, split at r_{i-1}.
void expect_consistent_layout(const PolarBlocks& blocks, std::int64_t n) {
  const std::size_t k = blocks.corners.size();
  ASSERT_GE(k, 3U);
  ASSERT_EQ(k % 2, 1U);
  ASSERT_EQ(blocks.splits.size(), k);
  ASSERT_EQ(blocks.chord_segments.size(), k);
  for (std::size_t i = 0; i < k; ++i) {
    const std::int64_t next = i + 1 < k ? blocks.corners[i + 1] : blocks.corners[0] + n;
    ASSERT_LT(blocks.corners[i], next);
    const Index before = blocks.chord_segments[(i + k - 1) % k], after = blocks.chord_segments[(i + 1) % k];
    EXPECT_GE(blocks.chord_segments[i], 1U);
    EXPECT_EQ(next - blocks.corners[i], static_cast<std::int64_t>(before + after)) << "side " << i;
    EXPECT_EQ((blocks.splits[i] - blocks.corners[i] + n) % n, static_cast<std::int64_t>(before)) << "split " << i;
  }
}

TEST(PolarBlockCandidates, PentagonGetsItsFiveCornersFirst) {
  const Polygon2 pentagon = regular_polygon(5, 8);
  const std::vector<PolarBlocks> layouts = polar_block_candidates(pentagon, 3);
  ASSERT_FALSE(layouts.empty());
  for (const PolarBlocks& blocks : layouts) expect_consistent_layout(blocks, 40);
  // No corner left out: the five corners themselves, every chord 4 segments.
  EXPECT_EQ(layouts[0].corners, (std::vector<std::int64_t>{0, 8, 16, 24, 32}));
  EXPECT_EQ(layouts[0].chord_segments, (std::vector<Index>{4, 4, 4, 4, 4}));
  const std::optional<PavedPart> part = polar_mesh(pentagon, layouts[0]);
  ASSERT_TRUE(part.has_value());
  expect_valid_polar(pentagon, *part, 5);
}

TEST(PolarBlockCandidates, UnmatchedRectangleGetsThreeBlocks) {
  // Opposite sides with 12 and 10, 7 and 9 points: no grid, but three corners of the
  // four (or one moved by a point) give integer chords.
  const Polygon2 rectangle = sampled_polygon({{0, 0}, {2, 0}, {2, 1.4}, {0, 1.4}}, {12, 7, 10, 9});
  const std::vector<PolarBlocks> layouts = polar_block_candidates(rectangle, 5);
  ASSERT_FALSE(layouts.empty());
  const std::vector<std::int64_t> corners{0, 12, 19, 29};
  for (const PolarBlocks& blocks : layouts) {
    expect_consistent_layout(blocks, 38);
    EXPECT_EQ(blocks.corners.size(), 3U);
    for (const std::int64_t c : blocks.corners) {
      const bool near_corner = std::any_of(corners.begin(), corners.end(), [&](std::int64_t k) {
        const std::int64_t d = std::abs(c - k);
        return std::min(d, 38 - d) <= 1;
      });
      EXPECT_TRUE(near_corner) << "corner " << c;
    }
    // Whatever polar_mesh makes of it is valid.
    const std::optional<PavedPart> part = polar_mesh(rectangle, blocks);
    if (part) expect_valid_polar(rectangle, *part, 3);
  }
}

TEST(PolarBlockCandidates, RoundedCornerIsOneCorner) {
  // A pentagon-like part whose corner at (4, 0) is cut by a short chamfer: two points
  // turning by about 45° each, one corner between them, not two.
  const Polygon2 part =
      sampled_polygon({{0, 0}, {3.8, 0}, {4, 0.2}, {4, 3}, {2, 4.5}, {0, 3}}, {19, 1, 14, 12, 12, 16});
  const std::int64_t n = static_cast<std::int64_t>(part.points.size());
  ASSERT_EQ(n % 2, 0);
  const std::vector<PolarBlocks> layouts = polar_block_candidates(part, 3);
  ASSERT_FALSE(layouts.empty());
  for (const PolarBlocks& blocks : layouts) {
    expect_consistent_layout(blocks, n);
    const auto at = [&](std::int64_t i) {
      return std::find(blocks.corners.begin(), blocks.corners.end(), i) != blocks.corners.end();
    };
    EXPECT_FALSE(at(19) && at(20)) << "both ends of the chamfer taken as corners";
  }
  // Five corners (chamfer, three others, the origin): the first layout takes them all.
  EXPECT_EQ(layouts[0].corners.size(), 5U);
}

TEST(PolarBlockCandidates, NoLayoutWithoutCornersOrWithHolesOrAnOddLoop) {
  // A circle turns by 9° per point: no corner.
  EXPECT_TRUE(polar_block_candidates(regular_polygon(40, 1), 3).empty());
  // A ring (a hole).
  Polygon2 annulus = regular_polygon(4, 6);
  std::vector<Vec2> hole;
  for (int i = 0; i < 8; ++i)
    hole.emplace_back(0.3 * std::cos(-i * std::numbers::pi / 4), 0.3 * std::sin(-i * std::numbers::pi / 4));
  annulus.add_ring(hole);
  EXPECT_TRUE(polar_block_candidates(annulus, 3).empty());
  // An odd number of points.
  EXPECT_TRUE(polar_block_candidates(sampled_polygon({{0, 0}, {1, 0}, {0.5, 1}}, {5, 5, 5}), 3).empty());
  // A comb with 12 corners: more than a polar layout takes.
  std::vector<Vec2> comb{{0, 0}, {6, 0}, {6, 2}};
  for (int t = 5; t >= 1; --t) {
    comb.emplace_back(t + 0.5, 2);
    comb.emplace_back(t + 0.5, 1);
    comb.emplace_back(t, 1);
    comb.emplace_back(t, 2);
  }
  comb.emplace_back(0, 2);
  EXPECT_TRUE(polar_block_candidates(sampled_polygon(comb, std::vector<int>(comb.size(), 2)), 3).empty());
  EXPECT_TRUE(polar_block_candidates(regular_polygon(5, 8), 0).empty());
}

TEST(IntervalAssignment, MakesOppositeSidesMatchAndPartsEven) {
  // Two unit squares side by side, sides of ideal length 10, 10, 10 and the shared
  // one; the top/bottom of the right square are 13 long: matching forces the
  // left square's opposite sides equal and the right one's too.
  quad2d::IntervalProblem problem;
  // edges: 0 bottom-left, 1 shared, 2 top-left, 3 left, 4 bottom-right, 5 right, 6 top-right
  problem.ideal = {10, 10, 10.4, 10, 13, 9.6, 12.6};
  problem.minimum.assign(7, 1);
  problem.part_edges = {{0, 1, 2, 3}, {4, 5, 6, 1}};
  problem.four_sided.push_back({0, {{{0}, {1}, {2}, {3}}}});
  problem.four_sided.push_back({1, {{{4}, {5}, {6}, {1}}}});
  const quad2d::IntervalSolution s = quad2d::solve_interval_assignment(problem);
  ASSERT_TRUE(s.solved);
  EXPECT_EQ(s.mapped, (std::vector<std::uint8_t>{1, 1}));
  EXPECT_EQ(s.counts[0], s.counts[2]);
  EXPECT_EQ(s.counts[1], s.counts[3]);
  EXPECT_EQ(s.counts[4], s.counts[6]);
  EXPECT_EQ(s.counts[5], s.counts[1]);
  // Every count within one segment of its ideal.
  for (std::size_t e = 0; e < 7; ++e) EXPECT_LE(std::abs(double(s.counts[e]) - problem.ideal[e]), 1.0) << e;
}

TEST(IntervalAssignment, PolarPentagonCountsHold) {
  quad2d::IntervalProblem problem;
  problem.ideal = {7.2, 8.1, 6.9, 7.7, 8.4};  // one edge per side
  problem.minimum.assign(5, 1);
  problem.part_edges = {{0, 1, 2, 3, 4}};
  quad2d::IntervalProblem::Polar polar;
  polar.part = 0;
  polar.sides = {{0}, {1}, {2}, {3}, {4}};
  polar.chord_ideal = {4, 4, 4, 4, 4};
  problem.polar.push_back(polar);
  const quad2d::IntervalSolution s = quad2d::solve_interval_assignment(problem);
  ASSERT_TRUE(s.solved);
  ASSERT_EQ(s.polar, (std::vector<std::uint8_t>{1}));
  const auto& r = s.chord_segments[0];
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(s.counts[i], r[(i + 4) % 5] + r[(i + 1) % 5]) << i;
}

TEST(IntervalAssignment, TrapezoidTakesItsPolarAlternativeAndNeverBoth) {
  // A four-sided part with sides 20, 10, 8, 10: bottom and top cannot match within
  // the allowed size range, so the grid is out; the three-block alternative (corners
  // 0, 1, 2; the last side joins top and left) holds. The pair is exclusive.
  quad2d::IntervalProblem problem;
  problem.ideal = {20, 10, 8, 10};
  problem.minimum.assign(4, 1);
  problem.part_edges = {{0, 1, 2, 3}};
  problem.four_sided.push_back({0, {{{0}, {1}, {2}, {3}}}});
  quad2d::IntervalProblem::Polar polar;
  polar.part = 0;
  polar.sides = {{0}, {1}, {2, 3}};
  polar.chord_ideal = {5, 5, 5};
  problem.polar.push_back(polar);
  problem.exclusive.emplace_back(0, 0);
  const quad2d::IntervalSolution s = quad2d::solve_interval_assignment(problem);
  ASSERT_TRUE(s.solved);
  EXPECT_EQ(s.mapped, (std::vector<std::uint8_t>{0}));
  ASSERT_EQ(s.polar, (std::vector<std::uint8_t>{1}));
  const auto& r = s.chord_segments[0];
  EXPECT_EQ(s.counts[0], r[2] + r[1]);
  EXPECT_EQ(s.counts[1], r[0] + r[2]);
  EXPECT_EQ(s.counts[2] + s.counts[3], r[1] + r[0]);
  EXPECT_EQ((s.counts[0] + s.counts[1] + s.counts[2] + s.counts[3]) % 2, 0U);

  // A square: both would hold; the MILP may reward only one, the grid (larger reward).
  problem.ideal = {10, 10, 10, 10};
  const quad2d::IntervalSolution square = quad2d::solve_interval_assignment(problem);
  ASSERT_TRUE(square.solved);
  EXPECT_EQ(square.mapped, (std::vector<std::uint8_t>{1}));
  EXPECT_EQ(square.polar.size(), 1U);
  EXPECT_FALSE(square.mapped[0] && square.polar[0]) << "both blocks rewarded";
}

TEST(IntervalAssignment, ClustersOfARowOfSquaresAgreeOnSharedEdges) {
  // 30 squares in a row: edges 3i (bottom of square i), 3i+1 (top), 3i+2 (the left
  // side, shared with square i-1's right side), 90 (the last right side). Ideal lengths
  // wobble so that matching needs changes; solved in clusters of 4 squares, every
  // square must still come out a grid, and shared edges have one count.
  quad2d::IntervalProblem problem;
  const std::size_t n = 30;
  problem.ideal.assign(3 * n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    problem.ideal[3 * i] = 10 + 0.3 * static_cast<double>(i % 3);
    problem.ideal[3 * i + 1] = 10.4 - 0.2 * static_cast<double>(i % 2);
    problem.ideal[3 * i + 2] = 8 + 0.25 * static_cast<double>(i % 4);
  }
  problem.ideal[3 * n] = 8.6;
  problem.minimum.assign(problem.ideal.size(), 1);
  for (std::size_t i = 0; i < n; ++i) {
    const Index bottom = static_cast<Index>(3 * i), top = bottom + 1, left = bottom + 2;
    const Index right = i + 1 < n ? static_cast<Index>(3 * (i + 1) + 2) : static_cast<Index>(3 * n);
    problem.part_edges.push_back({bottom, right, top, left});
    problem.four_sided.push_back({i, {{{bottom}, {right}, {top}, {left}}}});
  }
  const quad2d::IntervalSolution s = quad2d::solve_interval_assignment_in_clusters(problem, 4);
  ASSERT_TRUE(s.solved);
  ASSERT_EQ(s.counts.size(), problem.ideal.size());
  for (std::size_t i = 0; i < n; ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(s.mapped[i], 1);
    const auto& e = problem.part_edges[i];
    EXPECT_EQ(s.counts[e[0]], s.counts[e[2]]);
    EXPECT_EQ(s.counts[e[1]], s.counts[e[3]]);
  }
  // Clusters that share no edge are solved in parallel: one thread gives the same counts.
  quad2d::IntervalSolution one_thread;
  tbb::task_arena(1).execute([&] { one_thread = quad2d::solve_interval_assignment_in_clusters(problem, 4); });
  EXPECT_EQ(one_thread.counts, s.counts);
  EXPECT_EQ(one_thread.mapped, s.mapped);
  EXPECT_THROW(quad2d::solve_interval_assignment_in_clusters(problem, 0), InputError);
}

TEST(PolarMesh, UnevenBlocksArePolishedTogether) {
  // A scalene triangle whose long side bends outward at its split point, meshed as
  // three polar blocks: with straight chords to the centroid the blocks' worst corner
  // is below the acceptance threshold; moving the chord points and the centre with
  // the interiors must lift it over (or give nothing, which this shape must not).
  const Vec2 a(0, 0), b(4, 0), c(1, 2.6), bend(0.2, 1.4);
  const std::vector<Vec2> corners{a, b, c, bend};
  const std::vector<int> per_side{14, 12, 6, 6};  // 38 segments; the bend splits side c -> a
  std::vector<Vec2> ring;
  for (std::size_t i = 0; i < corners.size(); ++i)
    for (int j = 0; j < per_side[i]; ++j)
      ring.push_back(corners[i] + (corners[(i + 1) % corners.size()] - corners[i]) * (double(j) / per_side[i]));
  Polygon2 polygon;
  polygon.add_ring(ring);
  // Sides 14 (a -> b), 12 (b -> c), 12 (c -> a over the bend); side i = r_{i-1} +
  // r_{i+1} gives r = (5, 7, 7); side i's first piece has r_{i-1} segments.
  PolarBlocks blocks;
  blocks.corners = {0, 14, 26};
  blocks.chord_segments = {5, 7, 7};
  blocks.splits = {0 + 7, 14 + 5, 26 + 7};
  const std::optional<PavedPart> part = polar_mesh(polygon, blocks);
  ASSERT_TRUE(part.has_value());
  QuadMesh mesh;
  for (const Vec2& p : part->points) mesh.points.emplace_back(p.x(), p.y(), 0.0);
  mesh.quads = part->quads;
  const QuadQuality quality = quad_quality(mesh);
  EXPECT_EQ(quality.inverted, 0U);
  EXPECT_GE(quality.scaled_jacobian_stats.min, MappedMeshOptions{}.min_scaled_jacobian);
  EXPECT_EQ(quality.singular_vertices, 1U);
  EXPECT_NEAR(quad_mesh_area(mesh), area(polygon), 1e-9 * area(polygon));
  for (std::size_t i = 0; i < polygon.points.size(); ++i) ASSERT_EQ(part->points[i], polygon.points[i]);
  // Right angles must not be bought with slivers: an energy for angles alone
  // stretched quads to edge ratios of 10 and more on such parts.
  double worst_ratio = 0;
  for (const auto& q : part->quads) {
    double shortest = INFINITY, longest = 0;
    for (int e = 0; e < 4; ++e) {
      const double length = (part->points[q[(e + 1) % 4]] - part->points[q[e]]).norm();
      shortest = std::min(shortest, length);
      longest = std::max(longest, length);
    }
    worst_ratio = std::max(worst_ratio, longest / shortest);
  }
  EXPECT_LT(worst_ratio, 4.0);
}

// Interior points of the mesh by their number of quads.
std::map<int, int> interior_valences(const Polygon2& polygon, const PavedPart& part) {
  std::vector<int> quads_at(part.points.size(), 0);
  for (const auto& q : part.quads)
    for (const Index v : q) ++quads_at[v];
  std::map<int, int> count;
  for (std::size_t v = polygon.points.size(); v < part.points.size(); ++v) ++count[quads_at[v]];
  return count;
}

TEST(TransitionBlockCandidates, TrapezoidGetsAThreeFivePair) {
  // Bottom 40 segments, top 20: no grid fits and a three-block layout must leave a
  // corner inside a block side; the transition keeps all four corners as block corners
  // and takes up the difference of 20 in a triangle on the bottom.
  const Polygon2 trapezoid = sampled_polygon({{0, 0}, {4, 0}, {3, 2}, {1, 2}}, {40, 22, 20, 22});
  const std::vector<PolarBlocks> layouts = transition_block_candidates(trapezoid, 3);
  ASSERT_FALSE(layouts.empty());
  for (const PolarBlocks& blocks : layouts) {
    ASSERT_EQ(blocks.corners.size(), 5U);
    ASSERT_EQ(blocks.triangle.size(), 5U);
    EXPECT_EQ(std::count(blocks.triangle.begin(), blocks.triangle.end(), 1), 1);
    // The four corners of the trapezoid are among the layout's corners.
    for (const std::int64_t c : {0, 40, 62, 82})
      EXPECT_NE(std::find(blocks.corners.begin(), blocks.corners.end(), c), blocks.corners.end()) << c;
    // The triangle sits on the bottom, between the corners at 0 and 40.
    const auto t = static_cast<std::size_t>(std::find(blocks.triangle.begin(), blocks.triangle.end(), 1) -
                                            blocks.triangle.begin());
    EXPECT_GT(blocks.corners[t], 0);
    EXPECT_LT(blocks.corners[t], 40);
  }
  const std::optional<PavedPart> part = polar_mesh(trapezoid, layouts[0]);
  ASSERT_TRUE(part.has_value());
  // Two interior singular vertices: the centre (5 quads) and the triangle's (3).
  expect_valid_blocks(trapezoid, *part, 2U);
  const std::map<int, int> valences = interior_valences(trapezoid, *part);
  EXPECT_EQ(valences.count(5) ? valences.at(5) : 0, 1);
  EXPECT_EQ(valences.count(3) ? valences.at(3) : 0, 1);
  QuadMesh mesh;
  for (const Vec2& p : part->points) mesh.points.emplace_back(p.x(), p.y(), 0.0);
  mesh.quads = part->quads;
  EXPECT_GE(quad_quality(mesh).scaled_jacobian_stats.min, MappedMeshOptions{}.min_scaled_jacobian);
}

TEST(TransitionBlockCandidates, NoneWhereAGridFitsOrWithoutFourCorners) {
  // Opposite sides match: a grid, no transition.
  EXPECT_TRUE(
      transition_block_candidates(sampled_polygon({{0, 0}, {2, 0}, {2, 1}, {0, 1}}, {20, 10, 20, 10}), 3).empty());
  // Three corners, a circle, an odd loop, no candidates asked for.
  EXPECT_TRUE(transition_block_candidates(sampled_polygon({{0, 0}, {2, 0}, {1, 1.7}}, {10, 10, 10}), 3).empty());
  EXPECT_TRUE(transition_block_candidates(regular_polygon(40, 1), 3).empty());
  EXPECT_TRUE(
      transition_block_candidates(sampled_polygon({{0, 0}, {4, 0}, {3, 2}, {1, 2}}, {40, 22, 19, 22}), 3).empty());
  EXPECT_TRUE(
      transition_block_candidates(sampled_polygon({{0, 0}, {4, 0}, {3, 2}, {1, 2}}, {40, 22, 20, 22}), 0).empty());
}

TEST(PolarMesh, RejectsATriangleBlockThatIsNoTriangle) {
  // The trapezoid's layout with the triangle's legs made as long as its base plus the
  // other leg: the triangle inequalities fail.
  const Polygon2 trapezoid = sampled_polygon({{0, 0}, {4, 0}, {3, 2}, {1, 2}}, {40, 22, 20, 22});
  std::vector<PolarBlocks> layouts = transition_block_candidates(trapezoid, 1);
  ASSERT_EQ(layouts.size(), 1U);
  PolarBlocks blocks = layouts[0];
  const auto t =
      static_cast<std::size_t>(std::find(blocks.triangle.begin(), blocks.triangle.end(), 1) - blocks.triangle.begin());
  const std::size_t k = blocks.corners.size(), previous = (t + k - 1) % k;
  const std::int64_t base = blocks.splits[t] - blocks.splits[previous];
  // Unflagged, the triangle is taken as a grid block, whose opposite sides differ.
  PolarBlocks unflagged = blocks;
  unflagged.triangle.assign(k, 0);
  EXPECT_THROW(polar_mesh(trapezoid, unflagged), InputError);
  blocks.chord_segments[t] = static_cast<Index>(base + blocks.chord_segments[previous]);
  EXPECT_THROW(polar_mesh(trapezoid, blocks), InputError);
  blocks = layouts[0];
  blocks.triangle.pop_back();
  EXPECT_THROW(polar_mesh(trapezoid, blocks), InputError);
}

}  // namespace
}  // namespace structmesh
