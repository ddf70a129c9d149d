// remove_narrow_water(): narrow creeks and straits are closed, small islands dropped,
// spikes of water removed, everything else kept exactly; the result is a valid region
// whose vertices are input vertices.
#include "structmesh/check.hpp"
#include "structmesh/partition2d.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <vector>

namespace structmesh {
namespace {

Polygon2 make_polygon(std::initializer_list<std::vector<Vec2>> rings) {
  Polygon2 polygon;
  for (const auto& ring : rings) polygon.add_ring(ring);
  return polygon;
}

// A 10 x 10 basin whose top side has a dead-end creek of the given width and depth 3,
// its banks sampled every 0.25 (a real creek has many vertices).
Polygon2 basin_with_creek(double width) {
  std::vector<Vec2> ring{{0, 0}, {10, 0}, {10, 10}, {5 + width / 2, 10}};
  for (double y = 10.25; y < 13; y += 0.25) ring.emplace_back(5 + width / 2, y);
  ring.emplace_back(5 + width / 2, 13);
  ring.emplace_back(5 - width / 2, 13);
  for (double y = 12.75; y > 10; y -= 0.25) ring.emplace_back(5 - width / 2, y);
  ring.emplace_back(5 - width / 2, 10);
  ring.emplace_back(0, 10);
  return make_polygon({ring});
}

void expect_valid_subset(const Polygon2& input, const NarrowWaterResult& result) {
  const RegionReport check = check_region({result.region});
  EXPECT_EQ(check.self_intersections, 0u);
  ASSERT_GE(result.region.ring_count(), 1u);
  EXPECT_GT(signed_area(result.region.ring(0)), 0) << "outer ring counter-clockwise";
  for (std::size_t r = 1; r < result.region.ring_count(); ++r)
    EXPECT_LT(signed_area(result.region.ring(r)), 0) << "hole " << r << " clockwise";
  ASSERT_EQ(result.rings.size(), result.region.ring_count());
  std::size_t k = 0;
  for (const auto& ring : result.rings)
    for (const Index v : ring) {
      ASSERT_LT(v, input.points.size());
      EXPECT_EQ(result.region.points[k++], input.points[v]) << "every vertex is an input vertex";
    }
  EXPECT_NEAR(result.report.area_after, std::abs(area(result.region)), 1e-9 * result.report.area_after);
}

TEST(RemoveNarrowWater, ClosesACreekNarrowerThanTheWidth) {
  const Polygon2 region = basin_with_creek(0.1);
  const NarrowWaterResult result = remove_narrow_water(region, 0.5, 0);
  expect_valid_subset(region, result);
  EXPECT_TRUE(result.report.changed);
  // The creek (0.1 x 3) is gone, the basin (100) is whole.
  EXPECT_NEAR(result.report.area_after, 100.0, 1e-9);
  EXPECT_NEAR(result.report.area_before - result.report.area_after, 0.3, 1e-9);
  EXPECT_NEAR(result.report.closed_area + result.report.dropped_area, 0.3, 1e-9);
}

TEST(RemoveNarrowWater, KeepsACreekWiderThanTheWidth) {
  const Polygon2 region = basin_with_creek(0.8);
  const NarrowWaterResult result = remove_narrow_water(region, 0.5, 0);
  EXPECT_FALSE(result.report.changed);
  EXPECT_EQ(result.region.points, region.points);
  EXPECT_NEAR(result.report.area_after, 100.0 + 0.8 * 3, 1e-9);
}

TEST(RemoveNarrowWater, ARegionWithNothingNarrowIsReturnedUnchanged) {
  const Polygon2 region = make_polygon({{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {{4, 4}, {4, 6}, {6, 6}, {6, 4}}});
  const NarrowWaterResult result = remove_narrow_water(region, 0.5, 0.1);
  EXPECT_FALSE(result.report.changed);
  EXPECT_EQ(result.region.points, region.points);
  EXPECT_EQ(result.region.ring_offsets, region.ring_offsets);
}

TEST(RemoveNarrowWater, DropsIslandsBelowTheAreaAndKeepsLargerOnes) {
  const Polygon2 region = make_polygon({{{0, 0}, {10, 0}, {10, 10}, {0, 10}},
                                        {{2, 2}, {2, 2.2}, {2.2, 2.2}, {2.2, 2}},  // 0.04
                                        {{5, 5}, {5, 7}, {7, 7}, {7, 5}}});        // 4
  const NarrowWaterResult result = remove_narrow_water(region, 0, 0.25);
  expect_valid_subset(region, result);
  EXPECT_EQ(result.report.islands_dropped, 1u);
  EXPECT_NEAR(result.report.island_area, 0.04, 1e-12);
  EXPECT_EQ(result.region.hole_count(), 1u);
  EXPECT_NEAR(result.report.area_after, 96.0, 1e-9);
}

TEST(RemoveNarrowWater, AnIslandNextToTheShoreJoinsIt) {
  // A 2 x 2 island 0.1 from the bottom shore: the strait is closed, so the island
  // is no longer a hole, and the water lost is about the strait (0.1 x 2) plus slivers.
  const Polygon2 region =
      make_polygon({{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {{4, 0.1}, {4, 2.1}, {6, 2.1}, {6, 0.1}}});
  const NarrowWaterResult result = remove_narrow_water(region, 0.5, 0);
  expect_valid_subset(region, result);
  EXPECT_EQ(result.region.hole_count(), 0u);
  const double lost = result.report.area_before - result.report.area_after;
  EXPECT_GE(lost, 0.2 - 1e-9);
  EXPECT_LT(lost, 0.2 + 0.5 * 0.5 * 4);  // at most a few width-sized triangles beyond the strait
}

TEST(RemoveNarrowWater, ASpikeOfWaterAlongOneLongSegmentIsClosed) {
  // The top side is one long segment; a sliver of water runs back along it (its far
  // bank 0.05 below), as OpenStreetMap creeks do where one bank has few vertices.
  const Polygon2 region = make_polygon({{{0, 0}, {10, 0}, {10, 10}, {2, 10}, {8, 9.95}, {1, 9.5}, {0, 10}}});
  ASSERT_EQ(check_region({region}).self_intersections, 0u);
  const NarrowWaterResult result = remove_narrow_water(region, 0.5, 0);
  expect_valid_subset(region, result);
  EXPECT_TRUE(result.report.changed);
  // The sliver between the top side and the segment back to (8, 9.95) is closed: its
  // tip (2, 10) goes, and the water loses that triangle (8 x 0.05 / 2).
  for (const Vec2& p : result.region.points) EXPECT_FALSE(p == Vec2(2, 10)) << "the spike's tip is gone";
  EXPECT_NEAR(result.report.area_before - result.report.area_after, 0.2, 1e-9);
}

TEST(RemoveNarrowWater, KeepsTheLargestPieceWhenAChannelCutsTheWaterInTwo) {
  // Two basins (10 x 10 and 4 x 4) joined by a channel 0.1 wide: the small basin is cut off.
  std::vector<Vec2> ring{{0, 0}, {10, 0}, {10, 4.95}};
  for (double x = 10.5; x < 13; x += 0.5) ring.emplace_back(x, 4.95);
  ring.insert(ring.end(), {{13, 4.95}, {13, 3}, {17, 3}, {17, 7}, {13, 7}, {13, 5.05}});
  for (double x = 12.5; x > 10; x -= 0.5) ring.emplace_back(x, 5.05);
  ring.insert(ring.end(), {{10, 5.05}, {10, 10}, {0, 10}});
  const Polygon2 region = make_polygon({ring});
  const NarrowWaterResult result = remove_narrow_water(region, 0.5, 0);
  expect_valid_subset(region, result);
  EXPECT_NEAR(result.report.area_after, 100.0, 1e-9);
  EXPECT_GE(result.report.pieces_dropped, 1u);
  EXPECT_NEAR(result.report.dropped_area, 16.0, 0.3);
}

}  // namespace
}  // namespace structmesh
