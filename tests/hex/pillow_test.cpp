// hex_boundary_quads and pillow on box grids counted by hand: the boundary's size and
// orientation, the new layer's hexes and the exact inward offset of the old boundary.
#include "quality/test_meshes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>

namespace structmesh {
namespace {

Vec3 vector_area(const HexMesh& mesh, const std::array<Index, 4>& q) {
  return (mesh.points[q[2]] - mesh.points[q[0]]).cross(mesh.points[q[3]] - mesh.points[q[1]]);
}

// Boundary faces per hex.
std::vector<int> boundary_faces_per_hex(const HexMesh& mesh) {
  const FaceAdjacency<4> faces = build_faces(mesh);
  std::vector<int> count(mesh.hexes.size(), 0);
  for (std::size_t f = 0; f < faces.faces.size(); ++f)
    if (faces.face_cells[f][1] == kInvalidIndex) ++count[faces.face_cells[f][0]];
  return count;
}

// The hexes of an L: a 2x2x1 grid without its (1, 1) hex.
HexMesh l_shape() {
  HexMesh mesh = test::hex_grid(2, 2, 1);
  mesh.hexes.erase(mesh.hexes.begin() + 3);
  return mesh;
}

TEST(HexBoundaryQuads, GridOf2x2x2Has24OutwardQuads) {
  const HexMesh mesh = test::hex_grid(2, 2, 2);
  const auto quads = hex_boundary_quads(mesh);
  ASSERT_EQ(quads.size(), 24u);
  const Vec3 centre(1, 1, 1);
  for (const auto& q : quads) {
    Vec3 middle = Vec3::Zero();
    for (const Index v : q) middle += mesh.points[v] / 4;
    // A boundary face of the box: its middle is on a box face, and its normal points away
    // from the box centre along that face's axis.
    const Vec3 normal = vector_area(mesh, q).normalized();
    const Vec3 out = middle - centre;
    int axis = 0;
    out.cwiseAbs().maxCoeff(&axis);
    EXPECT_DOUBLE_EQ(std::abs(out[axis]), 1.0);
    EXPECT_NEAR(normal[axis], out[axis] > 0 ? 1.0 : -1.0, 1e-12);
  }
}

TEST(HexBoundaryQuads, RejectsAPointPastTheEnd) {
  HexMesh mesh = test::hex_grid(1, 1, 1);
  mesh.hexes[0][5] = 8;
  EXPECT_THROW(hex_boundary_quads(mesh), InputError);
}

TEST(Pillow, BoxGridGetsOneLayerOffsetByTheDepth) {
  const HexMesh mesh = test::hex_grid(2, 3, 1);
  const double depth = 0.25;
  std::vector<Index> copied_from;
  std::vector<std::uint8_t> is_outer;
  const HexMesh padded = pillow(mesh, depth, &copied_from, &is_outer);
  const auto old_quads = hex_boundary_quads(mesh);
  ASSERT_EQ(old_quads.size(), 22u);  // 2 * (2*3 + 2*1 + 3*1)
  EXPECT_EQ(padded.hexes.size(), mesh.hexes.size() + old_quads.size());
  // Every point of a one-layer grid is on the boundary: each gets a copy.
  ASSERT_EQ(padded.points.size(), 2 * mesh.points.size());
  ASSERT_EQ(copied_from.size(), padded.points.size());
  ASSERT_EQ(is_outer.size(), padded.points.size());

  for (std::size_t h = 0; h < padded.hexes.size(); ++h) {
    std::array<Vec3, 8> p;
    for (int i = 0; i < 8; ++i) p[i] = padded.points[padded.hexes[h][i]];
    const auto sj = hex_scaled_jacobian(p);
    ASSERT_TRUE(sj.has_value()) << h;
    EXPECT_GT(*sj, 0.0) << h;
  }

  const auto new_quads = hex_boundary_quads(padded);
  EXPECT_EQ(new_quads.size(), old_quads.size());
  for (const auto& q : new_quads)
    for (const Index v : q) EXPECT_EQ(is_outer[v], 1) << v;

  const Vec3 lo(0, 0, 0), hi(2, 3, 1);
  for (std::size_t v = 0; v < padded.points.size(); ++v) {
    const Vec3& old = mesh.points[copied_from[v]];
    if (is_outer[v]) {
      EXPECT_EQ(padded.points[v], old) << v;  // the copy keeps the old position
      continue;
    }
    EXPECT_EQ(copied_from[v], v);
    // Inward by the depth along every axis whose box face the point is on: a box corner
    // moves by the depth on all three axes.
    Vec3 expected = old;
    for (int axis = 0; axis < 3; ++axis) {
      if (old[axis] == lo[axis]) expected[axis] += depth;
      if (old[axis] == hi[axis]) expected[axis] -= depth;
    }
    EXPECT_NEAR((padded.points[v] - expected).norm(), 0.0, 1e-12) << v;
  }

  for (const int count : boundary_faces_per_hex(padded)) EXPECT_LE(count, 1);
}

TEST(Pillow, ConcaveEdgeMovesInwardThroughBothPlanes) {
  // The L's reflex edge at x = y = 1: its faces have normals +x and +y, so the inward offset
  // is (-depth, -depth) there, and every face plane moves by exactly the depth.
  const HexMesh mesh = l_shape();
  const double depth = 0.2;
  std::vector<std::uint8_t> is_outer;
  const HexMesh padded = pillow(mesh, depth, nullptr, &is_outer);
  EXPECT_EQ(padded.hexes.size(), mesh.hexes.size() + hex_boundary_quads(mesh).size());
  const Index reflex_bottom = 4;  // point (1, 1, 0) of the 3x3x2 lattice
  ASSERT_EQ(mesh.points[reflex_bottom], Vec3(1, 1, 0));
  EXPECT_NEAR((padded.points[reflex_bottom] - Vec3(1 - depth, 1 - depth, depth)).norm(), 0.0, 1e-12);
  for (const auto& hex : padded.hexes) {
    std::array<Vec3, 8> p;
    for (int i = 0; i < 8; ++i) p[i] = padded.points[hex[i]];
    EXPECT_GT(hex_scaled_jacobian(p).value_or(-1), 0.0);
  }
  for (const int count : boundary_faces_per_hex(padded)) EXPECT_LE(count, 1);
}

TEST(Pillow, RejectsANonPositiveDepth) {
  const HexMesh mesh = test::hex_grid(1, 1, 1);
  EXPECT_THROW(pillow(mesh, 0.0), InputError);
  EXPECT_THROW(pillow(mesh, -1.0), InputError);
}

}  // namespace
}  // namespace structmesh
