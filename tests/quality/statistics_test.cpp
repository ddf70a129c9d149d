#include "structmesh/error.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace structmesh {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(Statistics, PopulationStandardDeviation) {
  const Statistics s = statistics({2, 4, 4, 4, 5, 5, 7, 9});
  EXPECT_EQ(s.count, 8u);
  EXPECT_DOUBLE_EQ(s.mean, 5.0);
  EXPECT_DOUBLE_EQ(s.stddev, 2.0);
  EXPECT_EQ(s.min, 2.0);
  EXPECT_EQ(s.max, 9.0);
}

TEST(Statistics, SkipsNaNAndHandlesEmpty) {
  const Statistics s = statistics({kNaN, 1.0, kNaN, 3.0});
  EXPECT_EQ(s.count, 2u);
  EXPECT_DOUBLE_EQ(s.mean, 2.0);
  EXPECT_DOUBLE_EQ(s.stddev, 1.0);
  const Statistics none = statistics({kNaN});
  EXPECT_EQ(none.count, 0u);
  EXPECT_EQ(none.min, 0.0);
  EXPECT_EQ(none.mean, 0.0);
  EXPECT_EQ(statistics({}).count, 0u);
}

TEST(Statistics, KeepsDigitsForValuesNearOne) {
  // A naive sum of squares would cancel here.
  const Statistics s = statistics({1.0 - 1e-9, 1.0 + 1e-9});
  EXPECT_NEAR(s.stddev, 1e-9, 1e-15);
}

TEST(Histogram, BinsClampsAndSkipsNaN) {
  const std::vector<std::uint64_t> h = histogram({-1.0, -0.95, 0.0, 0.04, 0.999, 1.0, 5.0, -7.0, kNaN}, -1, 1, 20);
  ASSERT_EQ(h.size(), 20u);
  EXPECT_EQ(h[0], 3u);   // -1, -0.95 and the clamped -7
  EXPECT_EQ(h[10], 2u);  // 0 and 0.04
  EXPECT_EQ(h[19], 3u);  // 0.999, 1 (the upper end) and the clamped 5
  std::uint64_t total = 0;
  for (std::uint64_t b : h) total += b;
  EXPECT_EQ(total, 8u);
}

TEST(Histogram, RejectsBadRanges) {
  EXPECT_THROW(histogram({1.0}, 0, 1, 0), InputError);
  EXPECT_THROW(histogram({1.0}, 1, 1, 5), InputError);
  EXPECT_THROW(histogram({1.0}, kNaN, 1, 5), InputError);
}

}  // namespace
}  // namespace structmesh
