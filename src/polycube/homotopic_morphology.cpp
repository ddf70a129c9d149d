// homotopic_erode / dilate / open / close: the homotopic morphological operations of
// §4.4.2 inside a box of voxels.
//
// The dissertation removes a voxel when its cells collapse onto the rest of the set
// ("simple removal", Fig. 4.6) and adds one when it collapses onto the complement; the
// (26, 6) simple point test decides the same (simple_voxel.cpp). On top of that a flip
// must leave no critical configuration around the voxel, so the boundary stays a
// 2-manifold (well_composed.cpp): the surface of the voxels is the polycube P, and a
// non-manifold edge or vertex would not be one. The work is done on bit rows
// (voxel_window.hpp); an opening's dilations restore only voxels its erosions removed,
// and a closing's erosions remove only voxels its dilations added, so that voxels
// outside the box, which never flip, do not seed growth inside it (without that, an
// opening of a box on a flat face grows a rim along the box's edge instead of leaving
// the face alone).
//
// Written by hand: no Debian-packaged library does topology-preserving voxel morphology
// (ITK and OpenVDB morphology ignore topology; DGtal, which has simple points, is not
// packaged).
#include "structmesh/polycube.hpp"
#include "voxel_window.hpp"

namespace structmesh {
namespace {

template <class Operation>
std::size_t in_window(VoxelGrid& grid, const VoxelBox& box, Operation&& operation) {
  voxel::VoxelWindow window;
  if (!window.load(grid, box)) return 0;
  operation(window);
  return window.store(grid);
}

}  // namespace

std::size_t homotopic_erode(VoxelGrid& grid, const VoxelBox& box) {
  return in_window(grid, box, [](voxel::VoxelWindow& window) { return window.erode(); });
}

std::size_t homotopic_dilate(VoxelGrid& grid, const VoxelBox& box) {
  return in_window(grid, box, [](voxel::VoxelWindow& window) { return window.dilate(); });
}

std::size_t homotopic_open(VoxelGrid& grid, const VoxelBox& box, int layers) {
  return in_window(grid, box, [&](voxel::VoxelWindow& window) { return window.open(layers); });
}

std::size_t homotopic_close(VoxelGrid& grid, const VoxelBox& box, int layers) {
  return in_window(grid, box, [&](voxel::VoxelWindow& window) { return window.close(layers); });
}

}  // namespace structmesh
