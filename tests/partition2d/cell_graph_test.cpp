// Cell graph, corner costs (3.6)-(3.8) and connectivity repair on hand-checkable
// tessellations (graph_fixtures.hpp); expected values worked out in the comments.
#include "partition2d/graph_fixtures.hpp"

#include "structmesh/error.hpp"
#include "structmesh/regions.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace structmesh::partition2d {
namespace {

using testing::grid_tessellation;
using testing::GridSquare;
using testing::hex_tessellation;
using testing::polygon_tessellation;

constexpr double kPi = std::numbers::pi;

// The corner whose position is p (to 1e-9), or kInvalidIndex.
Index corner_at(const CellGraph& g, const Vec2& p) {
  for (Index c = 0; c < g.corner_position.size(); ++c)
    if ((g.corner_position[c] - p).norm() < 1e-9) return c;
  return kInvalidIndex;
}

std::vector<CellGraph::Spoke> spokes_of(const CellGraph& g, Index c) {
  return {g.spokes.begin() + g.corner_offsets[c], g.spokes.begin() + g.corner_offsets[c + 1]};
}

// L_S (3.3): total length of arcs between different labels, each arc once.
double separator_length(const CellGraph& g, const std::vector<std::int32_t>& label) {
  double total = 0;
  for (Index v = 0; v < g.node_count(); ++v)
    for (Index a = g.adjacency_offsets[v]; a < g.adjacency_offsets[v + 1]; ++a)
      if (g.adjacency[a] > v && label[v] != label[g.adjacency[a]]) total += g.arc_length[a];
  return total;
}

std::vector<std::int32_t> grid_labels(int nx, int ny, const std::function<std::int32_t(int, int)>& f) {
  std::vector<std::int32_t> labels;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) labels.push_back(f(i, j));
  return labels;
}

// Symmetric CSR, sorted rows, no self loops or duplicates; node_corners consistent
// with the sectors of the corners.
void expect_well_formed(const CellGraph& g) {
  ASSERT_EQ(g.adjacency_offsets.size(), g.node_count() + 1);
  for (Index v = 0; v < g.node_count(); ++v) {
    for (Index a = g.adjacency_offsets[v]; a < g.adjacency_offsets[v + 1]; ++a) {
      const Index w = g.adjacency[a];
      EXPECT_NE(w, v);
      if (a > g.adjacency_offsets[v]) {
        EXPECT_LT(g.adjacency[a - 1], w);
      }
      const auto row_begin = g.adjacency.begin() + g.adjacency_offsets[w];
      const auto row_end = g.adjacency.begin() + g.adjacency_offsets[w + 1];
      const auto back = std::find(row_begin, row_end, v);
      ASSERT_NE(back, row_end);
      EXPECT_EQ(g.arc_length[back - g.adjacency.begin()], g.arc_length[a]);  // bit-identical
    }
  }
  for (Index c = 0; c < g.corner_position.size(); ++c) {
    for (Index s = g.corner_offsets[c]; s < g.corner_offsets[c + 1]; ++s) {
      if (s > g.corner_offsets[c]) {
        EXPECT_LE(g.spokes[s - 1].angle, g.spokes[s].angle);
      }
      const Index node = g.spokes[s].left_node;
      if (node == kInvalidIndex) continue;
      const auto begin = g.node_corners.begin() + g.node_corner_offsets[node];
      const auto end = g.node_corners.begin() + g.node_corner_offsets[node + 1];
      EXPECT_NE(std::find(begin, end, c), end);
    }
  }
}

TEST(AngleDeviation, NearestMultipleOfRightAngle) {
  EXPECT_NEAR(angle_deviation(0), 0, 1e-15);
  EXPECT_NEAR(angle_deviation(kPi / 4), kPi / 4, 1e-15);
  EXPECT_NEAR(angle_deviation(kPi / 2), 0, 1e-15);
  EXPECT_NEAR(angle_deviation(kPi), 0, 1e-15);
  EXPECT_NEAR(angle_deviation(2 * kPi), 0, 1e-15);
  EXPECT_NEAR(angle_deviation(3 * kPi / 8), kPi / 8, 1e-15);
  EXPECT_NEAR(angle_deviation(2 * kPi / 3), kPi / 6, 1e-15);  // the 120° of a Voronoi vertex
  EXPECT_NEAR(angle_deviation(4 * kPi / 3), kPi / 6, 1e-15);  // its reflex side
  EXPECT_NEAR(angle_deviation(5 * kPi / 4), kPi / 4, 1e-15);
  EXPECT_NEAR(angle_deviation(-kPi / 6), kPi / 6, 1e-15);
  EXPECT_NEAR(angle_deviation(-3 * kPi / 8), kPi / 8, 1e-15);
  EXPECT_NEAR(angle_deviation(-kPi / 2), 0, 1e-15);
  EXPECT_NEAR(angle_deviation(-2 * kPi + 0.1), 0.1, 1e-14);
  // Symmetries of §1.4: delta(theta) = delta(2 pi - theta) = delta(pi - theta).
  for (double t = -7; t < 7; t += 0.37) {
    EXPECT_GE(angle_deviation(t), 0);
    EXPECT_LE(angle_deviation(t), kPi / 4 + 1e-15);
    EXPECT_NEAR(angle_deviation(t), angle_deviation(2 * kPi - t), 1e-12);
    EXPECT_NEAR(angle_deviation(t), angle_deviation(kPi - t), 1e-12);
  }
}

TEST(CellGraph, GridOfUnitSquares) {
  const CellGraph g = build_cell_graph(grid_tessellation(4, 4), 1e-3);
  expect_well_formed(g);
  ASSERT_EQ(g.node_count(), 16u);
  for (Index v = 0; v < 16; ++v) {
    EXPECT_EQ(g.face_node[v], v);  // one face per cell: node = face
    EXPECT_EQ(g.node_cell[v], v);
    EXPECT_DOUBLE_EQ(g.node_area[v], 1.0);
  }
  EXPECT_EQ(g.adjacency.size(), 2u * 24u);  // 2 * 4 * 3 shared edges, both directions
  for (double length : g.arc_length) EXPECT_EQ(length, 1.0);
  const std::vector<Index> row5(g.adjacency.begin() + g.adjacency_offsets[5],
                                g.adjacency.begin() + g.adjacency_offsets[6]);
  EXPECT_EQ(row5, (std::vector<Index>{1, 4, 6, 9}));
  EXPECT_DOUBLE_EQ(g.mean_arc_length, 1.0);

  // 9 interior vertices + 12 boundary vertices where a separating edge meets the
  // boundary; the rectangle's 4 corners have boundary edges only.
  EXPECT_EQ(g.corner_position.size(), 21u);
  EXPECT_EQ(corner_at(g, {0, 0}), kInvalidIndex);
  const Index centre = corner_at(g, {1, 1});
  ASSERT_NE(centre, kInvalidIndex);
  const auto s = spokes_of(g, centre);
  ASSERT_EQ(s.size(), 4u);
  const double angles[] = {-kPi / 2, 0, kPi / 2, kPi};
  const Index left[] = {1, 5, 4, 0};  // sector after each spoke, counter-clockwise
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(s[k].angle, angles[k], 1e-15);
    EXPECT_EQ(s[k].left_node, left[k]);
  }
  for (int x = 1; x <= 3; ++x)
    for (int y = 1; y <= 3; ++y) {
      const Index c = corner_at(g, Vec2(x, y));
      ASSERT_NE(c, kInvalidIndex);
      const auto spokes = spokes_of(g, c);
      ASSERT_EQ(spokes.size(), 4u);
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(spokes[k].angle, angles[k], 1e-15);
    }
  const Index side = corner_at(g, {2, 0});
  ASSERT_NE(side, kInvalidIndex);
  const auto b = spokes_of(g, side);
  ASSERT_EQ(b.size(), 3u);
  EXPECT_NEAR(b[0].angle, 0, 1e-15);
  EXPECT_EQ(b[0].left_node, 2u);
  EXPECT_NEAR(b[1].angle, kPi / 2, 1e-15);
  EXPECT_EQ(b[1].left_node, 1u);
  EXPECT_NEAR(b[2].angle, kPi, 1e-15);
  EXPECT_EQ(b[2].left_node, kInvalidIndex);  // outside

  // Node 0 = square (0,0): corners (1,0), (1,1), (0,1); node 5 has all four.
  EXPECT_EQ(g.node_corner_offsets[1] - g.node_corner_offsets[0], 3u);
  EXPECT_EQ(g.node_corner_offsets[6] - g.node_corner_offsets[5], 4u);
}

TEST(CellGraph, CellSplitByHoleIsTwoNodes) {
  // Squares (0,0) and (2,0) of one cell, the square between them missing.
  const Tessellation t = grid_tessellation(3, 1, {GridSquare{1, 0}}, [](int, int) { return Index{0}; });
  const CellGraph g = build_cell_graph(t, 1e-3);
  ASSERT_EQ(g.node_count(), 2u);
  EXPECT_EQ(g.node_cell, (std::vector<Index>{0, 0}));
  EXPECT_EQ(g.face_node, (std::vector<Index>{0, 1}));
  EXPECT_TRUE(g.adjacency.empty());
  EXPECT_TRUE(g.corner_position.empty());
  EXPECT_EQ(g.mean_arc_length, 0.0);

  // Without the hole the two faces (and the one between) are one node of area 3.
  const CellGraph whole = build_cell_graph(grid_tessellation(3, 1, {}, [](int, int) { return Index{0}; }), 1e-3);
  ASSERT_EQ(whole.node_count(), 1u);
  EXPECT_DOUBLE_EQ(whole.node_area[0], 3.0);
}

TEST(CellGraph, HoleBoundaryGivesBoundarySpokes) {
  // 3 x 3 squares without the centre one: faces 0 (0,0), 1 (1,0), 2 (2,0), 3 (0,1),
  // 4 (2,1), 5 (0,2), 6 (1,2), 7 (2,2). At (1,1) the hole fills the sector 0..pi/2.
  const Tessellation t = grid_tessellation(3, 3, {GridSquare{1, 1}});
  std::size_t hole_edges = 0;
  for (std::size_t h = 0; h < t.twin.size(); ++h) hole_edges += t.boundary_ring[h] == 1;
  EXPECT_EQ(hole_edges, 4u);
  const CellGraph g = build_cell_graph(t, 1e-3);
  expect_well_formed(g);
  ASSERT_EQ(g.node_count(), 8u);
  const Index c = corner_at(g, {1, 1});
  ASSERT_NE(c, kInvalidIndex);
  const auto s = spokes_of(g, c);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].left_node, 1u);             // -pi/2: separator between faces 0 and 1
  EXPECT_EQ(s[1].left_node, kInvalidIndex);  // 0: hole boundary, the hole on its left
  EXPECT_EQ(s[2].left_node, 3u);             // pi/2: hole boundary
  EXPECT_EQ(s[3].left_node, 0u);             // pi: separator between faces 3 and 0
  // Every face its own part: the separators meet at 90° (one separator corner), each
  // separator meets the hole at 90° (two boundary corners), the hole's own 90° bend
  // between two boundary spokes counts nothing.
  const std::vector<std::int32_t> labels{0, 1, 2, 3, 4, 5, 6, 7};
  const CornerCost cost = corner_cost_at(g, c, labels);
  EXPECT_EQ(cost.separator_corners, 1u);
  EXPECT_EQ(cost.boundary_corners, 2u);
  EXPECT_NEAR(cost.separator_sum + cost.boundary_sum, 0, 1e-15);
  // Faces 0, 1, 3 one part: no separator passes (1,1), nothing counts.
  const CornerCost none = corner_cost_at(g, c, std::vector<std::int32_t>{0, 0, 1, 0, 1, 1, 1, 1});
  EXPECT_EQ(none.separator_corners + none.boundary_corners, 0u);
}

TEST(CellGraph, InteriorEdgesAreNotSpokesAndPassThroughVerticesAreLeftOut) {
  // 2 x 2 squares, one cell per row: the separator y = 1 runs straight through (1,1),
  // where only the cells' interior edges meet it.
  const Tessellation t = grid_tessellation(2, 2, {}, [](int, int j) { return static_cast<Index>(j); });
  const CellGraph g = build_cell_graph(t, 1e-3);
  expect_well_formed(g);
  ASSERT_EQ(g.node_count(), 2u);
  EXPECT_DOUBLE_EQ(g.node_area[0], 2.0);
  ASSERT_EQ(g.adjacency.size(), 2u);
  EXPECT_DOUBLE_EQ(g.arc_length[0], 2.0);  // two unit half-edges, one arc
  EXPECT_EQ(corner_at(g, {1, 1}), kInvalidIndex);
  EXPECT_EQ(g.corner_position.size(), 2u);  // (0,1) and (2,1), on the boundary
  const Index end = corner_at(g, {0, 1});
  ASSERT_NE(end, kInvalidIndex);
  EXPECT_EQ(spokes_of(g, end).size(), 3u);
  // The separator is one primal edge of length 2 (its pieces meet at a pass-through vertex).
  EXPECT_DOUBLE_EQ(g.mean_arc_length, 2.0);
}

TEST(CornerCost, QuadrantsOfAGrid) {
  const CellGraph g = build_cell_graph(grid_tessellation(4, 4), 1e-3);
  const auto labels = grid_labels(4, 4, [](int i, int j) { return (i >= 2 ? 1 : 0) + (j >= 2 ? 2 : 0); });
  EXPECT_DOUBLE_EQ(separator_length(g, labels), 8.0);
  const CornerCost cost = corner_cost(g, labels);
  // Centre: 4 active spokes -> 4 right-angle separator corners; (2,1), (2,3), (1,2),
  // (3,2): 2 active spokes straight through (theta = pi); all delta 0.
  EXPECT_EQ(cost.separator_corners, 8u);
  EXPECT_NEAR(cost.separator_sum, 0, 1e-15);
  // Where the separators meet the boundary: two right-angle corners each.
  EXPECT_EQ(cost.boundary_corners, 8u);
  EXPECT_NEAR(cost.boundary_sum, 0, 1e-15);
  const CornerCost centre = corner_cost_at(g, corner_at(g, {2, 2}), labels);
  EXPECT_EQ(centre.separator_corners, 4u);
  EXPECT_EQ(centre.boundary_corners, 0u);
  const CornerCost end = corner_cost_at(g, corner_at(g, {2, 0}), labels);
  EXPECT_EQ(end.separator_corners, 0u);
  EXPECT_EQ(end.boundary_corners, 2u);
  // A plain boundary vertex (both active spokes on the boundary) counts nothing.
  const CornerCost plain = corner_cost_at(g, corner_at(g, {1, 0}), labels);
  EXPECT_EQ(plain.separator_corners + plain.boundary_corners, 0u);
  // One label everywhere: no corners at all.
  const std::vector<std::int32_t> one(16, 0);
  const CornerCost none = corner_cost(g, one);
  EXPECT_EQ(none.separator_corners + none.boundary_corners, 0u);
}

TEST(CornerCost, StaircaseBendsAreRightAngles) {
  // Squares below the diagonal (i > j) against the rest: the separator is the
  // staircase (1,0)-(1,1)-(2,1)-(2,2)-(3,2)-(3,3)-(4,3) with 5 bends of pi/2 or 3pi/2.
  const CellGraph g = build_cell_graph(grid_tessellation(4, 4), 1e-3);
  const auto labels = grid_labels(4, 4, [](int i, int j) { return i > j ? 1 : 0; });
  EXPECT_DOUBLE_EQ(separator_length(g, labels), 6.0);
  const CornerCost cost = corner_cost(g, labels);
  EXPECT_EQ(cost.separator_corners, 5u);
  EXPECT_NEAR(cost.separator_sum, 0, 1e-15);
  EXPECT_EQ(cost.boundary_corners, 4u);  // at (1,0) and (4,3)
  EXPECT_NEAR(cost.boundary_sum, 0, 1e-15);
}

TEST(CellGraph, HexagonPatch) {
  // Rows of 3 pointy-top hexagons, edge length 1; row 1 sits on row 0.
  const CellGraph g = build_cell_graph(hex_tessellation(3, 2), 1e-3);
  expect_well_formed(g);
  ASSERT_EQ(g.node_count(), 6u);
  for (double a : g.node_area) EXPECT_NEAR(a, 1.5 * std::sqrt(3.0), 1e-12);
  EXPECT_EQ(g.adjacency.size(), 2u * 9u);  // 2 + 2 within rows, 5 between them
  for (double length : g.arc_length) EXPECT_NEAR(length, 1.0, 1e-12);
  // An interior vertex: three spokes 120° apart, one hexagon per sector.
  const double r3 = std::sqrt(3.0);
  const Index c = corner_at(g, {r3 / 2, 0.5});
  ASSERT_NE(c, kInvalidIndex);
  const auto s = spokes_of(g, c);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_NEAR(s[0].angle, -kPi / 2, 1e-12);
  EXPECT_NEAR(s[1].angle, kPi / 6, 1e-12);
  EXPECT_NEAR(s[2].angle, 5 * kPi / 6, 1e-12);
  EXPECT_EQ(s[0].left_node, 1u);  // hexagon (q=1, r=0), lower right
  EXPECT_EQ(s[1].left_node, 3u);  // hexagon (q=0, r=1), above
  EXPECT_EQ(s[2].left_node, 0u);  // hexagon (q=0, r=0), lower left
}

TEST(CornerCost, HexagonRowsMeetAt120Degrees) {
  // Row 0 against row 1: the separator zigzags through 4 interior vertices, each with
  // two active spokes 120° apart -> delta = pi/6; it meets the boundary at (0,1) and
  // (5 sqrt(3)/2, 1/2), each with two 120° separator/boundary corners.
  const CellGraph g = build_cell_graph(hex_tessellation(3, 2), 1e-3);
  const std::vector<std::int32_t> labels{0, 0, 0, 1, 1, 1};
  EXPECT_NEAR(separator_length(g, labels), 5.0, 1e-12);
  const CornerCost cost = corner_cost(g, labels);
  EXPECT_EQ(cost.separator_corners, 4u);
  EXPECT_NEAR(cost.separator_sum, 4 * kPi / 6, 1e-12);
  EXPECT_EQ(cost.boundary_corners, 4u);
  EXPECT_NEAR(cost.boundary_sum, 4 * kPi / 6, 1e-12);
  // Three parts at one vertex: 3 corners of 120°.
  const Index c = corner_at(g, {std::sqrt(3.0) / 2, 0.5});
  const CornerCost three = corner_cost_at(g, c, std::vector<std::int32_t>{0, 1, 0, 2, 2, 2});
  EXPECT_EQ(three.separator_corners, 3u);
  EXPECT_NEAR(three.separator_sum, 3 * kPi / 6, 1e-12);
}

// Four squares around (1,1) with the centre split into P = (1-e, 1-e) and Q = (1+e, 1+e)
// by a tiny diagonal edge between the lower-right and upper-left cells.
Tessellation tiny_edge_tessellation(double e) {
  const Vec2 p(1 - e, 1 - e), q(1 + e, 1 + e);
  return polygon_tessellation({{{0, 0}, {1, 0}, p, {0, 1}},
                               {{1, 0}, {2, 0}, {2, 1}, q, p},
                               {q, {2, 1}, {2, 2}, {1, 2}},
                               {{0, 1}, p, q, {1, 2}, {0, 2}}});
}

TEST(CellGraph, ContractionMergesVerticesOfATinyEdge) {
  const double e = 1e-5;
  const std::vector<std::int32_t> labels{0, 1, 3, 2};
  const CellGraph merged = build_cell_graph(tiny_edge_tessellation(e), 1e-3);
  expect_well_formed(merged);
  // 4 boundary corners + one corner for P and Q, at their mean, with 4 spokes.
  EXPECT_EQ(merged.corner_position.size(), 5u);
  const Index c = corner_at(merged, {1, 1});
  ASSERT_NE(c, kInvalidIndex);
  EXPECT_EQ(spokes_of(merged, c).size(), 4u);
  const CornerCost a = corner_cost(merged, labels);
  EXPECT_EQ(a.separator_corners, 4u);
  EXPECT_NEAR(a.separator_sum, 0, 1e-4);  // four near-right angles
  // The arcs still carry the tiny edge (the graph itself is not contracted).
  EXPECT_EQ(merged.adjacency.size(), 2u * 5u);

  // Without contraction P and Q are corners of their own, each with two 135° sectors.
  const CellGraph raw = build_cell_graph(tiny_edge_tessellation(e), 0);
  EXPECT_EQ(raw.corner_position.size(), 6u);
  const CornerCost b = corner_cost(raw, labels);
  EXPECT_EQ(b.separator_corners, 6u);
  EXPECT_NEAR(b.separator_sum, kPi, 1e-4);
}

// Two unit squares side by side whose shared edge x = 1 is split into `pieces`
// collinear pieces (as where a Voronoi edge crosses many fine CDT edges).
Tessellation split_separator_tessellation(int pieces) {
  std::vector<Vec2> left{{0, 0}, {1, 0}}, right{{1, 0}, {2, 0}, {2, 1}, {1, 1}};
  for (int i = 1; i < pieces; ++i) left.emplace_back(1, static_cast<double>(i) / pieces);
  left.emplace_back(1, 1);
  left.emplace_back(0, 1);
  for (int i = pieces - 1; i > 0; --i) right.emplace_back(1, static_cast<double>(i) / pieces);
  return testing::polygon_tessellation({left, right});
}

TEST(CellGraph, ContractionMeasuresWholeStraightChains) {
  // 100 pieces of length 0.01 each, contraction 0.1: the chain is 1 long, so
  // nothing is contracted and the only corners are the two ends on the boundary
  // (plus the four plain boundary corners, which are not corners).
  const CellGraph graph = build_cell_graph(split_separator_tessellation(100), 0.1);
  expect_well_formed(graph);
  ASSERT_EQ(graph.corner_position.size(), 2u);
  for (Index c = 0; c < 2; ++c) {
    EXPECT_NEAR(graph.corner_position[c].x(), 1.0, 1e-12);
    EXPECT_EQ(spokes_of(graph, c).size(), 3u);  // the separator and two boundary edges
  }
  const CornerCost cost = corner_cost(graph, std::vector<std::int32_t>{0, 1});
  EXPECT_EQ(cost.separator_corners, 0u);
  EXPECT_EQ(cost.boundary_corners, 4u);
  EXPECT_NEAR(cost.boundary_sum, 0, 1e-12);  // the separator meets the boundary at 90°
}

TEST(CellGraph, ContractedClustersStaySmall) {
  // A zigzag separator of 40 edges, each 0.05 long at +-45°, between two cells:
  // contraction 0.1 may merge neighbouring zigzag vertices but no cluster may span
  // more than 0.1, so many corners remain (one cluster would leave none inside).
  const int n = 40;
  const double step = 0.05 / std::sqrt(2.0);
  std::vector<Vec2> zig;
  for (int i = 0; i <= n; ++i) zig.emplace_back((i % 2) * step, i * step);
  const double top = n * step;
  // Counter-clockwise: the left cell goes up the zigzag, the right cell down it.
  std::vector<Vec2> left_ccw{{-1, 0}};
  left_ccw.insert(left_ccw.end(), zig.begin(), zig.end());
  left_ccw.emplace_back(-1, top);
  std::vector<Vec2> right_ccw{zig.front(), {1, 0}, {1, top}};
  right_ccw.insert(right_ccw.end(), zig.rbegin(), zig.rend() - 1);
  const CellGraph graph = build_cell_graph(testing::polygon_tessellation({left_ccw, right_ccw}), 0.1);
  expect_well_formed(graph);
  std::size_t interior = 0;
  for (const Vec2& c : graph.corner_position)
    if (c.y() > 1e-9 && c.y() < top - 1e-9) ++interior;
  EXPECT_GE(interior, 8u);
  EXPECT_LE(interior, static_cast<std::size_t>(n - 1));
}

TEST(CellGraph, TriangleTessellationOfTheKey) {
  // The METIS/MADD baselines' tessellation of a real region: areas add up, the CSR is
  // well formed, and around every corner consecutive sectors belong to different
  // nodes (each spoke separates two nodes or a node from the outside).
  const Polygon2 key = make_key_region(2000);
  for (const bool madd : {false, true}) {
    const Tessellation t = triangle_tessellation(key, Frame{}, 5000, madd);
    const CellGraph g = build_cell_graph(t, 1e-5);
    expect_well_formed(g);
    EXPECT_EQ(g.node_count(), t.cell_count);  // triangles and MADD groups are never split
    double node_area = 0, face_area = 0;
    for (const double a : g.node_area) node_area += a;
    for (const double a : face_areas(t)) face_area += a;
    EXPECT_NEAR(node_area, face_area, 1e-12 * face_area);
    EXPECT_GT(g.corner_position.size(), 0u);
    for (Index c = 0; c < g.corner_position.size(); ++c) {
      const auto s = spokes_of(g, c);
      for (std::size_t k = 0; k < s.size(); ++k)
        EXPECT_NE(s[k].left_node, s[(k + s.size() - 1) % s.size()].left_node) << "corner " << c;
    }
    // Every triangle is a node, so every edge separates: mean = total / edges.
    EXPECT_GT(g.mean_arc_length, 0);
  }
}

TEST(CornerCost, TotalIsSumOfCornersAndLocalUpdatesSuffice) {
  const CellGraph g = build_cell_graph(hex_tessellation(12, 10), 1e-3);
  expect_well_formed(g);
  std::mt19937 random(7);
  std::vector<std::int32_t> labels(g.node_count());
  for (auto& l : labels) l = static_cast<std::int32_t>(random() % 3);
  const auto sum_of_corners = [&] {
    CornerCost sum;
    for (Index c = 0; c < g.corner_position.size(); ++c) sum += corner_cost_at(g, c, labels);
    return sum;
  };
  const CornerCost total = corner_cost(g, labels), sum = sum_of_corners();
  EXPECT_EQ(total.separator_corners, sum.separator_corners);
  EXPECT_EQ(total.boundary_corners, sum.boundary_corners);
  EXPECT_DOUBLE_EQ(total.separator_sum, sum.separator_sum);
  EXPECT_DOUBLE_EQ(total.boundary_sum, sum.boundary_sum);
  EXPECT_GT(total.separator_corners, 0u);

  // Relabelling node v changes the cost only at the corners listed for v.
  for (int trial = 0; trial < 50; ++trial) {
    const Index v = static_cast<Index>(random() % g.node_count());
    std::vector<CornerCost> before;
    for (Index c = 0; c < g.corner_position.size(); ++c) before.push_back(corner_cost_at(g, c, labels));
    labels[v] = (labels[v] + 1) % 3;
    const auto begin = g.node_corners.begin() + g.node_corner_offsets[v];
    const auto end = g.node_corners.begin() + g.node_corner_offsets[v + 1];
    for (Index c = 0; c < g.corner_position.size(); ++c) {
      if (std::find(begin, end, c) != end) continue;
      const CornerCost after = corner_cost_at(g, c, labels);
      EXPECT_EQ(after.separator_corners, before[c].separator_corners);
      EXPECT_EQ(after.separator_sum, before[c].separator_sum);
      EXPECT_EQ(after.boundary_corners, before[c].boundary_corners);
    }
  }
}

TEST(RepairConnectivity, DetachedPieceJoinsTheLongestSharedBoundary) {
  // Left half part 0, lower right part 1, upper right part 2; square (3,2) of part 0
  // is cut off: it shares 2 edges with part 2 and 1 with part 1.
  const CellGraph g = build_cell_graph(grid_tessellation(4, 4), 1e-3);
  auto labels = grid_labels(4, 4, [](int i, int j) { return i < 2 ? 0 : j < 2 ? 1 : 2; });
  labels[2 * 4 + 3] = 0;
  EXPECT_EQ(max_components_per_part(g, labels, 3), 2u);
  EXPECT_EQ(repair_connectivity(g, labels, 3), 1u);
  EXPECT_EQ(labels[2 * 4 + 3], 2);
  EXPECT_EQ(max_components_per_part(g, labels, 3), 1u);
  EXPECT_EQ(repair_connectivity(g, labels, 3), 0u);  // nothing left to do
}

TEST(RepairConnectivity, LargestComponentStays) {
  // Part 1 = top half (8 squares) plus squares (2,0), (3,0), cut off by part 0.
  const CellGraph g = build_cell_graph(grid_tessellation(4, 4), 1e-3);
  auto labels = grid_labels(4, 4, [](int i, int j) { return j >= 2 || (j == 0 && i >= 2) ? 1 : 0; });
  EXPECT_EQ(max_components_per_part(g, labels, 2), 2u);
  EXPECT_EQ(repair_connectivity(g, labels, 2), 2u);
  EXPECT_EQ(labels, grid_labels(4, 4, [](int, int j) { return j >= 2 ? 1 : 0; }));
}

TEST(RepairConnectivity, ManyPiecesEndConnectedAndNonEmpty) {
  // Random labels on a hexagon patch: many pieces per part, several rounds.
  const CellGraph g = build_cell_graph(hex_tessellation(20, 20), 1e-3);
  std::mt19937 random(11);
  const std::size_t parts = 5;
  std::vector<std::int32_t> labels(g.node_count());
  for (auto& l : labels) l = static_cast<std::int32_t>(random() % parts);
  EXPECT_GT(max_components_per_part(g, labels, parts), 1u);
  auto again = labels;
  const std::size_t moved = repair_connectivity(g, labels, parts);
  EXPECT_GT(moved, 0u);
  EXPECT_EQ(max_components_per_part(g, labels, parts), 1u);
  for (std::int32_t p = 0; p < static_cast<std::int32_t>(parts); ++p)
    EXPECT_NE(std::find(labels.begin(), labels.end(), p), labels.end());
  EXPECT_EQ(repair_connectivity(g, again, parts), moved);  // deterministic
  EXPECT_EQ(again, labels);
}

TEST(RepairConnectivity, EmptyPartStaysEmpty) {
  // Part 1 has no node (the caller's problem): repair neither fills nor fails on it.
  const CellGraph g = build_cell_graph(grid_tessellation(3, 1), 1e-3);
  std::vector<std::int32_t> labels{0, 2, 0};
  EXPECT_EQ(max_components_per_part(g, labels, 3), 2u);
  // Part 0's two equal pieces: the one with the smaller node stays; node 2 joins part 2.
  EXPECT_EQ(repair_connectivity(g, labels, 3), 1u);
  EXPECT_EQ(labels, (std::vector<std::int32_t>{0, 2, 2}));
  EXPECT_EQ(max_components_per_part(g, labels, 3), 1u);
}

TEST(RepairConnectivity, RejectsBadLabels) {
  const CellGraph g = build_cell_graph(grid_tessellation(2, 2), 1e-3);
  std::vector<std::int32_t> labels{0, 1, 2, 0};
  EXPECT_THROW(repair_connectivity(g, labels, 2), Error);
  EXPECT_THROW(max_components_per_part(g, std::vector<std::int32_t>{0, 1}, 2), Error);
}

}  // namespace
}  // namespace structmesh::partition2d
