// The exact bisection MILP (design/partition2d.md §2.8) on graphs small enough to
// know the optimum by hand, its lazy connectivity cuts (3.9)/(3.10), and CVT-GP's
// first bisection against it.
#include "partition2d/graph_fixtures.hpp"
#include "partition2d/graph_partition_detail.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace structmesh::partition2d {
namespace {

using testing::grid_graph;
using testing::grid_tessellation;
using testing::GridSquare;
using testing::hex_tessellation;

// An nx x ny grid whose interior vertices are moved by up to 0.2 in x and y
// (a fixed hash, no RNG): quads with angles off 90 degrees, so D_theta matters.
CellGraph jittered_grid(int nx, int ny) {
  const auto vertex = [&](int i, int j) {
    Vec2 p(i, j);
    if (i > 0 && i < nx && j > 0 && j < ny) {
      const double a = std::sin(i * 12.9898 + j * 78.233) * 43758.5453,
                   b = std::sin(i * 39.346 + j * 11.135) * 24634.6345;
      p += 0.4 * Vec2(a - std::floor(a) - 0.5, b - std::floor(b) - 0.5);
    }
    return p;
  };
  std::vector<std::vector<Vec2>> faces;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      faces.push_back({vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
  return build_cell_graph(testing::polygon_tessellation(faces), 1e-3);
}

struct Solved {
  std::vector<std::int32_t> labels;
  detail::ExactBisectionResult result;
};

Solved solve_first_bisection(const CellGraph& graph, const GraphPartitionOptions& options, double seconds = 60) {
  Solved s;
  s.labels = detail::gp_first_bisection(graph, options);
  s.result = detail::exact_bisection(graph, s.labels, detail::first_bisection_problem(graph, options), seconds);
  return s;
}

GraphPartitionOptions two_parts() {
  GraphPartitionOptions o;
  o.parts = 2;
  return o;
}

TEST(ExactBisection, SixBySixGridIsCutStraight) {
  // 36 unit squares, 18 per side (the band is narrower than one cell): the straight
  // cut has L_S = 6 and every corner at 90 or 180 degrees, so J = 6. Any other
  // balanced cut crosses more unit edges.
  const CellGraph graph = grid_graph(6, 6);
  const Solved s = solve_first_bisection(graph, two_parts());
  EXPECT_TRUE(s.result.proven);
  EXPECT_NEAR(s.result.objective, 6.0, 1e-6);
  EXPECT_NEAR(s.result.bound, 6.0, 1e-6);
  EXPECT_EQ(s.result.connectivity_cuts, 0u);
  EXPECT_NEAR(detail::separator_length(graph, s.labels), 6.0, 1e-9);
  // The cut is a straight line: one half is columns 0-2 or rows 0-2.
  const bool columns = s.labels[0] == s.labels[2] && s.labels[0] != s.labels[3];
  const bool rows = s.labels[0] == s.labels[12] && s.labels[0] != s.labels[18];
  EXPECT_TRUE(columns || rows);
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) {
      const bool low = columns ? i < 3 : j < 3;
      EXPECT_EQ(s.labels[static_cast<std::size_t>(j * 6 + i)] == s.labels[0], low);
    }
}

TEST(ExactBisection, ConnectivityCutsFireOnAU) {
  // A U: a 4 x 3 base with two 1-wide arms of length 10 on columns 0 and 3
  // (32 cells, 16 per side). Without (3.9)/(3.10) the optimum takes the top 8 cells
  // of both arms (L_S = 2, side disconnected); the connected optimum cuts the base
  // vertically (L_S = 3, every corner 90 or 180 degrees).
  std::vector<GridSquare> missing;
  for (int j = 3; j < 13; ++j) {
    missing.push_back({1, j});
    missing.push_back({2, j});
  }
  const CellGraph graph = build_cell_graph(grid_tessellation(4, 13, missing), 1e-3);
  ASSERT_EQ(graph.node_count(), 32u);
  const Solved s = solve_first_bisection(graph, two_parts());
  EXPECT_GT(s.result.connectivity_cuts, 0u);
  EXPECT_TRUE(s.result.proven);
  EXPECT_NEAR(s.result.objective, 3.0, 1e-6);
  EXPECT_NEAR(detail::separator_length(graph, s.labels), 3.0, 1e-9);
  EXPECT_EQ(max_components_per_part(graph, s.labels, 2), 1u);
}

TEST(ExactBisection, CvtGpFirstBisectionWithin15PercentOfExact) {
  std::vector<GridSquare> hole;
  for (int i = 3; i < 6; ++i)
    for (int j = 4; j < 6; ++j) hole.push_back({i, j});
  struct Case {
    const char* name;
    CellGraph graph;
    std::size_t parts;
  };
  std::vector<Case> cases;
  cases.push_back({"8x8 grid", grid_graph(8, 8), 2});
  cases.push_back({"10x6 grid", grid_graph(10, 6), 2});
  cases.push_back({"10x6 grid, 3 parts", grid_graph(10, 6), 3});
  cases.push_back({"9x9 grid with a hole", build_cell_graph(grid_tessellation(9, 9, hole), 1e-3), 2});
  cases.push_back({"7x6 hexagons", build_cell_graph(hex_tessellation(7, 6), 1e-3), 2});
  cases.push_back({"8x8 jittered grid", jittered_grid(8, 8), 2});
  cases.push_back({"10x6 jittered, 3 parts", jittered_grid(10, 6), 3});
  // Pairs of squares merged into 2x1 and 1x2 cells: unequal nodes and T-junctions.
  cases.push_back(
      {"10x8 merged squares",
       build_cell_graph(grid_tessellation(10, 8, {}, [](int i, int j) { return static_cast<Index>((i / 2) * 8 + j); }),
                        1e-3),
       2});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    GraphPartitionOptions o = two_parts();
    o.parts = c.parts;
    const double lambda = o.angle_weight * c.graph.mean_arc_length;
    const std::vector<std::int32_t> gp = detail::gp_first_bisection(c.graph, o);
    const double gp_value = detail::objective(c.graph, gp, lambda, true);
    const Solved s = solve_first_bisection(c.graph, o);
    const double exact_value = detail::objective(c.graph, s.labels, lambda, true);
    EXPECT_NEAR(exact_value, s.result.objective, 1e-6);
    EXPECT_LE(s.result.objective, gp_value + 1e-6);
    EXPECT_LE(gp_value, 1.15 * (s.result.proven ? s.result.objective : s.result.bound) + 1e-9);
    EXPECT_EQ(max_components_per_part(c.graph, s.labels, 2), 1u);
    std::printf("%-22s CVT-GP J = %.4f, exact J = %.4f (bound %.4f, %s, %zu cuts)\n", c.name, gp_value,
                s.result.objective, s.result.bound, s.result.proven ? "proven" : "not proven",
                s.result.connectivity_cuts);
  }
}

}  // namespace
}  // namespace structmesh::partition2d

namespace structmesh::partition2d {
namespace {

TEST(ExactBisection, OutOfTimeKeepsTheCvtGpBisection) {
  // No time at all: CBC never runs, the engine keeps CVT-GP's bisections, says the
  // result is not proven, and the parts are still valid.
  const CellGraph graph = testing::grid_graph(8, 8);
  GraphPartitionOptions o;
  o.engine = GraphPartitionOptions::Engine::Exact;
  o.parts = 4;
  o.exact_time_limit = 0;
  GraphPartitionReport report;
  const std::vector<std::int32_t> labels = partition_cell_graph(graph, o, &report);
  EXPECT_FALSE(report.exact_proven);
  EXPECT_EQ(max_components_per_part(graph, labels, 4), 1u);
  EXPECT_NEAR(detail::separator_length(graph, labels), 16.0, 1e-9);  // quadrants
}

}  // namespace
}  // namespace structmesh::partition2d
