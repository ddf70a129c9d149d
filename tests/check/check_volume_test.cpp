// check_volume() on single cells and tiny meshes with known answers.
#include "structmesh/check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

namespace structmesh {
namespace {

MeshBundle unit_tet() {
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.tets = {{0, 1, 2, 3}};
  return mesh;
}

MeshBundle unit_cube_hex() {
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  mesh.hexes = {{0, 1, 2, 3, 4, 5, 6, 7}};
  return mesh;
}

std::size_t count_kind(const VolumeReport& report, const std::string& kind) {
  return std::size_t(
      std::count_if(report.problems.begin(), report.problems.end(), [&](const Problem& p) { return p.kind == kind; }));
}

TEST(CheckVolume, PositiveTetIsValid) {
  const VolumeReport r = check_volume(unit_tet());
  EXPECT_EQ(r.tets, 1u);
  EXPECT_EQ(r.vertices, 4u);
  EXPECT_EQ(r.inverted, 0u);
  EXPECT_EQ(r.degenerate, 0u);
  EXPECT_EQ(r.non_manifold_faces, 0u);
  EXPECT_EQ(r.unused_vertices, 0u);
  EXPECT_NEAR(r.min_tet_volume, 1.0 / 6.0, 1e-15);
  EXPECT_TRUE(r.valid);
  EXPECT_TRUE(r.problems.empty());
}

TEST(CheckVolume, FlippedTetIsInverted) {
  MeshBundle mesh = unit_tet();
  std::swap(mesh.tets[0][1], mesh.tets[0][2]);
  mesh.lines.tet_lines = {7};
  const VolumeReport r = check_volume(mesh);
  EXPECT_EQ(r.inverted, 1u);
  EXPECT_NEAR(r.min_tet_volume, -1.0 / 6.0, 1e-15);
  EXPECT_FALSE(r.valid);
  ASSERT_EQ(count_kind(r, "inverted-cell"), 1u);
  EXPECT_EQ(r.problems.front().line, 7u);
  EXPECT_EQ(r.problems.front().element, 0);
}

TEST(CheckVolume, FlatTetIsInverted) {
  MeshBundle mesh = unit_tet();
  mesh.points[3] = {0.3, 0.3, 1e-15};  // positive, but flat within rounding
  const VolumeReport r = check_volume(mesh);
  EXPECT_EQ(r.inverted, 1u);
  EXPECT_FALSE(r.valid);
}

TEST(CheckVolume, UnitCubeHexIsValid) {
  const VolumeReport r = check_volume(unit_cube_hex());
  EXPECT_EQ(r.hexes, 1u);
  EXPECT_NEAR(r.min_hex_scaled_jacobian, 1.0, 1e-12);
  EXPECT_TRUE(r.valid);
  EXPECT_TRUE(r.problems.empty());
}

TEST(CheckVolume, MirroredHexIsInverted) {
  MeshBundle mesh = unit_cube_hex();
  auto& h = mesh.hexes[0];
  std::swap_ranges(h.begin(), h.begin() + 4, h.begin() + 4);  // top and bottom exchanged
  const VolumeReport r = check_volume(mesh);
  EXPECT_EQ(r.inverted, 1u);
  EXPECT_LT(r.min_hex_scaled_jacobian, 0);
  EXPECT_FALSE(r.valid);
}

TEST(CheckVolume, HexWithRepeatedVertexIsDegenerate) {
  MeshBundle mesh = unit_cube_hex();
  mesh.hexes[0][6] = mesh.hexes[0][5];
  const VolumeReport r = check_volume(mesh);
  EXPECT_EQ(r.degenerate, 1u);
  EXPECT_EQ(r.unused_vertices, 1u);  // vertex 6 is no longer used: a warning only
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(count_kind(r, "degenerate-cell"), 1u);
}

TEST(CheckVolume, HexWithCoincidentCornersIsInvalid) {
  MeshBundle mesh = unit_cube_hex();
  mesh.points[6] = mesh.points[5];  // distinct indices, zero-length edge
  const VolumeReport r = check_volume(mesh);
  EXPECT_EQ(r.degenerate, 1u);
  EXPECT_FALSE(r.valid);
}

TEST(CheckVolume, ThreeTetsOnOneFaceAreNonManifold) {
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 1}, {0.2, 0.2, -1}, {0.3, 0.3, 2}};
  mesh.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
  const VolumeReport r = check_volume(mesh);
  EXPECT_EQ(r.inverted, 0u);
  EXPECT_EQ(r.non_manifold_faces, 1u);
  EXPECT_FALSE(r.valid);
  ASSERT_EQ(count_kind(r, "non-manifold-face"), 1u);
  const Problem& p = r.problems.front();
  EXPECT_NE(p.message.find("3 tets"), std::string::npos) << p.message;
}

TEST(CheckVolume, TwoTetsSharingAFaceAreValid) {
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 1}, {0.2, 0.2, -1}};
  mesh.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  EXPECT_TRUE(check_volume(mesh).valid);
}

TEST(CheckVolume, UnusedVertexIsAWarning) {
  MeshBundle mesh = unit_tet();
  mesh.points.emplace_back(5, 5, 5);
  mesh.triangles = {{0, 1, 2}};  // a boundary element: counted, otherwise ignored
  const VolumeReport r = check_volume(mesh);
  EXPECT_EQ(r.unused_vertices, 1u);
  EXPECT_EQ(r.triangles, 1u);
  EXPECT_TRUE(r.valid);
  EXPECT_EQ(count_kind(r, "unused-vertex"), 1u);
}

TEST(CheckVolume, MixedTetsAndHexesNumberCellsInBundleOrder) {
  MeshBundle mesh = unit_cube_hex();
  mesh.points.emplace_back(0.5, 0.5, 2);  // 8, above the top face
  mesh.tets = {{4, 6, 5, 8}};             // inverted: 4-6-5 runs clockwise seen from 8
  mesh.quads = {{4, 5, 6, 7}};
  const VolumeReport r = check_volume(mesh);
  EXPECT_EQ(r.inverted, 1u);
  ASSERT_EQ(count_kind(r, "inverted-cell"), 1u);
  EXPECT_EQ(r.problems.front().element, 1);  // after the quad
}

TEST(CheckVolume, OutOfRangeIndexIsReported) {
  MeshBundle mesh = unit_tet();
  mesh.tets.push_back({0, 1, 2, 42});
  const VolumeReport r = check_volume(mesh);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(count_kind(r, "index-out-of-range"), 1u);
}

TEST(CheckVolume, NonFinitePointIsReported) {
  MeshBundle mesh = unit_cube_hex();
  mesh.points[3].z() = std::numeric_limits<double>::infinity();
  const VolumeReport r = check_volume(mesh);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(count_kind(r, "non-finite-point"), 1u);
}

TEST(CheckVolume, NoCellsIsNotValid) {
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  const VolumeReport r = check_volume(mesh);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(count_kind(r, "no-cells"), 1u);
}

}  // namespace
}  // namespace structmesh
