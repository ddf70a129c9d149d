// voxel_boundary(), polycube_corners(): the polycube surface P of §4.4 (the boundary of
// the voxel union) and its corner count, the E_c of energy (4.1).
//
// A boundary grid vertex is one whose eight voxels are neither all occupied nor all
// empty; it is a corner when boundary faces of all three axis directions meet there.
// On a well-composed set those are exactly the surface vertices of valence other than
// 4, the dissertation's definition (tests/polycube/voxel_test.cpp checks it). Both are
// read off the 2x2x2 block around the vertex (voxel_neighbourhood.hpp).
//
// Written by hand: a quad per occupied/empty face pair with shared grid vertices is a
// few lines; no library offers it with the corner flags.
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"
#include "voxel_neighbourhood.hpp"

#include <array>
#include <limits>
#include <string>
#include <vector>

namespace structmesh {
namespace {

/// The six faces of a voxel: the neighbour's offset and the face's corners as vertex
/// offsets from the voxel's lowest corner, counter-clockwise seen from the neighbour
/// (so the quad's normal points from the occupied voxel to the empty one).
struct VoxelFace {
  std::array<int, 3> neighbour;
  std::array<std::array<int, 3>, 4> corners;
};
constexpr std::array<VoxelFace, 6> kVoxelFaces{{
    {{-1, 0, 0}, {{{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}}},
    {{1, 0, 0}, {{{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}}},
    {{0, -1, 0}, {{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}}},
    {{0, 1, 0}, {{{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}}},
    {{0, 0, -1}, {{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}}},
    {{0, 0, 1}, {{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}}},
}};

}  // namespace

QuadMesh voxel_boundary(const VoxelGrid& grid, std::vector<std::uint8_t>* corner) {
  QuadMesh mesh;
  if (corner) corner->clear();
  // Boundary vertices numbered in vertex_index order.
  std::vector<Index> point_of_vertex(grid.vertex_count(), kInvalidIndex);
  voxel::for_each_vertex_block(grid, [&](int vx, int vy, int vz, unsigned block) {
    if (!voxel::block_is_boundary(block)) return;
    if (mesh.points.size() >= kInvalidIndex) throw InputError("voxel_boundary: more than 2^32 - 1 boundary vertices");
    point_of_vertex[grid.vertex_index(vx, vy, vz)] = static_cast<Index>(mesh.points.size());
    mesh.points.push_back(grid.vertex_position(vx, vy, vz));
    if (corner) corner->push_back(voxel::block_is_corner(block) ? 1 : 0);
  });
  for (int z = 0; z < grid.dims[2]; ++z)
    for (int y = 0; y < grid.dims[1]; ++y)
      for (int x = 0; x < grid.dims[0]; ++x) {
        if (!grid.occupied[grid.index(x, y, z)]) continue;
        for (const VoxelFace& face : kVoxelFaces) {
          if (grid.at(x + face.neighbour[0], y + face.neighbour[1], z + face.neighbour[2])) continue;
          std::array<Index, 4> quad;
          for (int k = 0; k < 4; ++k)
            quad[k] = point_of_vertex[grid.vertex_index(x + face.corners[k][0], y + face.corners[k][1],
                                                        z + face.corners[k][2])];
          mesh.quads.push_back(quad);
        }
      }
  return mesh;
}

std::size_t polycube_corners(const VoxelGrid& grid) {
  std::size_t corners = 0;
  voxel::for_each_vertex_block(grid, [&](int, int, int, unsigned block) { corners += voxel::block_is_corner(block); });
  return corners;
}

}  // namespace structmesh
