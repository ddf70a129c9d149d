// partition_cell_graph (design/partition2d.md §2.7): every engine gives exactly k
// non-empty connected parts; CVT-GP's balance band, straight cuts on grids,
// determinism, the error paths, k = 1 and disconnected graphs.
#include "partition2d/graph_fixtures.hpp"
#include "partition2d/graph_partition_detail.hpp"
#include "structmesh/error.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <vector>

namespace structmesh::partition2d {
namespace {

using Engine = GraphPartitionOptions::Engine;
using testing::grid_graph;
using testing::grid_tessellation;
using testing::GridSquare;
using testing::hex_tessellation;

GraphPartitionOptions options_for(Engine engine, std::size_t parts) {
  GraphPartitionOptions o;
  o.engine = engine;
  o.parts = parts;
  return o;
}

std::vector<double> part_areas(const CellGraph& graph, const std::vector<std::int32_t>& labels, std::size_t k) {
  std::vector<double> area(k, 0.0);
  for (std::size_t v = 0; v < labels.size(); ++v) area[static_cast<std::size_t>(labels[v])] += graph.node_area[v];
  return area;
}

// Exactly k parts, each non-empty and one component.
void expect_valid(const CellGraph& graph, const std::vector<std::int32_t>& labels, std::size_t k) {
  ASSERT_EQ(labels.size(), graph.node_count());
  std::vector<std::size_t> count(k, 0);
  for (std::int32_t l : labels) {
    ASSERT_GE(l, 0);
    ASSERT_LT(static_cast<std::size_t>(l), k);
    ++count[static_cast<std::size_t>(l)];
  }
  for (std::size_t p = 0; p < k; ++p) EXPECT_GT(count[p], 0u) << "part " << p;
  EXPECT_EQ(max_components_per_part(graph, labels, k), 1u);
}

// Corners where one part occupies two separate sectors (a vertex-only self-contact,
// which makes a self-touching part ring; design §2.7 "no pinch").
std::size_t pinches(const CellGraph& graph, const std::vector<std::int32_t>& labels) {
  std::size_t count = 0;
  std::vector<int> runs;
  for (Index c = 0; c + 1 < graph.corner_offsets.size(); ++c) {
    const Index begin = graph.corner_offsets[c], end = graph.corner_offsets[c + 1];
    const auto label = [&](Index s) {
      const Index node = graph.spokes[s].left_node;
      return node == kInvalidIndex ? -1 : labels[node];
    };
    runs.clear();
    for (Index s = begin; s < end; ++s)
      if (label(s) >= 0 && label(s) != label(s == begin ? end - 1 : s - 1)) runs.push_back(label(s));
    std::sort(runs.begin(), runs.end());
    if (std::adjacent_find(runs.begin(), runs.end()) != runs.end()) ++count;
  }
  return count;
}

// A 12 x 12 grid with a 4 x 3 hole and a notch, a hexagon patch, a plain grid.
std::vector<CellGraph> sample_graphs() {
  std::vector<GridSquare> missing;
  for (int i = 4; i < 8; ++i)
    for (int j = 5; j < 8; ++j) missing.push_back({i, j});
  missing.push_back({0, 0});
  missing.push_back({1, 0});
  std::vector<CellGraph> graphs;
  graphs.push_back(build_cell_graph(grid_tessellation(12, 12, missing), 1e-3));
  graphs.push_back(build_cell_graph(hex_tessellation(10, 9), 1e-3));
  graphs.push_back(grid_graph(16, 10));
  return graphs;
}

TEST(GraphPartition, EveryEngineGivesKConnectedParts) {
  for (const CellGraph& graph : sample_graphs()) {
    for (Engine engine : {Engine::RecursiveGp, Engine::MetisKway, Engine::MetisRecursive}) {
      for (std::size_t k : {2u, 3u, 4u, 7u, 16u}) {
        SCOPED_TRACE(::testing::Message()
                     << "engine " << static_cast<int>(engine) << " k " << k << " nodes " << graph.node_count());
        GraphPartitionReport report;
        const std::vector<std::int32_t> labels = partition_cell_graph(graph, options_for(engine, k), &report);
        expect_valid(graph, labels, k);
        if (engine == Engine::RecursiveGp) {
          EXPECT_EQ(pinches(graph, labels), 0u);
        }
      }
    }
  }
}

TEST(GraphPartition, OptionVariantsStayValid) {
  // No angle term, no boundary corners, no refinement, a loose band, another seed.
  const CellGraph graph = build_cell_graph(hex_tessellation(20, 18), 1e-3);
  for (int variant = 0; variant < 5; ++variant) {
    GraphPartitionOptions o = options_for(Engine::RecursiveGp, 6);
    if (variant == 0) o.angle_weight = 0;
    if (variant == 1) o.boundary_corners = false;
    if (variant == 2) o.refinement_passes = 0;
    if (variant == 3) o.imbalance = 0.3;
    if (variant == 4) o.seed = 12345;
    SCOPED_TRACE(::testing::Message() << "variant " << variant);
    GraphPartitionReport report;
    expect_valid(graph, partition_cell_graph(graph, o, &report), 6);
    if (variant != 2) {
      EXPECT_TRUE(report.balanced);
    }
  }
}

TEST(GraphPartition, ExactEngineGivesKConnectedParts) {
  const CellGraph graph = grid_graph(6, 6);
  for (std::size_t k : {2u, 3u, 4u}) {
    SCOPED_TRACE(::testing::Message() << "k " << k);
    GraphPartitionOptions o = options_for(Engine::Exact, k);
    o.exact_time_limit = 60;
    GraphPartitionReport report;
    const std::vector<std::int32_t> labels = partition_cell_graph(graph, o, &report);
    expect_valid(graph, labels, k);
    EXPECT_TRUE(report.exact_proven);
    EXPECT_NEAR(report.exact_gap, 0.0, 1e-6);
  }
}

TEST(GraphPartition, RecursiveGpBalanceOnA32x32Grid) {
  const CellGraph graph = grid_graph(32, 32);
  for (std::size_t k : {2u, 3u, 4u, 5u, 8u, 16u}) {
    SCOPED_TRACE(::testing::Message() << "k " << k);
    GraphPartitionOptions o = options_for(Engine::RecursiveGp, k);
    GraphPartitionReport report;
    const std::vector<std::int32_t> labels = partition_cell_graph(graph, o, &report);
    expect_valid(graph, labels, k);
    const std::vector<double> area = part_areas(graph, labels, k);
    const double ratio = *std::max_element(area.begin(), area.end()) / *std::min_element(area.begin(), area.end());
    EXPECT_LE(ratio, 1 + o.imbalance);
    EXPECT_TRUE(report.balanced);
  }
}

TEST(GraphPartition, RecursiveGpCutsAGridStraight) {
  // Four 16 x 16 quadrants: L_S = 2 * 32, the shortest balanced 4-way cut; every
  // corner of a grid is a multiple of 90 degrees, so D_theta = 0.
  const CellGraph graph = grid_graph(32, 32);
  const std::vector<std::int32_t> gp = partition_cell_graph(graph, options_for(Engine::RecursiveGp, 4));
  const std::vector<std::int32_t> metis = partition_cell_graph(graph, options_for(Engine::MetisKway, 4));
  const double gp_length = detail::separator_length(graph, gp);
  EXPECT_LE(gp_length, detail::separator_length(graph, metis) + 1e-9);
  EXPECT_NEAR(gp_length, 64.0, 1e-9);
  EXPECT_NEAR(detail::angle_cost(graph, gp, true), 0.0, 1e-12);
}

TEST(GraphPartition, RefinementLowersJBelowMetisOnHexagons) {
  // Hexagon patches: separators must zig-zag, every bend costs delta; the refined
  // partition is at least as good in J as METIS's on the same graph.
  const CellGraph graph = build_cell_graph(hex_tessellation(24, 20), 1e-3);
  for (std::size_t k : {2u, 4u, 8u}) {
    SCOPED_TRACE(::testing::Message() << "k " << k);
    const GraphPartitionOptions o = options_for(Engine::RecursiveGp, k);
    const double lambda = o.angle_weight * graph.mean_arc_length;
    const double gp = detail::objective(graph, partition_cell_graph(graph, o), lambda, true);
    const double metis =
        detail::objective(graph, partition_cell_graph(graph, options_for(Engine::MetisRecursive, k)), lambda, true);
    EXPECT_LE(gp, metis * 1.0001);
  }
}

TEST(GraphPartition, DeterministicAndIndependentOfThreads) {
  const CellGraph graph = build_cell_graph(hex_tessellation(30, 30), 1e-3);
  for (Engine engine : {Engine::RecursiveGp, Engine::MetisKway, Engine::MetisRecursive}) {
    const GraphPartitionOptions o = options_for(engine, 12);
    std::vector<std::int32_t> one, two;
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
      one = partition_cell_graph(graph, o);
    }
    {
      tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
      two = partition_cell_graph(graph, o);
    }
    EXPECT_EQ(one, two);
    EXPECT_EQ(one, partition_cell_graph(graph, o));
  }
}

TEST(GraphPartition, TooFewNodesIsAnInputError) {
  const CellGraph graph = grid_graph(4, 4);  // 16 nodes: at most 8 parts
  EXPECT_THROW(partition_cell_graph(graph, options_for(Engine::RecursiveGp, 9)), InputError);
  EXPECT_THROW(partition_cell_graph(graph, options_for(Engine::MetisKway, 9)), InputError);
  EXPECT_THROW(partition_cell_graph(graph, options_for(Engine::RecursiveGp, 0)), InputError);
  expect_valid(graph, partition_cell_graph(graph, options_for(Engine::RecursiveGp, 8)), 8);
}

TEST(GraphPartition, OnePartIsAllZeros) {
  // METIS is never called with one part (it would crash or hang, METIS#86).
  const CellGraph graph = grid_graph(5, 3);
  for (Engine engine : {Engine::RecursiveGp, Engine::MetisKway, Engine::MetisRecursive, Engine::Exact}) {
    GraphPartitionReport report;
    const std::vector<std::int32_t> labels = partition_cell_graph(graph, options_for(engine, 1), &report);
    EXPECT_EQ(labels, std::vector<std::int32_t>(15, 0));
    EXPECT_TRUE(report.balanced);
  }
}

TEST(GraphPartition, TwoIslands) {
  // Column 5 missing: two 5 x 8 islands. CONTIG would make METIS fail on this graph.
  std::vector<GridSquare> missing;
  for (int j = 0; j < 8; ++j) missing.push_back({5, j});
  const CellGraph graph = build_cell_graph(grid_tessellation(11, 8, missing), 1e-3);
  ASSERT_EQ(graph.node_count(), 80u);
  for (Engine engine : {Engine::MetisKway, Engine::MetisRecursive, Engine::RecursiveGp}) {
    for (std::size_t k : {2u, 4u, 6u}) {
      SCOPED_TRACE(::testing::Message() << "engine " << static_cast<int>(engine) << " k " << k);
      GraphPartitionReport report;
      expect_valid(graph, partition_cell_graph(graph, options_for(engine, k), &report), k);
    }
  }
}

TEST(GraphPartition, LargeGraphIntoManyParts) {
  // The size class of the benchmark (about 25k nodes, 1024 parts), checked for
  // validity only; nothing here is timed.
  const CellGraph graph = build_cell_graph(hex_tessellation(160, 154), 1e-3);
  GraphPartitionReport report;
  const std::vector<std::int32_t> labels = partition_cell_graph(graph, options_for(Engine::RecursiveGp, 1024), &report);
  expect_valid(graph, labels, 1024);
  const std::vector<double> area = part_areas(graph, labels, 1024);
  const double ratio = *std::max_element(area.begin(), area.end()) / *std::min_element(area.begin(), area.end());
  EXPECT_LE(ratio, 1.25);
}

}  // namespace
}  // namespace structmesh::partition2d
