#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"

#include <gtest/gtest.h>

namespace structmesh {
namespace {

TEST(AssignParts, LongestFirstOntoTheLeastLoaded) {
  const std::vector<double> work{3, 3, 2, 2, 2};
  // LPT: 3->0, 3->1, 2->0 (tie, lowest), 2->1, 2->0: loads 7 and 5.
  EXPECT_EQ(assign_parts(work, 2), (std::vector<std::int32_t>{0, 1, 0, 1, 0}));
  EXPECT_DOUBLE_EQ(predicted_speedup(work, 2), 12.0 / 7.0);
}

TEST(AssignParts, EqualPartsGiveIdealSpeedupAndOneProcessGivesOne) {
  const std::vector<double> work(64, 1.5);
  EXPECT_DOUBLE_EQ(predicted_speedup(work, 16), 16.0);
  EXPECT_DOUBLE_EQ(predicted_speedup(work, 1), 1.0);
  // More processes than parts: the longest part bounds the speedup.
  EXPECT_DOUBLE_EQ(predicted_speedup(work, 128), 64.0);
}

TEST(AssignParts, RejectsZeroProcesses) {
  const std::vector<double> work{1};
  EXPECT_THROW(assign_parts(work, 0), InputError);
}

}  // namespace
}  // namespace structmesh
