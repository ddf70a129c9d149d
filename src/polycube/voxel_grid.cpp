// VoxelGrid's queries (§4.4: the voxel set whose union of closed cubes is the polycube):
// count(), the number of occupied voxels; voxel_of(), the voxel holding a point;
// occupied_within(), whether a voxel is occupied in a block around one.
#include "structmesh/polycube.hpp"

#include <algorithm>
#include <cmath>

namespace structmesh {

std::size_t VoxelGrid::count() const {
  return static_cast<std::size_t>(
      std::count_if(occupied.begin(), occupied.end(), [](std::uint8_t value) { return value != 0; }));
}

std::array<int, 3> VoxelGrid::voxel_of(const Vec3& p) const {
  std::array<int, 3> voxel{};
  for (int a = 0; a < 3; ++a)
    voxel[a] = std::clamp(static_cast<int>(std::floor((p[a] - origin[a]) / size)), 0, dims[a] - 1);
  return voxel;
}

bool VoxelGrid::occupied_within(int x, int y, int z, int radius) const {
  for (int dz = -radius; dz <= radius; ++dz)
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx)
        if (at(x + dx, y + dy, z + dz)) return true;
  return false;
}

}  // namespace structmesh
