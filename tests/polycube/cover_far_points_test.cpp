// cover_far_points(): a block with a tail thinner than a voxel, which voxelize() drops
// whole (no voxel centre falls in it, and the topology does not notice), gets the tail
// back as voxels the tail passes through, attached to the block, the topology kept; a
// shape every vertex of which a voxel reaches is left alone. build_polycube() keeps the
// tail through the optimisation (the coverage guard of optimize_polycube()).
#include "polycube/voxel_checks.hpp"
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"
#include "structmesh/solids.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace structmesh {
namespace {

constexpr double kVoxel = 2.5;

/// A 6 x 6 x 6 block of unit cells with a tail of `length` cells (12 voxels of 2.5 for
/// the default), one cell thick, along +x.
TriMesh block_with_tail(int length = 30) {
  std::vector<std::array<int, 3>> cells;
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i) cells.push_back({i, j, k});
  for (int i = 6; i < 6 + length; ++i) cells.push_back({i, 2, 2});
  return voxel_union_surface(cells, 1);
}

/// Whether an occupied voxel lies within `radius` voxels (by index) of p's voxel.
bool reached(const VoxelGrid& grid, const Vec3& p, int radius) {
  std::array<int, 3> c{};
  for (int a = 0; a < 3; ++a) c[a] = static_cast<int>(std::floor((p[a] - grid.origin[a]) / grid.size));
  for (int dz = -radius; dz <= radius; ++dz)
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx)
        if (grid.at(c[0] + dx, c[1] + dy, c[2] + dz)) return true;
  return false;
}

std::size_t unreached(const VoxelGrid& grid, const TriMesh& surface, int radius) {
  return static_cast<std::size_t>(std::count_if(surface.points.begin(), surface.points.end(),
                                                [&](const Vec3& p) { return !reached(grid, p, radius); }));
}

TEST(CoverFarPoints, BringsBackATailThinnerThanAVoxel) {
  const TriMesh shape = block_with_tail();
  VoxelGrid grid = voxelize(shape, kVoxel);
  const VoxelGrid before = grid;
  // What this test is about: the tail's end has no voxel within one voxel.
  ASSERT_GT(unreached(grid, shape, 1), 0u);
  const VoxelTopology topology = voxel_topology(grid);
  ASSERT_EQ(topology.components, 1);

  const std::size_t added = cover_far_points(grid, shape);
  EXPECT_GT(added, 0u);
  EXPECT_EQ(grid.count(), before.count() + added);
  const VoxelTopology after = voxel_topology(grid);
  EXPECT_EQ(after.components, 1);
  EXPECT_EQ(after.handles, 0);
  EXPECT_EQ(after.voids, 0);
  EXPECT_EQ(unreached(grid, shape, 1), 0u);
  // Only voxels are added, each one the tail (y, z in [2, 3]) passes through, beyond the block.
  test::expect_only_additions(before, grid, [&](int x, int y, int z) {
    const Vec3 lo = grid.vertex_position(x, y, z), hi = grid.vertex_position(x + 1, y + 1, z + 1);
    EXPECT_TRUE(lo.y() <= 3 && hi.y() >= 2 && lo.z() <= 3 && hi.z() >= 2 && hi.x() >= 6) << x << " " << y << " " << z;
  });
}

TEST(CoverFarPoints, LeavesAShapeEveryVertexOfWhichIsReachedAsItWas) {
  std::vector<std::array<int, 3>> cells;
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i) cells.push_back({i, j, k});
  const TriMesh block = voxel_union_surface(cells, 2);
  VoxelGrid grid = voxelize(block, 1.0);
  const VoxelGrid before = grid;
  EXPECT_EQ(cover_far_points(grid, block), 0u);
  EXPECT_EQ(grid.occupied, before.occupied);
  EXPECT_THROW(cover_far_points(grid = VoxelGrid{}, block), InputError);
}

TEST(CoverFarPoints, LeavesATailOfAFewVoxelsToTheProjection) {
  // 4 voxels long: no vertex is 5 voxels from every voxel, so nothing is added (such a
  // tip is the rounding of a curved surface, which the hex mesh's projection covers).
  const TriMesh shape = block_with_tail(10);
  VoxelGrid grid = voxelize(shape, kVoxel);
  ASSERT_GT(unreached(grid, shape, 1), 0u);
  const VoxelGrid before = grid;
  EXPECT_EQ(cover_far_points(grid, shape), 0u);
  EXPECT_EQ(grid.occupied, before.occupied);
}

TEST(BuildPolycube, KeepsATailThinnerThanAVoxel) {
  PolycubeOptions options;
  options.align = false;
  options.deformation.max_iterations = 0;
  options.voxel_size = kVoxel;
  options.merge_planes_within = 0;
  const TriMesh shape = block_with_tail();
  const PolycubeResult result = build_polycube(shape, options);
  EXPECT_GT(result.far_point_voxels, 0u);
  EXPECT_EQ(result.final.components, 1);
  EXPECT_EQ(result.final.handles, 0);
  EXPECT_EQ(result.final.voids, 0);
  EXPECT_TRUE(is_well_composed(result.voxels));
  // After the optimisation every vertex still has a voxel within the guard's 3 voxels.
  EXPECT_EQ(unreached(result.voxels, shape, 3), 0u);
  // Plane merging (not guarded) moves facets by up to 2 voxels more.
  options.merge_planes_within = 2;
  const PolycubeResult merged = build_polycube(shape, options);
  EXPECT_EQ(unreached(merged.voxels, shape, 5), 0u);
  EXPECT_EQ(merged.final.components, 1);
}

}  // namespace
}  // namespace structmesh
