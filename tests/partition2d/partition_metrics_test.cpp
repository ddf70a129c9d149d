// measure_partition_geometry (design/partition2d.md §1.2-§1.4) on hand-built
// partitions with hand-computed values: R_W, L_S, R^_C (both), area error, pieces,
// and the junction angle deviation by the chord rule.
#include "partition2d/part_geometry_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace structmesh::partition2d {
namespace {

using testing::build;
using testing::Face;
using testing::grid_faces;
using testing::make_tessellation;
using testing::unit_square;

constexpr double kPi = std::numbers::pi;

TEST(PartitionMetrics, QuadrantsOfTheUnitSquare) {
  const Polygon2 region = unit_square();
  Partition partition =
      build(make_tessellation(grid_faces(4, 4, {0, 0}, 0.25), region), testing::quadrant_labels(), 4, region);
  measure_partition_geometry(partition, 1.0, 0.1);
  const PartitionMetrics& m = partition.metrics;
  EXPECT_EQ(m.parts, 4u);
  EXPECT_DOUBLE_EQ(m.workload_ratio, 1.0);
  EXPECT_DOUBLE_EQ(m.separator_length, 2.0);
  EXPECT_DOUBLE_EQ(m.compactness, 0.5);
  EXPECT_DOUBLE_EQ(m.compactness_normalized, 1.0);  // 2 (1 - 1/sqrt(k)) at k = 4
  EXPECT_DOUBLE_EQ(m.region_area, 1.0);
  EXPECT_LT(m.area_error, 1e-15);
  EXPECT_EQ(m.max_components_per_part, 1u);
  // The centre: 4 corners; each side midpoint: 2 (the outside sector skipped).
  EXPECT_EQ(m.junction_corners, 4u + 4u * 2u);
  EXPECT_NEAR(m.junction_angle_deviation, 0.0, 1e-15);
}

TEST(PartitionMetrics, DiagonalSeparatorGivesFortyFiveDegreeCorners) {
  // Unit square as four squares, the lower right one cut along its diagonal from
  // (0.5,0.5) to (1,0). Part 0: the upper half; part 2: the triangle (1,0), (1,0.5),
  // (0.5,0.5); part 1: the rest.
  const Polygon2 region = unit_square();
  std::vector<Face> faces = grid_faces(2, 2, {0, 0}, 0.5);
  faces.erase(faces.begin() + 1);  // the lower right square
  faces.push_back({{0.5, 0}, {1, 0}, {0.5, 0.5}});
  faces.push_back({{1, 0}, {1, 0.5}, {0.5, 0.5}});
  const std::vector<std::int32_t> labels{1, 0, 0, 1, 2};
  Partition partition = build(make_tessellation(faces, region), labels, 3, region);
  measure_partition_geometry(partition, 1.0, 0.2);
  const PartitionMetrics& m = partition.metrics;
  EXPECT_DOUBLE_EQ(m.workload_ratio, 0.5 / 0.125);
  EXPECT_NEAR(m.separator_length, 0.5 + 0.5 + std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(m.compactness, m.separator_length / 3, 1e-15);
  EXPECT_NEAR(m.compactness_normalized, m.separator_length / std::sqrt(3.0), 1e-15);
  // Corners: centre 180° (part 0), 135° (part 1), 45° (part 2); (0,0.5) and (1,0.5):
  // 90° twice each; corner (1,0): 45° twice. Four of nine corners deviate by 45°.
  EXPECT_EQ(m.junction_corners, 9u);
  EXPECT_NEAR(m.junction_angle_deviation, 4 * (kPi / 4) / 9, 1e-12);
}

TEST(PartitionMetrics, SquareWithHole) {
  const testing::HoleFixture fixture;
  Partition partition = build(make_tessellation(fixture.faces, fixture.region), fixture.labels, 2, fixture.region);
  measure_partition_geometry(partition, 24.0, 0.5);
  const PartitionMetrics& m = partition.metrics;
  EXPECT_DOUBLE_EQ(m.workload_ratio, 2.0);
  EXPECT_DOUBLE_EQ(m.separator_length, 12.0);  // the square [1,4]^2, without the region's rings
  EXPECT_EQ(m.max_components_per_part, 1u);
  EXPECT_EQ(m.junction_corners, 0u);
  EXPECT_EQ(m.junction_angle_deviation, 0.0);
  EXPECT_LT(m.area_error, 1e-15);
}

TEST(PartitionMetrics, AreaErrorAgainstTheGivenRegionArea) {
  const Polygon2 region = unit_square();
  Partition partition =
      build(make_tessellation(grid_faces(4, 4, {0, 0}, 0.25), region), testing::quadrant_labels(), 4, region);
  measure_partition_geometry(partition, 1.25, 0.1);
  EXPECT_NEAR(partition.metrics.area_error, 0.25 / 1.25, 1e-15);
}

TEST(PartitionMetrics, PiecesAreTheCounterClockwiseLoopsOfAPart) {
  const Polygon2 region = unit_square();
  Partition partition =
      build(make_tessellation(grid_faces(4, 4, {0, 0}, 0.25), region), testing::quadrant_labels(), 4, region);
  // Give part 0 the loop of part 3 as a second outer loop, and part 1 the reversed
  // loop of part 2 (a hole, not a piece).
  partition.part_loops[0].push_back(partition.part_loops[3][0]);
  std::vector<std::int64_t> reversed;
  for (auto it = partition.part_loops[2][0].rbegin(); it != partition.part_loops[2][0].rend(); ++it)
    reversed.push_back(-*it - 1);
  partition.part_loops[1].push_back(reversed);
  measure_partition_geometry(partition, 1.0, 0.1);
  EXPECT_EQ(partition.metrics.max_components_per_part, 2u);
}

TEST(PartitionMetrics, ChordRuleLooksPastATinyFirstEdge) {
  // A vertical separator from (0.5,0) to (0.5,1) whose first edge is a 45° kink of
  // length sqrt(2) 1e-3: the chord of length r from (0.5,0) sees almost a right
  // angle; a chord shorter than the kink sees the kink.
  const Polygon2 region = unit_square();
  const Vec2 kink(0.501, 0.001);
  const std::vector<Face> faces{{{0, 0}, {0.5, 0}, kink, {0.5, 1}, {0, 1}}, {{0.5, 0}, {1, 0}, {1, 1}, {0.5, 1}, kink}};
  const Partition base = build(make_tessellation(faces, region), {0, 1}, 2, region);

  // Deviation of the separator chord from the vertical, by hand.
  const auto bottom_chord_deviation = [&](double r) {
    const double first = (kink - Vec2(0.5, 0)).norm();
    const Vec2 point = r <= first ? Vec2(0.5, 0) + r / first * (kink - Vec2(0.5, 0))
                                  : kink + (r - first) / (Vec2(0.5, 1) - kink).norm() * (Vec2(0.5, 1) - kink);
    return std::atan2(std::abs(point.x() - 0.5), point.y());
  };
  const double top_deviation = std::atan2(0.001, 0.999);  // the chord from (0.5,1) runs straight to the kink

  Partition wide = base;
  measure_partition_geometry(wide, 1.0, 0.25);
  EXPECT_EQ(wide.metrics.junction_corners, 4u);
  EXPECT_NEAR(wide.metrics.junction_angle_deviation, (2 * bottom_chord_deviation(0.25) + 2 * top_deviation) / 4, 1e-12);
  EXPECT_LT(wide.metrics.junction_angle_deviation, 0.01);

  Partition narrow = base;
  measure_partition_geometry(narrow, 1.0, 1e-4);
  EXPECT_NEAR(bottom_chord_deviation(1e-4), kPi / 4, 1e-12);
  EXPECT_NEAR(narrow.metrics.junction_angle_deviation, (2 * kPi / 4 + 2 * top_deviation) / 4, 1e-12);
  // L_S is the polyline length.
  EXPECT_NEAR(wide.metrics.separator_length, (kink - Vec2(0.5, 0)).norm() + (Vec2(0.5, 1) - kink).norm(), 1e-15);
}

}  // namespace
}  // namespace structmesh::partition2d
