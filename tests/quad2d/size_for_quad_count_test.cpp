#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"

#include <gtest/gtest.h>

namespace structmesh {
namespace {

TEST(SizeForQuadCount, UnitSquareWithHundredQuadsHasTenthSize) { EXPECT_DOUBLE_EQ(size_for_quad_count(1.0, 100), 0.1); }

TEST(SizeForQuadCount, RejectsZeroQuadsAndEmptyArea) {
  EXPECT_THROW(size_for_quad_count(1.0, 0), InputError);
  EXPECT_THROW(size_for_quad_count(0.0, 10), InputError);
}

}  // namespace
}  // namespace structmesh
