// The built-in solids (solids.hpp): each is a closed, outward, self-intersection-free surface
// of the genus it names; the building blocks on analytic cases; the error paths.
#include "structmesh/solids.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace structmesh {
namespace {

TEST(BuiltinSolids, EveryOneIsAValidSolidBoundaryOfItsGenus) {
  ASSERT_GE(builtin_solids().size(), 16u);
  for (const BuiltinSolid& solid : builtin_solids()) {
    SCOPED_TRACE(std::string(solid.name));
    const TriMesh surface = make_builtin_solid(solid.name);
    const SurfaceReport report = check_surface(to_bundle(surface));
    EXPECT_TRUE(report.valid_solid_boundary) << solid_boundary_problems(report);
    EXPECT_EQ(report.genus, solid.genus);
    EXPECT_EQ(report.euler_characteristic, 2 - 2 * solid.genus);
    EXPECT_GT(enclosed_volume(surface), 0);
  }
}

TEST(BuiltinSolids, UnknownNameNamesTheChoices) {
  try {
    make_builtin_solid("teapot");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("trefoil"), std::string::npos) << e.what();
  }
}

TEST(BuiltinSolids, IcosphereHasTheIcosahedronsCountsAndItsRadius) {
  const TriMesh sphere = icosphere(3, [](const Vec3&) { return 2.0; });
  EXPECT_EQ(sphere.points.size(), 10u * 64 + 2);
  EXPECT_EQ(sphere.triangles.size(), 20u * 64);
  for (const Vec3& p : sphere.points) EXPECT_NEAR(p.norm(), 2.0, 1e-12);
}

TEST(BuiltinSolids, RevolvedRectangleIsACylinderOfTheRightVolume) {
  // A cylinder of radius 1 and height 2 from its profile, either way round: the volume of
  // the inscribed 64-gon prism, outward both times.
  const std::vector<std::pair<double, double>> up{{0, 0}, {1, 0}, {1, 2}, {0, 2}};
  const std::vector<std::pair<double, double>> down{{0, 2}, {1, 2}, {1, 0}, {0, 0}};
  const double prism = 2 * 0.5 * 64 * std::sin(2 * 3.14159265358979323846 / 64);
  for (const auto& profile : {up, down}) {
    const TriMesh cylinder = surface_of_revolution(profile, 64, false);
    EXPECT_NEAR(enclosed_volume(cylinder), prism, 1e-9);
    EXPECT_TRUE(check_surface(to_bundle(cylinder)).valid_solid_boundary);
  }
}

TEST(BuiltinSolids, RevolutionRejectsAProfileOffTheAxisAcrossItOrPinchedOnIt) {
  const std::vector<std::pair<double, double>> open_off_axis{{0.5, 0}, {1, 0}, {1, 1}};
  EXPECT_THROW(surface_of_revolution(open_off_axis, 16, false), InputError);
  const std::vector<std::pair<double, double>> closed_on_axis{{0, 0}, {1, 0}, {1, 1}};
  EXPECT_THROW(surface_of_revolution(closed_on_axis, 16, true), InputError);
  const std::vector<std::pair<double, double>> negative{{0, 0}, {-1, 0}, {0, 1}};
  EXPECT_THROW(surface_of_revolution(negative, 16, false), InputError);
  const std::vector<std::pair<double, double>> pinched{{0, 0}, {1, 0}, {0, 1}, {1, 2}, {0, 2}};
  EXPECT_THROW(surface_of_revolution(pinched, 16, false), InputError);
  const std::vector<std::pair<double, double>> two_poles{{0, 0}, {0, 1}};
  EXPECT_THROW(surface_of_revolution(two_poles, 16, false), InputError);
}

TEST(BuiltinSolids, TaubinSmoothingKeepsAVoxelCubesSizeAndRoundsIt) {
  // One unit voxel, subdivided: smoothing moves the corner (0, 0, 0) in along the diagonal,
  // while lambda|mu keeps the volume within a few percent of the cube's (plain Laplacian
  // steps would shrink it steadily).
  const std::vector<std::array<int, 3>> cell{{0, 0, 0}};
  TriMesh cube = voxel_union_surface(cell, 6);
  EXPECT_NEAR(enclosed_volume(cube), 1.0, 1e-12);
  std::size_t corner = cube.points.size();
  for (std::size_t v = 0; v < cube.points.size(); ++v)
    if (cube.points[v].norm() == 0) corner = v;
  ASSERT_LT(corner, cube.points.size());
  taubin_smooth(cube, 10);
  EXPECT_NEAR(enclosed_volume(cube), 1.0, 0.05);
  const Vec3& moved = cube.points[corner];
  EXPECT_GT(moved.minCoeff(), 0.02);
  EXPECT_NEAR(moved.x(), moved.y(), 1e-9);
  EXPECT_NEAR(moved.y(), moved.z(), 1e-9);
  EXPECT_TRUE(check_surface(to_bundle(cube)).valid_solid_boundary);
}

}  // namespace
}  // namespace structmesh
