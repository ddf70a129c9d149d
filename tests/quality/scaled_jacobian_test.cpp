// Analytic cases of the quad and hex scaled Jacobians (Verdict's definitions), plus
// values measured with VTK 9.1's vtkMeshQuality where Verdict has special rules.
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace structmesh {
namespace {

const Vec3 kUp = Vec3::UnitZ();

std::array<Vec3, 4> parallelogram(double theta) {
  const Vec3 side(std::cos(theta), std::sin(theta), 0);
  return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0) + side, side};
}

std::array<Vec3, 8> unit_cube() {
  return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
          Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
}

// The unit cube with its vertical edges tilted by theta from the x axis in the x-z plane.
std::array<Vec3, 8> sheared_hex(double theta) {
  std::array<Vec3, 8> c = unit_cube();
  for (int i = 4; i < 8; ++i) c[i] = c[i - 4] + Vec3(std::cos(theta), 0, std::sin(theta));
  return c;
}

TEST(QuadScaledJacobian, UnitSquareIsOne) {
  const std::array<Vec3, 4> square{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  EXPECT_DOUBLE_EQ(quad_scaled_jacobian(square), 1.0);
  EXPECT_DOUBLE_EQ(quad_scaled_jacobian(square, &kUp), 1.0);
}

TEST(QuadScaledJacobian, ParallelogramIsSineOfItsAngle) {
  for (double degrees : {15.0, 30.0, 45.0, 60.0, 75.0, 90.0, 110.0, 150.0}) {
    const double theta = degrees * std::numbers::pi / 180;
    EXPECT_NEAR(quad_scaled_jacobian(parallelogram(theta)), std::sin(theta), 1e-14) << degrees;
    EXPECT_NEAR(quad_scaled_jacobian(parallelogram(theta), &kUp), std::sin(theta), 1e-14) << degrees;
  }
}

TEST(QuadScaledJacobian, SizeAndPositionDoNotMatter) {
  std::array<Vec3, 4> q = parallelogram(std::numbers::pi / 3);
  for (Vec3& p : q) p = 1e-3 * p + Vec3(1e4, -2e4, 0);
  EXPECT_NEAR(quad_scaled_jacobian(q), std::sin(std::numbers::pi / 3), 1e-9);
}

TEST(QuadScaledJacobian, ReflexCornerIsNegative) {
  // An arrow: the corner at (0.5, 0.5) is reflex. Corner Jacobian -2 over 2.5.
  const std::array<Vec3, 4> arrow{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0, 2, 0)};
  EXPECT_NEAR(quad_scaled_jacobian(arrow), -0.8, 1e-15);
  EXPECT_NEAR(quad_scaled_jacobian(arrow, &kUp), -0.8, 1e-15);
}

TEST(QuadScaledJacobian, ClockwiseQuadIsInvertedOnlyAgainstAReferenceNormal) {
  const std::array<Vec3, 4> clockwise{Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(1, 0, 0)};
  EXPECT_DOUBLE_EQ(quad_scaled_jacobian(clockwise), 1.0);  // Verdict: its own normal
  EXPECT_DOUBLE_EQ(quad_scaled_jacobian(clockwise, &kUp), -1.0);
}

TEST(QuadScaledJacobian, BowTieIsNotPositive) {
  // Symmetric bow-tie: the principal axes are parallel, Verdict's normal is zero: 0.
  const std::array<Vec3, 4> bow_tie{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
  EXPECT_EQ(quad_scaled_jacobian(bow_tie), 0.0);
  EXPECT_NEAR(quad_scaled_jacobian(bow_tie, &kUp), -std::sqrt(0.5), 1e-15);
  // An asymmetric one has a normal, and a corner turning against it.
  const std::array<Vec3, 4> skewed{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0), Vec3(1, 1.5, 0)};
  EXPECT_LT(quad_scaled_jacobian(skewed), 0.0);
  EXPECT_LT(quad_scaled_jacobian(skewed, &kUp), 0.0);
}

TEST(QuadScaledJacobian, VerdictSpecialCases) {
  // Values measured with VTK 9.1 (vtkMeshQuality::QuadScaledJacobian, double points).
  // Node 3 on node 2: a triangle, scored by Verdict's tri_scaled_jacobian.
  const std::array<Vec3, 4> right_triangle{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 0)};
  EXPECT_NEAR(quad_scaled_jacobian(right_triangle), 0.816496580927726, 1e-15);
  const double h = std::sqrt(3.0) / 2;
  const std::array<Vec3, 4> equilateral{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, h, 0), Vec3(0.5, h, 0)};
  EXPECT_NEAR(quad_scaled_jacobian(equilateral), 1.0, 1e-15);
  // The same triangle clockwise: Verdict cannot tell; +z can.
  const std::array<Vec3, 4> clockwise{Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, 0, 0), Vec3(1, 0, 0)};
  EXPECT_NEAR(quad_scaled_jacobian(clockwise), 0.816496580927726, 1e-15);
  EXPECT_NEAR(quad_scaled_jacobian(clockwise, &kUp), -0.816496580927726, 1e-15);
  // Any other repeated node is a zero-length edge: 0, not a triangle.
  const std::array<Vec3, 4> repeated{Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  EXPECT_EQ(quad_scaled_jacobian(repeated), 0.0);
  EXPECT_EQ(quad_scaled_jacobian(repeated, &kUp), 0.0);
  const std::array<Vec3, 4> point{Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(1, 2, 3)};
  EXPECT_EQ(quad_scaled_jacobian(point), 0.0);
  // A non-planar (twisted) quad, projected on its principal-axes normal.
  const std::array<Vec3, 4> twisted{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 1), Vec3(0, 1, 0)};
  EXPECT_NEAR(quad_scaled_jacobian(twisted), 0.8164965809277259, 1e-15);
}

TEST(QuadScaledJacobian, ZeroReferenceNormalFallsBackToVerdict) {
  const Vec3 zero = Vec3::Zero();
  const std::array<Vec3, 4> clockwise{Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(1, 0, 0)};
  EXPECT_DOUBLE_EQ(quad_scaled_jacobian(clockwise, &zero), 1.0);
}

TEST(HexScaledJacobian, UnitCubeIsOne) {
  EXPECT_DOUBLE_EQ(hex_scaled_jacobian(unit_cube()).value(), 1.0);
  EXPECT_DOUBLE_EQ(hex_corner_scaled_jacobian(unit_cube()).value(), 1.0);
}

TEST(HexScaledJacobian, RotatedScaledBoxIsOne) {
  std::array<Vec3, 8> box = unit_cube();
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (Vec3& p : box) p = rotation * Vec3(3 * p.x(), 0.5 * p.y(), 7 * p.z()) + Vec3(10, 20, 30);
  EXPECT_NEAR(hex_scaled_jacobian(box).value(), 1.0, 1e-14);
  EXPECT_NEAR(hex_corner_scaled_jacobian(box).value(), 1.0, 1e-14);
}

TEST(HexScaledJacobian, ShearedHexIsSineOfTheShearAngle) {
  for (double degrees : {20.0, 45.0, 60.0, 85.0, 120.0}) {
    const double theta = degrees * std::numbers::pi / 180;
    EXPECT_NEAR(hex_scaled_jacobian(sheared_hex(theta)).value(), std::sin(theta), 1e-14) << degrees;
    EXPECT_NEAR(hex_corner_scaled_jacobian(sheared_hex(theta)).value(), std::sin(theta), 1e-14) << degrees;
  }
}

TEST(HexScaledJacobian, RepeatedVertexIsInvalidNotPerfect) {
  std::array<Vec3, 8> hex = unit_cube();
  hex[1] = hex[0];  // zero-length edge: Verdict returns VERDICT_DBL_MAX
  EXPECT_FALSE(hex_scaled_jacobian(hex).has_value());
  EXPECT_FALSE(hex_corner_scaled_jacobian(hex).has_value());
  std::array<Vec3, 8> flat = unit_cube();
  for (int i = 4; i < 8; ++i) flat[i] = flat[i - 4];  // zero-height hex: zero vertical edges and axis
  EXPECT_FALSE(hex_scaled_jacobian(flat).has_value());
  EXPECT_FALSE(hex_corner_scaled_jacobian(flat).has_value());
}

TEST(HexScaledJacobian, CornerPushedThroughTheOppositeFaceIsNegative) {
  std::array<Vec3, 8> hex = unit_cube();
  hex[6] = Vec3(0.5, 0.5, -0.5);  // top corner below the bottom face
  EXPECT_LT(hex_scaled_jacobian(hex).value(), 0.0);
  EXPECT_LT(hex_corner_scaled_jacobian(hex).value(), 0.0);
}

TEST(HexScaledJacobian, MirroredHexIsMinusOne) {
  std::array<Vec3, 8> hex = unit_cube();
  for (Vec3& p : hex) p.z() = -p.z();
  EXPECT_DOUBLE_EQ(hex_scaled_jacobian(hex).value(), -1.0);
  EXPECT_DOUBLE_EQ(hex_corner_scaled_jacobian(hex).value(), -1.0);
}

TEST(HexScaledJacobian, CentreSampleNeverRaisesTheMinimum) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (int trial = 0; trial < 1000; ++trial) {
    std::array<Vec3, 8> hex = unit_cube();
    for (Vec3& p : hex) p += Vec3(jitter(random), jitter(random), jitter(random));
    const double nine = hex_scaled_jacobian(hex).value();
    const double eight = hex_corner_scaled_jacobian(hex).value();
    EXPECT_LE(nine, eight);
    EXPECT_GE(nine, -1.0);
    EXPECT_LE(eight, 1.0);
  }
}

// The sample-by-sample interface the hex smoothing uses: the minimum of the 9 samples is
// hex_scaled_jacobian, and moving point l changes the centre and the corners of
// kCornersUsing[l] only.
TEST(HexJacobianSample, SamplesMakeTheScaledJacobianAndOnlyTheListedOnesMove) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (int trial = 0; trial < 200; ++trial) {
    std::array<Vec3, 8> hex = unit_cube();
    for (Vec3& p : hex) p += Vec3(jitter(random), jitter(random), jitter(random));
    double smallest = hex_jacobian_sample::centre(hex).value();
    for (int c = 0; c < 8; ++c) smallest = std::min(smallest, hex_jacobian_sample::corner(hex, c).value());
    EXPECT_EQ(smallest, hex_scaled_jacobian(hex).value());
    for (int l = 0; l < 8; ++l) {
      std::array<Vec3, 8> moved = hex;
      moved[static_cast<std::size_t>(l)] += Vec3(0.2, -0.1, 0.15);
      const auto& using_l = hex_jacobian_sample::kCornersUsing[static_cast<std::size_t>(l)];
      for (int c = 0; c < 8; ++c) {
        const bool listed = std::find(using_l.begin(), using_l.end(), c) != using_l.end();
        const bool changed = hex_jacobian_sample::corner(moved, c) != hex_jacobian_sample::corner(hex, c);
        EXPECT_EQ(changed, listed) << "point " << l << ", corner sample " << c;
      }
    }
  }
}

TEST(HexJacobianSample, DegenerateEdgeOrAxisHasNoSample) {
  std::array<Vec3, 8> hex = unit_cube();
  hex[1] = hex[0];
  EXPECT_FALSE(hex_jacobian_sample::corner(hex, 0).has_value());
  EXPECT_TRUE(hex_jacobian_sample::corner(hex, 6).has_value());
  EXPECT_FALSE(hex_scaled_jacobian(hex).has_value());
}

}  // namespace
}  // namespace structmesh
