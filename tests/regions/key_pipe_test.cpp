#include "structmesh/check.hpp"
#include "structmesh/regions.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace structmesh {
namespace {

struct Shape {
  const char* name;
  Polygon2 (*make)(std::size_t);
  std::size_t holes;
};
const Shape kShapes[] = {{"key", make_key_region, 1}, {"pipe", make_pipe_region, 9}};

// Segment lengths over all rings: {shortest, longest}.
std::pair<double, double> segment_length_range(const Polygon2& polygon) {
  double shortest = INFINITY, longest = 0;
  for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
    const auto ring = polygon.ring(r);
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const double length = (ring[(i + 1) % ring.size()] - ring[i]).norm();
      shortest = std::min(shortest, length);
      longest = std::max(longest, length);
    }
  }
  return {shortest, longest};
}

TEST(KeyPipe, ValidAtEveryResolutionWithTheRequestedSegmentCount) {
  for (const Shape& shape : kShapes) {
    for (const std::size_t segments : {64, 100, 1000, 4321, 100000, 1000000}) {
      SCOPED_TRACE(std::string(shape.name) + " " + std::to_string(segments));
      const Polygon2 polygon = shape.make(segments);
      EXPECT_EQ(polygon.hole_count(), shape.holes);
      EXPECT_EQ(polygon.coordinates, Polygon2::Coordinates::Planar);
      // Rings are implicitly closed, so there are as many segments as points.
      const double count = static_cast<double>(polygon.points.size());
      EXPECT_LE(std::abs(count - static_cast<double>(segments)), 0.01 * static_cast<double>(segments));
      const BoundingBox2 box = polygon.bounding_box();
      EXPECT_GE(box.min.x(), 0);
      EXPECT_GE(box.min.y(), 0);
      EXPECT_LE(box.max.x(), 10);
      EXPECT_LE(box.max.y(), 5);
      EXPECT_GT(signed_area(polygon.ring(0)), 0);
      for (std::size_t r = 1; r < polygon.ring_count(); ++r) EXPECT_LT(signed_area(polygon.ring(r)), 0);
      const RegionReport report = check_region({polygon});
      EXPECT_TRUE(report.valid) << (report.problems.empty() ? "" : report.problems[0].message);
    }
  }
}

TEST(KeyPipe, SegmentsAreNearlyUniformAtFineResolution) {
  for (const Shape& shape : kShapes) {
    const auto [shortest, longest] = segment_length_range(shape.make(100000));
    // Pieces get whole segment counts, and chords are a hair shorter than arcs.
    EXPECT_LT(longest / shortest, 1.05) << shape.name;
  }
}

TEST(KeyPipe, AreaConverges) {
  for (const Shape& shape : kShapes) {
    const double coarse = area(shape.make(1000)), medium = area(shape.make(100000)), fine = area(shape.make(1000000));
    EXPECT_LT(std::abs(medium - fine), 0.01 * std::abs(coarse - fine)) << shape.name;  // second order in the spacing
    EXPECT_LT(std::abs(coarse - fine) / fine, 1e-3) << shape.name;
    EXPECT_GT(fine, 5) << shape.name;
  }
}

TEST(KeyPipe, Deterministic) {
  for (const Shape& shape : kShapes) {
    const Polygon2 a = shape.make(12345), b = shape.make(12345);
    EXPECT_EQ(a.points, b.points) << shape.name;
    EXPECT_EQ(a.ring_offsets, b.ring_offsets) << shape.name;
  }
}

TEST(KeyPipe, TinyRequestsStillGiveValidShapes) {
  for (const Shape& shape : kShapes) {
    for (const std::size_t segments : {0, 1, 10, 40}) {
      const Polygon2 polygon = shape.make(segments);
      EXPECT_EQ(polygon.hole_count(), shape.holes);
      EXPECT_TRUE(check_region({polygon}).valid) << shape.name << " " << segments;
      EXPECT_LT(polygon.points.size(), 64u) << shape.name;
    }
  }
}

}  // namespace
}  // namespace structmesh
