// fill_holes(): holes closed so that check_surface() accepts the result as a solid
// boundary, the input's points and triangles kept in place; bad input rejected.
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cstdlib>
#include <filesystem>

namespace structmesh {
namespace {

// The unit cube's 12 outward triangles.
TriMesh cube() {
  TriMesh mesh;
  for (int i = 0; i < 8; ++i) mesh.points.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

double volume(const TriMesh& mesh) {
  double v = 0;
  for (const auto& t : mesh.triangles) v += mesh.points[t[0]].dot(mesh.points[t[1]].cross(mesh.points[t[2]])) / 6.0;
  return v;
}

TEST(FillHoles, ClosedSurfaceIsUnchanged) {
  const HoleFilling result = fill_holes(cube());
  EXPECT_EQ(result.holes, 0u);
  EXPECT_EQ(result.surface.triangles, cube().triangles);
  EXPECT_EQ(result.surface.points, cube().points);
}

TEST(FillHoles, TwoHolesAreClosedIntoAValidSolidKeepingTheInput) {
  TriMesh open = cube();
  // The whole top side (two triangles) and one triangle of the bottom side.
  open.triangles.erase(open.triangles.begin() + 2, open.triangles.begin() + 4);
  open.triangles.erase(open.triangles.begin());
  ASSERT_FALSE(check_surface(to_bundle(open)).closed);
  const HoleFilling result = fill_holes(open);
  EXPECT_EQ(result.holes, 2u);
  EXPECT_EQ(result.added_faces, 3u);  // a square needs two triangles, a triangle one
  EXPECT_EQ(result.added_vertices, 0u);
  ASSERT_EQ(result.surface.triangles.size(), open.triangles.size() + 3);
  for (std::size_t f = 0; f < open.triangles.size(); ++f) EXPECT_EQ(result.surface.triangles[f], open.triangles[f]);
  const SurfaceReport report = check_surface(to_bundle(result.surface));
  EXPECT_TRUE(report.valid_solid_boundary);
  EXPECT_NEAR(volume(result.surface), 1.0, 1e-12);
}

TEST(FillHoles, TheTwoEyesOfTheToscaDog) {
  const char* data = std::getenv("STRUCTMESH_DATA");
  const std::filesystem::path path =
      std::filesystem::path(data ? data : STRUCTMESH_DATA_DEFAULT) / "surfaces" / "tosca_dog0.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is missing (set STRUCTMESH_DATA)";
  const TriMesh dog = to_tri_mesh(read_mesh(path));
  const HoleFilling result = fill_holes(dog);
  EXPECT_EQ(result.holes, 2u);
  const SurfaceReport report = check_surface(to_bundle(result.surface));
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.valid_solid_boundary) << (report.problems.empty() ? "" : report.problems.front().message);
}

TEST(FillHoles, NonManifoldInputIsRejected) {
  TriMesh fan = cube();
  fan.points.emplace_back(0.5, 0.5, -1);
  fan.triangles.push_back({0, 1, 8});  // a third face on edge 0-1
  EXPECT_THROW(fill_holes(fan), InputError);
}

}  // namespace
}  // namespace structmesh
