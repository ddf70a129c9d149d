// polycube_hex_grid(): the tensor-product grid of a polycube's facet planes.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace structmesh {
namespace {

VoxelGrid filled(std::array<int, 3> dims, double size) {
  VoxelGrid grid(dims, Vec3(1, 2, 3), size);
  std::fill(grid.occupied.begin(), grid.occupied.end(), 1);
  return grid;
}

double hex_volume(const HexMesh& mesh) {
  double volume = 0;
  for (const auto& h : mesh.hexes) {
    const Vec3 d = mesh.points[h[6]] - mesh.points[h[0]];  // axis-aligned boxes here
    volume += d.x() * d.y() * d.z();
  }
  return volume;
}

/// Every hex a perfect box (scaled Jacobian 1), every interior face shared by exactly two.
void expect_valid_grid(const HexMesh& mesh) {
  const HexQuality quality = hex_quality(mesh);
  EXPECT_EQ(quality.inverted, 0u);
  EXPECT_EQ(quality.invalid, 0u);
  EXPECT_NEAR(quality.scaled_jacobian_stats.min, 1.0, 1e-12);
  const FaceAdjacency<4> faces = build_faces(mesh);
  EXPECT_TRUE(faces.extra_cells.empty());
  std::vector<std::uint8_t> used(mesh.points.size(), 0);
  for (const auto& h : mesh.hexes)
    for (Index v : h) used[v] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);  // no unused point
}

TEST(PolycubeHexGrid, BoxIsOneCubeOrAPerfectGrid) {
  const VoxelGrid box = filled({3, 2, 1}, 0.5);
  // One layer per slab: the box's only facets are its six sides.
  const HexMesh one = polycube_hex_grid(box, 0);
  ASSERT_EQ(one.hexes.size(), 1u);
  expect_valid_grid(one);
  EXPECT_NEAR(hex_volume(one), 1.5 * 1.0 * 0.5, 1e-12);
  // Hex size = voxel size: one hex per voxel.
  const HexMesh per_voxel = polycube_hex_grid(box, 0.5);
  EXPECT_EQ(per_voxel.hexes.size(), 6u);
  EXPECT_EQ(per_voxel.points.size(), 4u * 3 * 2);
  expect_valid_grid(per_voxel);
  // Layers round to the nearest count: 1.5 / 0.4 = 3.75 -> 4, 1.0 / 0.4 = 2.5 -> 3 (lround), 0.5 / 0.4 -> 1.
  const HexMesh rounded = polycube_hex_grid(box, 0.4);
  EXPECT_EQ(rounded.hexes.size(), 4u * 3 * 1);
  expect_valid_grid(rounded);
  EXPECT_NEAR(hex_volume(rounded), 0.75, 1e-12);
}

TEST(PolycubeHexGrid, LShapeCutsAtItsFacetPlanes) {
  // An L in the xy plane: 4 x 4 voxels minus the 2 x 2 top-right block, 1 voxel thick.
  VoxelGrid grid = filled({4, 4, 1}, 1.0);
  for (int x = 2; x < 4; ++x)
    for (int y = 2; y < 4; ++y) grid.set(x, y, 0, false);
  const HexMesh coarse = polycube_hex_grid(grid, 0);
  // Planes x = 0, 2, 4 and y = 0, 2, 4: 2 x 2 cells, 3 inside.
  EXPECT_EQ(coarse.hexes.size(), 3u);
  expect_valid_grid(coarse);
  EXPECT_NEAR(hex_volume(coarse), 12.0, 1e-12);
  const HexMesh fine = polycube_hex_grid(grid, 0.5);
  EXPECT_EQ(fine.hexes.size(), 12u * 4 * 2);
  expect_valid_grid(fine);
  EXPECT_NEAR(hex_volume(fine), 12.0, 1e-12);
  // Coordinates are lattice positions of the voxel grid.
  for (const Vec3& p : coarse.points)
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(p[a] - grid.origin[a], std::round(p[a] - grid.origin[a]), 1e-12);
}

TEST(PolycubeHexGrid, CountMatchesTheGrid) {
  // An L with a hole-free notch in z as well, at several sizes.
  VoxelGrid grid = filled({5, 4, 3}, 1.0);
  for (int x = 2; x < 5; ++x)
    for (int y = 2; y < 4; ++y) grid.set(x, y, 2, false);
  grid.set(0, 0, 0, false);
  for (const double size : {0.0, 0.3, 0.5, 1.0, 1.7, 10.0}) {
    SCOPED_TRACE(size);
    const HexMesh mesh = polycube_hex_grid(grid, size);
    const PolycubeGridCount count = polycube_hex_count(grid, size);
    EXPECT_EQ(count.hexes, mesh.hexes.size());
    EXPECT_EQ(count.boundary_quads, hex_boundary_quads(mesh).size());
  }
  EXPECT_EQ(polycube_hex_count(VoxelGrid({2, 2, 2}, Vec3::Zero(), 1.0), 1.0).hexes, 0u);
  // A tiny size asks for a huge grid; counting it costs nothing.
  EXPECT_GT(polycube_hex_count(grid, 1e-4).hexes, std::size_t{1} << 40);
}

TEST(PolycubeHexGrid, EmptyAndBadInput) {
  VoxelGrid empty({2, 2, 2}, Vec3::Zero(), 1.0);
  EXPECT_TRUE(polycube_hex_grid(empty, 1.0).hexes.empty());
  EXPECT_THROW(polycube_hex_grid(filled({1, 1, 1}, 1.0), -1), InputError);
  EXPECT_THROW(polycube_hex_grid(filled({1, 1, 1}, 1.0), std::nan("")), InputError);
}

}  // namespace
}  // namespace structmesh
