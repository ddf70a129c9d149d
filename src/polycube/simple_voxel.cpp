// is_simple_voxel(): whether flipping one voxel keeps the topology of the voxel union
// and of its complement (§4.4.2, "simple removal"; §4.5.1).
//
// The dissertation decides removability by collapsing the voxel's cells onto its
// neighbours (simple removals on the cubical complex). For the union of closed cubes
// (26-adjacency of voxels, 6-adjacency of the empty space) that collapse succeeds
// exactly when the voxel is a (26, 6) simple point (Bertrand and Malandain 1994;
// Kong and Rosenfeld 1989): the occupied voxels of its 26-neighbourhood form one
// 26-connected component (T26 = 1), and the empty voxels of its 18-neighbourhood that
// are 6-adjacent to it lie in one 6-connected component within that 18-neighbourhood
// (T6 = 1). Both counts are flood fills on a 27-bit mask, done here with shifts. On all
// 2^26 neighbourhoods the test agrees with comparing the Betti numbers of the 3x3x3
// block with and without the voxel (checked exhaustively once; the unit tests sample).
//
// Written by hand: no library packaged for Debian offers simple-point tests or
// homotopic voxel morphology (DGtal, which has them, is not packaged).
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"
#include "voxel_neighbourhood.hpp"

#include <string>

namespace structmesh {
namespace voxel {
namespace {

/// The bits of the 27-bit configuration whose offset along the axis of `stride` (1, 3
/// or 9) is `value`.
constexpr std::uint32_t layer(int stride, int value) {
  std::uint32_t mask = 0;
  for (int i = 0; i < 27; ++i)
    if ((i / stride) % 3 == value) mask |= 1u << i;
  return mask;
}

/// Shifts along one axis; the destination mask drops the bits that wrapped into the
/// next row or fell off the 3x3x3 cube. The masks are constants (template arguments),
/// not loops at run time.
template <int Stride>
constexpr std::uint32_t shift_up(std::uint32_t m) {
  constexpr std::uint32_t kKeep = kAllNeighbourhood & ~layer(Stride, 0);
  return (m << Stride) & kKeep;
}
template <int Stride>
constexpr std::uint32_t shift_down(std::uint32_t m) {
  constexpr std::uint32_t kKeep = kAllNeighbourhood & ~layer(Stride, 2);
  return (m >> Stride) & kKeep;
}

template <int Stride>
constexpr std::uint32_t dilate_axis(std::uint32_t m) {
  return m | shift_up<Stride>(m) | shift_down<Stride>(m);
}
/// 26-neighbours: the 3x3x3 cube is the product of three 1D dilations.
constexpr std::uint32_t dilate26(std::uint32_t m) { return dilate_axis<9>(dilate_axis<3>(dilate_axis<1>(m))); }
/// 6-neighbours: the union of the three 1D dilations.
constexpr std::uint32_t dilate6(std::uint32_t m) {
  return m | shift_up<1>(m) | shift_down<1>(m) | shift_up<3>(m) | shift_down<3>(m) | shift_up<9>(m) | shift_down<9>(m);
}

constexpr std::uint32_t kFaceNeighbours = dilate6(kCentre) & ~kCentre;
/// The 18-neighbourhood minus the centre: the 27 bits without the 8 cube corners.
constexpr std::uint32_t kN18 = [] {
  std::uint32_t mask = 0;
  for (int i = 0; i < 27; ++i) {
    const int off = (i % 3 != 1) + ((i / 3) % 3 != 1) + (i / 9 != 1);
    if (off == 1 || off == 2) mask |= 1u << i;
  }
  return mask;
}();

/// Grows `seed` inside `allowed` to its connected component under `dilate`.
template <class Dilate>
std::uint32_t component(std::uint32_t seed, std::uint32_t allowed, Dilate dilate) {
  for (;;) {
    const std::uint32_t grown = dilate(seed) & allowed;
    if (grown == seed) return seed;
    seed = grown;
  }
}

}  // namespace

bool is_simple_configuration(std::uint32_t config) {
  // T26: the occupied 26-neighbours form exactly one 26-component (none: the voxel is
  // isolated, and removing or adding it changes the component count).
  const std::uint32_t occupied = config & kAllNeighbourhood & ~kCentre;
  if (occupied == 0) return false;
  if (component(occupied & (~occupied + 1), occupied, [](std::uint32_t m) { return dilate26(m); }) != occupied)
    return false;
  // T6: the empty 18-neighbours that are face neighbours lie in one 6-component within
  // the empty 18-neighbours (none: the voxel is interior, and adding or removing it
  // opens or closes a cavity).
  const std::uint32_t empty = ~config & kN18;
  const std::uint32_t seeds = empty & kFaceNeighbours;
  if (seeds == 0) return false;
  return (seeds & ~component(seeds & (~seeds + 1), empty, [](std::uint32_t m) { return dilate6(m); })) == 0;
}

int occupied_components(std::uint32_t config, std::array<std::uint32_t, 26>& components) {
  std::uint32_t left = config & kAllNeighbourhood & ~kCentre;
  int count = 0;
  while (left != 0) {
    const std::uint32_t part = component(left & (~left + 1), left, [](std::uint32_t m) { return dilate26(m); });
    components[count++] = part;
    left &= ~part;
  }
  return count;
}

int empty_face_components(std::uint32_t config) {
  const std::uint32_t empty = ~config & kN18;
  std::uint32_t seeds = empty & kFaceNeighbours;
  int count = 0;
  while (seeds != 0) {
    seeds &= ~component(seeds & (~seeds + 1), empty, [](std::uint32_t m) { return dilate6(m); });
    ++count;
  }
  return count;
}

}  // namespace voxel

bool is_simple_voxel(const VoxelGrid& grid, int x, int y, int z) {
  if (!grid.inside(x, y, z))
    throw InputError("is_simple_voxel: voxel (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                     std::to_string(z) + ") is outside the grid");
  return voxel::is_simple_configuration(voxel::neighbourhood(grid, x, y, z));
}

}  // namespace structmesh
