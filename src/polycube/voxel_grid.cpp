// VoxelGrid::count(): the number of occupied voxels (§4.4: the voxel set whose union of
// closed cubes is the polycube).
#include "structmesh/polycube.hpp"

#include <algorithm>

namespace structmesh {

std::size_t VoxelGrid::count() const {
  return static_cast<std::size_t>(
      std::count_if(occupied.begin(), occupied.end(), [](std::uint8_t value) { return value != 0; }));
}

}  // namespace structmesh
