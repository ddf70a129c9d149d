// Internal: the local voxel configurations the voxel-set functions of polycube.hpp
// share.
//  - A 3x3x3 neighbourhood of a voxel is a 27-bit configuration, bit dx + 3*dy + 9*dz
//    for the voxel at offset (dx - 1, dy - 1, dz - 1); the centre is bit 13. The simple
//    point test and the local well-composedness test are functions of it alone.
//  - A 2x2x2 block of voxels around a grid vertex (vx, vy, vz) is an 8-bit
//    configuration, bit dx + 2*dy + 4*dz for voxel (vx - 1 + dx, vy - 1 + dy, vz - 1 + dz).
//    Whether the vertex is on the boundary, is a polycube corner, sits in a critical
//    configuration, and which cells of the cubical complex it is the lowest corner of,
//    are functions of it alone.
// Voxels outside the grid are empty throughout.
#pragma once

#include "structmesh/polycube.hpp"

#include <array>
#include <bit>
#include <cstdint>

namespace structmesh::voxel {

inline constexpr int kCentreBit = 13;
inline constexpr std::uint32_t kCentre = 1u << kCentreBit;
inline constexpr std::uint32_t kAllNeighbourhood = (1u << 27) - 1;

/// The 27-bit neighbourhood configuration of voxel (x, y, z) (which may be outside).
inline std::uint32_t neighbourhood(const VoxelGrid& grid, int x, int y, int z) {
  std::uint32_t config = 0;
  for (int dz = 0; dz < 3; ++dz)
    for (int dy = 0; dy < 3; ++dy)
      for (int dx = 0; dx < 3; ++dx)
        if (grid.at(x + dx - 1, y + dy - 1, z + dz - 1)) config |= 1u << (dx + 3 * dy + 9 * dz);
  return config;
}

/// The 2x2x2 block of a 27-bit configuration around corner (bx, by, bz) of the centre
/// voxel (offsets b + e, e in {0, 1}^3), as 8 bits, x fastest.
inline unsigned block_of_configuration(std::uint32_t config, int bx, int by, int bz) {
  const int base = bx + 3 * by + 9 * bz;
  return ((config >> base) & 3u) | (((config >> (base + 3)) & 3u) << 2) | (((config >> (base + 9)) & 3u) << 4) |
         (((config >> (base + 12)) & 3u) << 6);
}

/// The (26, 6) simple point test on a 27-bit configuration (the centre's bit is
/// ignored): T26 = 1 and T6 = 1. simple_voxel.cpp.
bool is_simple_configuration(std::uint32_t config);

/// The 26-connected components of the occupied voxels of a 27-bit configuration, the
/// centre left out (T26 counts them), as masks in `components`; returns how many.
/// simple_voxel.cpp.
int occupied_components(std::uint32_t config, std::array<std::uint32_t, 26>& components);

/// T6: the 6-connected components, within the empty 18-neighbours, that contain an empty
/// face neighbour of the centre. Occupying the centre with T6 = 0 fills a one-voxel void;
/// with T6 >= 2 it closes a tunnel or encloses a void. simple_voxel.cpp.
int empty_face_components(std::uint32_t config);

/// Whether none of the eight 2x2x2 blocks that contain the centre of a 27-bit
/// configuration is critical. well_composed.cpp.
bool is_well_composed_configuration(std::uint32_t config);

// ---------------------------------------------------------------------------
// 2x2x2 blocks

/// Critical configurations of well-composedness (Latecki): a face of the block (a 2x2
/// square of voxels around a grid edge) with exactly one diagonal pair occupied, or
/// exactly two antipodal voxels occupied, or exactly two antipodal voxels empty.
constexpr bool block_is_critical(unsigned block) {
  for (int axis = 0; axis < 3; ++axis) {
    const int u = 1 << ((axis + 1) % 3), v = 1 << ((axis + 2) % 3);
    for (int side = 0; side < 2; ++side) {
      const int base = side << axis;
      const bool b00 = (block >> base) & 1, b10 = (block >> (base + u)) & 1;
      const bool b01 = (block >> (base + v)) & 1, b11 = (block >> (base + u + v)) & 1;
      if (b00 == b11 && b10 == b01 && b00 != b10) return true;
    }
  }
  for (int i = 0; i < 4; ++i) {
    const unsigned pair = (1u << i) | (1u << (7 - i));
    if (block == pair || block == (0xFFu & ~pair)) return true;
  }
  return false;
}

/// Bit a of the result: some pair of voxels of the block adjacent along axis a differs,
/// i.e. a boundary face with normal along axis a meets the vertex.
constexpr unsigned block_face_axes(unsigned block) {
  unsigned axes = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (unsigned i = 0; i < 8; ++i)
      if (!(i & (1u << axis)) && ((block >> i) & 1) != ((block >> (i | (1u << axis))) & 1)) axes |= 1u << axis;
  return axes;
}

/// A polycube corner: boundary faces with normals along all three axes meet there.
constexpr bool block_is_corner(unsigned block) { return block_face_axes(block) == 7; }
/// A boundary vertex of the voxel union: some but not all of its eight voxels occupied.
constexpr bool block_is_boundary(unsigned block) { return block != 0 && block != 0xFF; }

/// The cells of the cubical complex of the voxel union whose lowest corner is the
/// vertex: the vertex itself, its +X, +Y and +Z edges, its XY, XZ and YZ squares, and
/// the cube of voxel (vx, vy, vz); each is present when one of its voxels (all in the
/// block) is occupied.
struct LowestCornerCells {
  int vertices = 0, edges = 0, squares = 0, cubes = 0;
};
constexpr LowestCornerCells lowest_corner_cells(unsigned block) {
  LowestCornerCells cells;
  cells.vertices = block != 0;
  cells.edges = ((block & 0xAA) != 0) + ((block & 0xCC) != 0) + ((block & 0xF0) != 0);
  cells.squares = ((block & 0x88) != 0) + ((block & 0xA0) != 0) + ((block & 0xC0) != 0);
  cells.cubes = (block & 0x80) != 0;
  return cells;
}

/// Calls visit(vx, vy, vz, block) for every grid vertex, vertex_index order, with the
/// 8-bit block configuration around it; one pass, four voxel reads per vertex.
template <class Visit>
void for_each_vertex_block(const VoxelGrid& grid, Visit&& visit) {
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  if (nx <= 0 || ny <= 0 || nz <= 0) return;
  for (int vz = 0; vz <= nz; ++vz)
    for (int vy = 0; vy <= ny; ++vy) {
      // The four voxel rows around the vertex row, k = dy + 2 * dz; null outside.
      std::array<const std::uint8_t*, 4> rows{};
      for (int k = 0; k < 4; ++k) {
        const int y = vy - 1 + (k & 1), z = vz - 1 + (k >> 1);
        rows[k] = (y >= 0 && y < ny && z >= 0 && z < nz) ? grid.occupied.data() + grid.index(0, y, z) : nullptr;
      }
      unsigned block = 0;
      for (int vx = 0; vx <= nx; ++vx) {
        // Shift the dx = 1 half to dx = 0 and read voxel column vx into dx = 1.
        block = (block >> 1) & 0x55u;
        if (vx < nx)
          for (int k = 0; k < 4; ++k)
            if (rows[k] && rows[k][vx]) block |= 1u << (1 + 2 * k);
        visit(vx, vy, vz, block);
      }
    }
}

}  // namespace structmesh::voxel
