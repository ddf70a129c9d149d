// make_well_composed(): removes the critical configurations (voxels meeting only
// along an edge or at a vertex) that a voxelization leaves, so the polycube's surface
// is a 2-manifold, an orthogonal polyhedron (§4.2). Only simple voxels flip, so the
// topology the Morse resolution of §4.4.1 preserved is kept.
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"

#include "polycube/voxel_neighbourhood.hpp"

#include <array>
#include <string>
#include <vector>

namespace structmesh {

namespace {

// Critical blocks around the grid vertices (vx, vy, vz) with lo <= v <= hi per axis; the
// block around a vertex holds voxels vx - 1 .. vx (and so on).
int critical_blocks_between(const VoxelGrid& grid, const std::array<int, 3>& lo, const std::array<int, 3>& hi) {
  int critical = 0;
  for (int vz = lo[2]; vz <= hi[2]; ++vz)
    for (int vy = lo[1]; vy <= hi[1]; ++vy)
      for (int vx = lo[0]; vx <= hi[0]; ++vx) {
        unsigned block = 0;
        for (int b = 0; b < 8; ++b)
          if (grid.at(vx - 1 + (b & 1), vy - 1 + ((b >> 1) & 1), vz - 1 + ((b >> 2) & 1))) block |= 1u << b;
        critical += voxel::block_is_critical(block) ? 1 : 0;
      }
  return critical;
}

// Critical blocks among the eight 2x2x2 blocks that contain voxel (x, y, z): those around
// its corners, grid vertices x .. x + 1 per axis.
int critical_blocks_around(const VoxelGrid& grid, int x, int y, int z) {
  return critical_blocks_between(grid, {x, y, z}, {x + 1, y + 1, z + 1});
}

bool flippable(const VoxelGrid& grid, int u, int v, int w) {
  // The outermost layer stays empty: the grid keeps its empty border.
  return u > 0 && v > 0 && w > 0 && u < grid.dims[0] - 1 && v < grid.dims[1] - 1 && w < grid.dims[2] - 1 &&
         is_simple_voxel(grid, u, v, w);
}

// Up to `depth` simple flips in a row, each within the 3x3x3 neighbourhood of the one
// before (the first within that of (x, y, z)), kept when together they lower the number
// of critical blocks below `before`. Some configurations need more than one flip (two
// voxels meeting along an edge where either addition alone would close a tunnel or
// make a new critical block); each flip is simple when made, so the sequence keeps the
// topology. Returns the number of flips kept (0: none found).
int resolve_by_flip_sequence(VoxelGrid& grid, int x, int y, int z, int depth, int before, const std::array<int, 3>& lo,
                             const std::array<int, 3>& hi) {
  for (int d = 0; d < 27; ++d) {
    const int u = x + d % 3 - 1, v = y + (d / 3) % 3 - 1, w = z + d / 9 - 1;
    if (!flippable(grid, u, v, w)) continue;
    const bool value = !grid.at(u, v, w);
    grid.set(u, v, w, value);
    if (critical_blocks_between(grid, lo, hi) < before) return 1;
    if (depth > 1)
      if (const int more = resolve_by_flip_sequence(grid, u, v, w, depth - 1, before, lo, hi)) return more + 1;
    grid.set(u, v, w, !value);
  }
  return 0;
}

int resolve_by_flip_sequence(VoxelGrid& grid, int x, int y, int z) {
  constexpr int kDepth = 3;
  // Every block a flip at Chebyshev distance <= kDepth of (x, y, z) touches.
  const std::array<int, 3> lo{x - kDepth, y - kDepth, z - kDepth}, hi{x + kDepth + 1, y + kDepth + 1, z + kDepth + 1};
  for (int depth = 2; depth <= kDepth; ++depth)
    if (const int flips = resolve_by_flip_sequence(grid, x, y, z, depth, critical_blocks_between(grid, lo, hi), lo, hi))
      return flips;
  return 0;
}

}  // namespace

std::size_t make_well_composed(VoxelGrid& grid) {
  std::size_t flips = 0;
  std::vector<std::array<int, 3>> bad;
  // A flip changes only the eight blocks around the flipped voxel and is accepted only
  // when fewer of them are critical, so the number of critical blocks falls with each
  // accepted flip. When no such flip is left, a patient pass also accepts additions that
  // keep the count (a configuration may need two voxels added); the count never rises
  // and between two falls only additions happen, so the loop ends.
  for (bool patient = false;;) {
    bad.clear();
    for (int z = 0; z < grid.dims[2]; ++z)
      for (int y = 0; y < grid.dims[1]; ++y)
        for (int x = 0; x < grid.dims[0]; ++x)
          if (grid.at(x, y, z) && !is_well_composed_near(grid, x, y, z)) bad.push_back({x, y, z});
    if (bad.empty()) return flips;
    bool progress = false;
    for (const auto& [x, y, z] : bad) {
      if (is_well_composed_near(grid, x, y, z)) continue;  // an earlier flip resolved it
      // The voxels of the eight blocks around (x, y, z): additions first (they
      // thicken an edge or vertex contact into a face contact), then removals.
      bool resolved = false;
      for (const bool add : {true, false}) {
        if (patient && !add) continue;
        for (int dz = -1; dz <= 1 && !resolved; ++dz)
          for (int dy = -1; dy <= 1 && !resolved; ++dy)
            for (int dx = -1; dx <= 1 && !resolved; ++dx) {
              const int u = x + dx, v = y + dy, w = z + dz;
              if (grid.at(u, v, w) == add || !flippable(grid, u, v, w)) continue;
              const int before = critical_blocks_around(grid, u, v, w);
              if (before == 0) continue;  // flipping it cannot resolve anything here
              grid.set(u, v, w, add);
              const int after = critical_blocks_around(grid, u, v, w);
              if (after < before || (patient && after == before)) {
                resolved = true;
                ++flips;
              } else {
                grid.set(u, v, w, !add);
              }
            }
      }
      progress = progress || resolved;
    }
    if (!progress && !patient) {
      patient = true;
      continue;
    }
    patient = false;
    if (!progress) {
      for (const auto& [x, y, z] : bad)
        if (!is_well_composed_near(grid, x, y, z))
          if (const int sequence = resolve_by_flip_sequence(grid, x, y, z)) {
            progress = true;
            flips += static_cast<std::size_t>(sequence);
          }
      if (progress) continue;
      throw Error("make_well_composed: " + std::to_string(bad.size()) +
                  " voxels touch others only along an edge or at a corner and no simple flip resolves them (first at " +
                  std::to_string(bad.front()[0]) + ", " + std::to_string(bad.front()[1]) + ", " +
                  std::to_string(bad.front()[2]) + ")");
    }
  }
}

}  // namespace structmesh
