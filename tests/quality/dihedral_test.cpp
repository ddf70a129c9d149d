// Dihedral angles of hexes (§5.3): 90 degrees in a box, theta and 180 - theta where
// a shear tilts two opposite faces.
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace structmesh {
namespace {

std::array<Vec3, 8> sheared_hex(double theta) {
  std::array<Vec3, 8> c{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  for (int i = 4; i < 8; ++i) c[i] = c[i - 4] + Vec3(std::cos(theta), 0, std::sin(theta));
  return c;
}

TEST(HexDihedralAngles, CubeIsAllRightAngles) {
  for (double a : hex_dihedral_angles(sheared_hex(std::numbers::pi / 2))) EXPECT_NEAR(a, std::numbers::pi / 2, 1e-15);
}

TEST(HexDihedralAngles, ShearTiltsTheFourEdgesAlongY) {
  const double theta = 50 * std::numbers::pi / 180;
  const std::array<double, 12> a = hex_dihedral_angles(sheared_hex(theta));
  for (std::size_t e = 0; e < 12; ++e) {
    double expected = std::numbers::pi / 2;
    // kHexEdges 3 = (3,0) and 5 = (5,6): between a tilted face and the bottom / top,
    // on the acute side; 1 = (1,2) and 7 = (7,4) on the obtuse side.
    if (e == 3 || e == 5) expected = theta;
    if (e == 1 || e == 7) expected = std::numbers::pi - theta;
    EXPECT_NEAR(a[e], expected, 1e-14) << "edge " << e;
  }
}

TEST(HexDihedralAngles, ZeroFaceNormalGivesNaN) {
  std::array<Vec3, 8> hex = sheared_hex(std::numbers::pi / 2);
  for (int i = 5; i < 8; ++i) hex[i] = hex[4];  // the top face collapses to a point
  const std::array<double, 12> a = hex_dihedral_angles(hex);
  for (int e : {4, 5, 6, 7}) EXPECT_TRUE(std::isnan(a[e])) << e;
  EXPECT_NEAR(a[0], std::numbers::pi / 2, 1e-15);  // bottom and front face still have normals
}

}  // namespace
}  // namespace structmesh
