// is_well_composed(), is_well_composed_near(): whether the boundary of the voxel union
// is a 2-manifold (§4.4.2: a polycube surface must be one, and the homotopic
// operations keep it so).
//
// A voxel set is well-composed (Latecki 1997) when no 2x2x2 block of voxels holds a
// critical configuration: a face of the block (the four voxels around a grid edge) with
// exactly one diagonal pair occupied, or exactly two antipodal voxels of one state and
// the other six of the other. Every 2x2 square around a grid edge is a face of the block
// around either end of the edge, so checking the blocks around all grid vertices checks
// everything; the blocks that contain one voxel are those around its eight corners,
// inside its 3x3x3 neighbourhood.
//
// Written by hand: no Debian-packaged library tests voxel sets for well-composedness.
#include "structmesh/polycube.hpp"
#include "voxel_neighbourhood.hpp"

#include <array>

namespace structmesh {
namespace voxel {
namespace {

constexpr std::array<bool, 256> kCritical = [] {
  std::array<bool, 256> table{};
  for (unsigned block = 0; block < 256; ++block) table[block] = block_is_critical(block);
  return table;
}();

}  // namespace

bool is_well_composed_configuration(std::uint32_t config) {
  for (int bz = 0; bz < 2; ++bz)
    for (int by = 0; by < 2; ++by)
      for (int bx = 0; bx < 2; ++bx)
        if (kCritical[block_of_configuration(config, bx, by, bz)]) return false;
  return true;
}

}  // namespace voxel

bool is_well_composed(const VoxelGrid& grid) {
  bool well_composed = true;
  voxel::for_each_vertex_block(grid, [&](int, int, int, unsigned block) {
    if (voxel::kCritical[block]) well_composed = false;
  });
  return well_composed;
}

bool is_well_composed_near(const VoxelGrid& grid, int x, int y, int z) {
  return voxel::is_well_composed_configuration(voxel::neighbourhood(grid, x, y, z));
}

}  // namespace structmesh
