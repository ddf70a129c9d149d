// voxel_topology(): cell counts, Euler characteristic (4.2) and Betti numbers of the
// union of the occupied closed cubes (§4.5.1), the invariants the homotopic operations
// of §4.4.2 must keep.
//
// Cells: every cell of the cubical complex is attributed to its lowest corner, so one
// pass over the grid vertices with the 2x2x2 block around each counts them all
// (voxel_neighbourhood.hpp). Betti numbers: b0 counts 26-components of the occupied
// voxels (closed cubes touching at a vertex are connected), b2 counts 6-components of
// the empty voxels other than the one around the grid (the empty space is open: it
// passes only through faces), and b1 = b0 + b2 - chi. The flood fills use an explicit
// stack on a copy of the grid with an empty layer around it (the outside) and a wall
// layer around that, so no neighbour needs a bounds test.
//
// Written by hand: no Debian-packaged library computes the homology of voxel sets
// with this (26, 6) adjacency pair.
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"
#include "voxel_neighbourhood.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace structmesh {
namespace {

constexpr std::uint8_t kEmpty = 0, kOccupied = 1, kDone = 2;  // kDone: visited, or the wall

/// Marks the component of `start` (all of state `state`) as done; neighbours by offset.
template <std::size_t N>
void flood(std::vector<std::uint8_t>& state, std::uint32_t start, std::uint8_t wanted,
           const std::array<std::int64_t, N>& offsets, std::vector<std::uint32_t>& stack) {
  state[start] = kDone;
  stack.assign(1, start);
  while (!stack.empty()) {
    const std::uint32_t cell = stack.back();
    stack.pop_back();
    for (const std::int64_t offset : offsets) {
      const auto next = static_cast<std::uint32_t>(cell + offset);
      if (state[next] == wanted) {
        state[next] = kDone;
        stack.push_back(next);
      }
    }
  }
}

}  // namespace

VoxelTopology voxel_topology(const VoxelGrid& grid) {
  VoxelTopology topology;
  voxel::for_each_vertex_block(grid, [&](int, int, int, unsigned block) {
    const voxel::LowestCornerCells cells = voxel::lowest_corner_cells(block);
    topology.vertices += cells.vertices;
    topology.edges += cells.edges;
    topology.squares += cells.squares;
    topology.cubes += cells.cubes;
  });
  topology.euler = topology.vertices - topology.edges + topology.squares - topology.cubes;
  if (topology.cubes == 0) return topology;

  // The grid inside an empty layer (the outside) inside a wall layer.
  const std::int64_t sx = grid.dims[0] + 4, sy = grid.dims[1] + 4, sz = grid.dims[2] + 4;
  if (sx * sy * sz > std::numeric_limits<std::uint32_t>::max())
    throw InputError("voxel_topology: a grid of " + std::to_string(grid.dims[0]) + " x " +
                     std::to_string(grid.dims[1]) + " x " + std::to_string(grid.dims[2]) +
                     " voxels is too large for 32-bit voxel indices");
  std::vector<std::uint8_t> state(static_cast<std::size_t>(sx * sy * sz), kDone);
  const auto padded = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::uint32_t>(x + sx * (y + sy * z));
  };
  for (std::int64_t z = 1; z < sz - 1; ++z)
    for (std::int64_t y = 1; y < sy - 1; ++y)
      for (std::int64_t x = 1; x < sx - 1; ++x)
        state[padded(x, y, z)] =
            grid.at(static_cast<int>(x - 2), static_cast<int>(y - 2), static_cast<int>(z - 2)) ? kOccupied : kEmpty;

  std::array<std::int64_t, 26> offsets26{};
  std::array<std::int64_t, 6> offsets6{};
  for (int i = 0, n26 = 0, n6 = 0; i < 27; ++i) {
    const int dx = i % 3 - 1, dy = (i / 3) % 3 - 1, dz = i / 9 - 1;
    if (i == voxel::kCentreBit) continue;
    const std::int64_t offset = dx + sx * (dy + sy * dz);
    offsets26[n26++] = offset;
    if (dx * dx + dy * dy + dz * dz == 1) offsets6[n6++] = offset;
  }

  std::vector<std::uint32_t> stack;
  // The empty layer is one 6-component, the outside; the first flood takes it.
  std::int64_t empty_components = 0;
  for (std::uint32_t cell = 0; cell < state.size(); ++cell) {
    if (state[cell] == kOccupied) {
      flood(state, cell, kOccupied, offsets26, stack);
      ++topology.components;
    } else if (state[cell] == kEmpty) {
      flood(state, cell, kEmpty, offsets6, stack);
      ++empty_components;
    }
  }
  topology.voids = empty_components - 1;
  topology.handles = topology.components + topology.voids - topology.euler;
  return topology;
}

}  // namespace structmesh
