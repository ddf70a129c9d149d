// mesh_region_quads() end to end on coastlines: the narrow-water filter runs before
// partitioning, and the mesh is all-quad, valid, conforming and covers the filtered
// region; the real Gulf of Mexico coast (../shared/data) meshes without an inverted quad.
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/regions.hpp"
#include "test_data.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

namespace structmesh {
namespace {

using test::data_dir;

// All quads counter-clockwise with positive scaled Jacobian, every edge in one or two
// quads; returns the number of boundary edges.
std::size_t expect_valid_conforming(const Quad2dResult& result) {
  const QuadMesh& mesh = result.merged.mesh;
  EXPECT_EQ(result.report.inverted, 0u);
  for (const double sj : result.scaled_jacobian) EXPECT_GT(sj, 0);
  std::map<std::pair<Index, Index>, int> edges;
  for (const auto& q : mesh.quads)
    for (int j = 0; j < 4; ++j) {
      const Index a = q[j], b = q[(j + 1) % 4];
      EXPECT_NE(a, b);
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  std::size_t boundary = 0;
  for (const auto& [edge, count] : edges) {
    EXPECT_LE(count, 2) << "edge " << edge.first << "-" << edge.second << " in more than two quads";
    if (count == 1) ++boundary;
  }
  return boundary;
}

// The longest region boundary edge of the mesh, in element sizes.
double longest_boundary_edge(const Quad2dResult& result) {
  const QuadMesh& mesh = result.merged.mesh;
  std::map<std::pair<Index, Index>, int> edges;
  for (const auto& q : mesh.quads)
    for (int j = 0; j < 4; ++j) ++edges[{std::min(q[j], q[(j + 1) % 4]), std::max(q[j], q[(j + 1) % 4])}];
  double longest = 0;
  for (const auto& [edge, count] : edges)
    if (count == 1) longest = std::max(longest, (mesh.points[edge.first] - mesh.points[edge.second]).norm());
  return longest / result.merged.size;
}

TEST(MeshRegionQuads, ACreekNarrowerThanAnElementIsClosedAndTheRestMeshed) {
  // A 10 x 10 basin with a dead-end creek 0.1 wide and 3 deep, meshed at size 0.5:
  // the creek is closed before partitioning and the basin is meshed whole.
  std::vector<Vec2> ring{{0, 0}, {10, 0}, {10, 10}, {5.05, 10}};
  for (double y = 10.25; y < 13; y += 0.25) ring.emplace_back(5.05, y);
  ring.insert(ring.end(), {{5.05, 13}, {4.95, 13}});
  for (double y = 12.75; y > 10; y -= 0.25) ring.emplace_back(4.95, y);
  ring.insert(ring.end(), {{4.95, 10}, {0, 10}});
  Polygon2 region;
  region.add_ring(ring);
  Quad2dOptions options;
  options.size = 0.5;
  options.partition.parts = 2;
  const Quad2dResult result = mesh_region_quads(region, options);
  expect_valid_conforming(result);
  EXPECT_TRUE(result.report.coastline_filter.changed);
  EXPECT_NEAR(result.report.region_area, 100.0, 1e-9);
  EXPECT_NEAR(result.report.mesh_area, 100.0, 1e-9);

  // Without the filter the creek stays in the region.
  options.min_channel = 0;
  options.min_island = 0;
  try {
    const Quad2dResult kept = mesh_region_quads(region, options);
    EXPECT_FALSE(kept.report.coastline_filter.changed);
    EXPECT_NEAR(kept.report.region_area, 100.3, 1e-9);
  } catch (const Error&) {
    // Paving a creek a fifth of an element wide may fail; it must say so, not crash.
  }
}

TEST(MeshRegionQuads, KeyPartsWithoutAPlannedLayoutGetPolarBlocksBeforePaving) {
  // The Key in 32 parts at its mean boundary segment: some parts have no layout from the
  // interval assignment or fail its quality check, and polar layouts chosen for their
  // sampled counts take over where they reach 0.6 (and a mean of 0.96).
  const Polygon2 region = make_key_region(2000);
  Quad2dOptions options;
  options.partition.parts = 32;
  const Quad2dResult result = mesh_region_quads(region, options);
  expect_valid_conforming(result);
  const PavingStats& stats = result.report.paving;
  EXPECT_GT(stats.unplanned_blocks, 0u);
  EXPECT_LE(stats.unplanned_blocks, stats.polar);
  EXPECT_LE(stats.mapped + stats.polar, 32u);
  // Every kept block reaches 0.6, and paved parts do too on the Key.
  EXPECT_GE(result.report.scaled_jacobian_min, 0.6);
  EXPECT_NEAR(result.report.mesh_area, result.report.region_area, 1e-5 * result.report.region_area);
}

TEST(MeshRegionQuads, DefaultPartCountGrowsWithTheQuadsAndTheRanks) {
  EXPECT_EQ(default_part_count(19999, 1), 1u);      // small meshes stay whole
  EXPECT_EQ(default_part_count(20000, 1), 8u);      // at least 8 for the threads
  EXPECT_EQ(default_part_count(2000000, 1), 8u);    // 4 by size
  EXPECT_EQ(default_part_count(20000000, 1), 40u);  // one per 500k quads
  EXPECT_EQ(default_part_count(20000001, 1), 41u);
  EXPECT_EQ(default_part_count(2000000, 16), 32u);  // two per MPI rank
}

TEST(MeshRegionQuads, RejectsNegativeFilterSettings) {
  Polygon2 square;
  square.add_ring(std::vector<Vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  Quad2dOptions options;
  options.size = 0.1;
  options.min_channel = -1;
  EXPECT_THROW(mesh_region_quads(square, options), InputError);
}

struct CoastCase {
  const char* file;
  std::size_t quads, parts;
};

class RealCoastline : public ::testing::TestWithParam<CoastCase> {};

TEST_P(RealCoastline, MeshesWithoutAnInvertedQuad) {
  const std::filesystem::path path = data_dir() / "regions" / GetParam().file;
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found (set STRUCTMESH_DATA)";
  const Polygon2 region = read_region(path.string()).front();
  Quad2dOptions options;
  options.target_quads = GetParam().quads;
  options.partition.parts = GetParam().parts;
  const Quad2dResult result = mesh_region_quads(region, options);
  const std::size_t boundary_edges = expect_valid_conforming(result);
  EXPECT_GT(boundary_edges, 0u);
  // Coast stretches that follow their input vertices split long input edges (the
  // Gulf's straight box sides were single edges of up to 30 element sizes).
  EXPECT_LT(longest_boundary_edge(result), 3.0);
  EXPECT_GT(result.report.quads, GetParam().quads * 8 / 10);
  // Parts of 40k quads (twice PavingOptions::grid_interior_quads) get a grid inside.
  if (GetParam().quads / GetParam().parts >= 40000) {
    EXPECT_GT(result.report.paving.grid_interior_quads, 0u);
  }
  // The mesh covers the filtered region: its boundary samples are chords of the
  // coast, so the areas agree to a small fraction.
  EXPECT_NEAR(result.report.mesh_area, result.report.region_area, 2e-3 * result.report.region_area);
  EXPECT_LE(result.report.region_area, result.report.coastline_filter.area_before * (1 + 1e-9));
}

INSTANTIATE_TEST_SUITE_P(Regions, RealCoastline,
                         ::testing::Values(CoastCase{"gulf_of_mexico.geojson", 100000, 8},
                                           // 50k quads per part: grid interiors.
                                           CoastCase{"gulf_of_mexico.geojson", 100000, 2},
                                           // 16 parts: one part paves with a folded zone
                                           // that untangle_quads() repairs.
                                           CoastCase{"gulf_of_mexico.geojson", 100000, 16},
                                           CoastCase{"gulf_of_mexico_ne10m.geojson", 100000, 16},
                                           CoastCase{"matagorda_bay.geojson", 30000, 8},
                                           CoastCase{"west_bay_galveston.geojson", 20000, 8}),
                         [](const auto& info) {
                           std::string name = info.param.file;
                           name = name.substr(0, name.find('.'));
                           return name + "_" + std::to_string(info.param.parts) + "_parts";
                         });

}  // namespace
}  // namespace structmesh
