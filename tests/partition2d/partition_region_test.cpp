// partition_region end to end: the parts tile the region, each is one valid piece,
// exactly k of them, deterministic and independent of the thread count, for every
// method; analytic values on the unit square.
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/partition2d.hpp"
#include "structmesh/regions.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace structmesh {
namespace {

std::filesystem::path data_root() {
  const char* env = std::getenv("STRUCTMESH_DATA");
  return env != nullptr ? std::filesystem::path(env) : std::filesystem::path(STRUCTMESH_DATA_DEFAULT);
}

Polygon2 unit_square() {
  Polygon2 square;
  const std::vector<Vec2> ring{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  square.add_ring(ring);
  return square;
}

// The properties every partition must have, whatever the method.
void expect_valid_partition(const Polygon2& region, const Partition& partition, std::size_t k) {
  ASSERT_EQ(partition.parts.size(), k);
  ASSERT_EQ(partition.part_areas.size(), k);
  EXPECT_EQ(partition.metrics.parts, k);
  double sum = 0;
  for (std::size_t p = 0; p < k; ++p) {
    EXPECT_GT(partition.part_areas[p], 0) << "part " << p << " is empty";
    sum += partition.part_areas[p];
    const RegionReport report = check_region({partition.parts[p]});
    EXPECT_TRUE(report.valid) << "part " << p << ": "
                              << (report.problems.empty() ? "" : report.problems.front().message);
    EXPECT_NEAR(std::abs(area(partition.parts[p])), partition.part_areas[p], 1e-9 * partition.part_areas[p]);
  }
  // Tiling: the parts' areas add up to the region's (no gap, no overlap: every
  // tessellation face is in exactly one part and parts are built from the faces).
  EXPECT_NEAR(sum / std::abs(area(region)), 1.0, 1e-9);
  EXPECT_LT(partition.metrics.area_error, 1e-9);
  EXPECT_EQ(partition.metrics.max_components_per_part, 1u);
  EXPECT_GE(partition.metrics.workload_ratio, 1.0);
  // Separators reference shared vertices: each separator curve has parts on both sides.
  for (const PartitionCurve& curve : partition.curves) {
    if (curve.kind == PartitionCurve::Kind::Separator) {
      EXPECT_GE(curve.left_part, 0);
      EXPECT_GE(curve.right_part, 0);
      EXPECT_NE(curve.left_part, curve.right_part);
    }
  }
}

TEST(PartitionRegion, UnitSquareIntoQuadrants) {
  PartitionOptions options;
  options.parts = 4;
  options.cells = 64;
  options.exact_cells = true;
  const Partition partition = partition_region(unit_square(), options);
  expect_valid_partition(unit_square(), partition, 4);
  // The L8-CVT of 64 sites in a square is the 8x8 grid; four equal quadrants are
  // the best bisections: perfectly balanced, straight separators.
  EXPECT_LT(partition.metrics.workload_ratio, 1.001);
  EXPECT_LT(partition.metrics.angle_deviation, 1e-3);
  EXPECT_NEAR(partition.metrics.separator_length, 2.0, 1e-3);
  EXPECT_NEAR(partition.metrics.compactness_normalized, 1.0, 1e-3);
}

TEST(PartitionRegion, KeyAndPipeAllMethods) {
  for (const auto& region : {make_key_region(2000), make_pipe_region(4000)}) {
    for (const PartitionMethod method :
         {PartitionMethod::CvtGp, PartitionMethod::Cvt, PartitionMethod::Metis, PartitionMethod::Madd}) {
      PartitionOptions options;
      options.parts = 16;
      options.cells = 1000;
      options.method = method;
      SCOPED_TRACE(method_name(method));
      const Partition partition = partition_region(region, options);
      expect_valid_partition(region, partition, 16);
      if (method != PartitionMethod::Cvt) {
        EXPECT_LT(partition.metrics.workload_ratio, 1.2) << method_name(method);
      }
    }
  }
}

TEST(PartitionRegion, CvtGpMeetsTheBalanceTolerance) {
  PartitionOptions options;
  options.parts = 32;
  const Polygon2 key = make_key_region(4000);
  const Partition partition = partition_region(key, options);
  expect_valid_partition(key, partition, 32);
  EXPECT_LE(partition.metrics.workload_ratio, 1.0 + options.imbalance + 1e-9);
}

TEST(PartitionRegion, DeterministicAndThreadIndependent) {
  PartitionOptions options;
  options.parts = 8;
  options.cells = 800;
  const Polygon2 pipe = make_pipe_region(4000);
  const Partition a = partition_region(pipe, options);
  const Partition b = partition_region(pipe, options);
  Partition one_thread;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one_thread = partition_region(pipe, options);
  }
  for (const Partition* other : std::initializer_list<const Partition*>{&b, &one_thread}) {
    ASSERT_EQ(a.vertices.size(), other->vertices.size());
    EXPECT_TRUE(a.vertices == other->vertices);
    EXPECT_TRUE(a.part_areas == other->part_areas);
    EXPECT_TRUE(a.sites == other->sites);
  }
  options.seed = 7;
  const Partition c = partition_region(pipe, options);
  expect_valid_partition(pipe, c, 8);
  EXPECT_FALSE(a.sites == c.sites);
}

TEST(PartitionRegion, InputVerticesAreKeptBitIdentical) {
  const Polygon2 key = make_key_region(2000);
  PartitionOptions options;
  options.parts = 8;
  options.cells = 600;
  const Partition partition = partition_region(key, options);
  std::size_t input = 0;
  for (std::size_t v = 0; v < partition.vertices.size(); ++v) {
    if (partition.input_vertex[v] < 0) continue;
    ++input;
    EXPECT_TRUE(partition.vertices[v] == key.points[static_cast<std::size_t>(partition.input_vertex[v])]);
  }
  EXPECT_EQ(input, key.points.size());
}

TEST(PartitionRegion, LonLatGulfIsProjectedAndConnected) {
  const auto path = data_root() / "regions" / "gulf_of_mexico.geojson";
  if (!std::filesystem::exists(path)) GTEST_FAIL() << "missing test data " << path;
  const Polygon2 gulf = read_region(path).front();
  PartitionOptions options;
  options.parts = 64;
  options.cells = 2000;
  const Partition partition = partition_region(gulf, options);
  EXPECT_NE(partition.projection.find("LAEA"), std::string::npos);
  ASSERT_EQ(partition.parts.size(), 64u);
  EXPECT_EQ(partition.metrics.max_components_per_part, 1u);
  EXPECT_LT(partition.metrics.area_error, 1e-9);
  // Parts are written back in lon/lat.
  const BoundingBox2 box = gulf.bounding_box();
  for (const Polygon2& part : partition.parts) {
    EXPECT_EQ(part.coordinates, Polygon2::Coordinates::LonLat);
    const BoundingBox2 b = part.bounding_box();
    EXPECT_GE(b.min.x(), box.min.x() - 1e-9);
    EXPECT_LE(b.max.y(), box.max.y() + 1e-9);
  }
}

TEST(PartitionRegion, BadInputAndOptions) {
  PartitionOptions options;
  options.parts = 0;
  EXPECT_THROW(partition_region(unit_square(), options), InputError);
  options.parts = 2;
  options.p = 7;
  EXPECT_THROW(partition_region(unit_square(), options), InputError);
  options.p = 8;
  Polygon2 bowtie;
  const std::vector<Vec2> ring{{0, 0}, {2, 2}, {2, 0}, {0, 2}};
  bowtie.add_ring(ring);
  EXPECT_THROW(partition_region(bowtie, options), InputError);
  options.parts = 50;
  options.cells = 40;
  options.exact_cells = true;
  EXPECT_THROW(partition_region(unit_square(), options), InputError);  // too few cells for k
  options.parts = 2;
  options.cells = 1000;  // 2.5 times the MILP's limit; 4000 cost 30 s of CVT under ASan
  options.method = PartitionMethod::Exact;
  EXPECT_THROW(partition_region(unit_square(), options), InputError);  // graph too big for the MILP
  // One part: the region itself.
  PartitionOptions one;
  one.parts = 1;
  one.cells = 100;
  const Partition single = partition_region(make_key_region(500), one);
  expect_valid_partition(make_key_region(500), single, 1);
  EXPECT_NEAR(single.metrics.workload_ratio, 1.0, 1e-12);
}

}  // namespace
}  // namespace structmesh
