// polycube_hex_grid(): the regular hex structure Omega_H on the polycube domain (§5.3,
// "Hexahedral Remeshing").
//
// A voxel polycube has its facets on lattice planes, but a hex per voxel is rarely the size
// a user asks for. The grid here is the tensor product of the polycube's own facet planes:
// between two consecutive x-planes that carry an x-facet somewhere, occupancy does not
// change along x (a change would be an x-facet), so the slab can take any number of layers
// and every cell is wholly inside or outside. Each slab gets max(1, round(thickness / h))
// layers: the hex count follows h except where the polycube itself has thinner slabs.
//
// Written by hand: it is three 1-D subdivisions and a lookup of one voxel per cell.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace structmesh {
namespace {

/// The lattice coordinates (0 .. dims[axis]) where some voxel face perpendicular to `axis`
/// separates occupied from empty, plus the ends of the occupied range.
std::vector<int> facet_planes(const VoxelGrid& grid, int axis) {
  std::vector<std::uint8_t> has_facet(static_cast<std::size_t>(grid.dims[axis]) + 1, 0);
  for (int z = 0; z < grid.dims[2]; ++z)
    for (int y = 0; y < grid.dims[1]; ++y)
      for (int x = 0; x < grid.dims[0]; ++x) {
        std::array<int, 3> v{x, y, z};
        const bool here = grid.occupied[grid.index(x, y, z)] != 0;
        std::array<int, 3> w = v;
        --w[axis];
        const bool below = grid.at(w[0], w[1], w[2]);
        if (here != below) has_facet[static_cast<std::size_t>(v[axis])] = 1;
        if (v[axis] == grid.dims[axis] - 1 && here) has_facet[static_cast<std::size_t>(grid.dims[axis])] = 1;
      }
  std::vector<int> planes;
  for (int i = 0; i <= grid.dims[axis]; ++i)
    if (has_facet[static_cast<std::size_t>(i)]) planes.push_back(i);
  return planes;
}

/// Per axis: the facet planes and each slab's layer count.
struct Slabs {
  std::array<std::vector<int>, 3> planes;
  std::array<std::vector<int>, 3> layers;  // per slab (planes[a][p] .. planes[a][p + 1])
};

Slabs slabs_of(const VoxelGrid& grid, double hex_size) {
  if (!(hex_size >= 0) || !std::isfinite(hex_size))
    throw InputError("polycube_hex_grid: hex size must be finite and >= 0, got " + std::to_string(hex_size));
  Slabs slabs;
  for (int axis = 0; axis < 3; ++axis) {
    slabs.planes[axis] = facet_planes(grid, axis);
    const auto& planes = slabs.planes[axis];
    for (std::size_t p = 0; p + 1 < planes.size(); ++p) {
      const double thickness = (planes[p + 1] - planes[p]) * grid.size;
      // Capped so that a tiny size cannot ask for more layers than 2^20 per slab.
      const double wanted = hex_size > 0 ? std::min(thickness / hex_size, double{1 << 20}) : 1.0;
      slabs.layers[axis].push_back(std::max(1, static_cast<int>(std::lround(wanted))));
    }
  }
  return slabs;
}

}  // namespace

PolycubeGridCount polycube_hex_count(const VoxelGrid& grid, double hex_size) {
  PolycubeGridCount count;
  if (grid.count() == 0) return count;
  const Slabs slabs = slabs_of(grid, hex_size);
  const std::array<std::size_t, 3> n{slabs.layers[0].size(), slabs.layers[1].size(), slabs.layers[2].size()};
  auto occupied = [&](std::array<std::ptrdiff_t, 3> c) {
    for (int a = 0; a < 3; ++a)
      if (c[a] < 0 || c[a] >= static_cast<std::ptrdiff_t>(n[a])) return false;
    return grid.at(slabs.planes[0][static_cast<std::size_t>(c[0])], slabs.planes[1][static_cast<std::size_t>(c[1])],
                   slabs.planes[2][static_cast<std::size_t>(c[2])]);
  };
  for (std::size_t k = 0; k < n[2]; ++k)
    for (std::size_t j = 0; j < n[1]; ++j)
      for (std::size_t i = 0; i < n[0]; ++i) {
        const std::array<std::ptrdiff_t, 3> c{static_cast<std::ptrdiff_t>(i), static_cast<std::ptrdiff_t>(j),
                                              static_cast<std::ptrdiff_t>(k)};
        if (!occupied(c)) continue;
        const std::array<std::size_t, 3> l{static_cast<std::size_t>(slabs.layers[0][i]),
                                           static_cast<std::size_t>(slabs.layers[1][j]),
                                           static_cast<std::size_t>(slabs.layers[2][k])};
        count.hexes += l[0] * l[1] * l[2];
        for (int axis = 0; axis < 3; ++axis)
          for (const int side : {-1, 1}) {
            std::array<std::ptrdiff_t, 3> d = c;
            d[axis] += side;
            if (!occupied(d)) count.boundary_quads += l[(axis + 1) % 3] * l[(axis + 2) % 3];
          }
      }
  return count;
}

HexMesh polycube_hex_grid(const VoxelGrid& grid, double hex_size) {
  HexMesh mesh;
  const Slabs slabs = slabs_of(grid, hex_size);
  if (grid.count() == 0) return mesh;
  // Per axis: grid coordinates (in lattice units, fractional) of every layer boundary, and
  // for each layer the voxel index it lies in.
  std::array<std::vector<double>, 3> coordinate;
  std::array<std::vector<int>, 3> voxel_of_layer;
  for (int axis = 0; axis < 3; ++axis) {
    const auto& planes = slabs.planes[axis];
    for (std::size_t p = 0; p + 1 < planes.size(); ++p) {
      const int a = planes[p], b = planes[p + 1], layers = slabs.layers[axis][p];
      for (int l = 0; l < layers; ++l) {
        coordinate[axis].push_back(a + (b - a) * static_cast<double>(l) / layers);
        // Occupancy is constant across the slab: its first voxel stands for it.
        voxel_of_layer[axis].push_back(a);
      }
    }
    coordinate[axis].push_back(planes.back());
  }
  const std::array<std::size_t, 3> n{coordinate[0].size(), coordinate[1].size(), coordinate[2].size()};
  const std::size_t lattice = n[0] * n[1] * n[2];
  std::vector<Index> point_of(lattice, kInvalidIndex);
  auto lattice_index = [&](std::size_t i, std::size_t j, std::size_t k) { return i + n[0] * (j + n[1] * k); };
  auto point = [&](std::size_t i, std::size_t j, std::size_t k) {
    Index& id = point_of[lattice_index(i, j, k)];
    if (id == kInvalidIndex) {
      if (mesh.points.size() >= kInvalidIndex) throw InputError("polycube_hex_grid: more than 2^32 - 1 points");
      id = static_cast<Index>(mesh.points.size());
      mesh.points.push_back(grid.origin + grid.size * Vec3(coordinate[0][i], coordinate[1][j], coordinate[2][k]));
    }
    return id;
  };
  for (std::size_t k = 0; k + 1 < n[2]; ++k)
    for (std::size_t j = 0; j + 1 < n[1]; ++j)
      for (std::size_t i = 0; i + 1 < n[0]; ++i) {
        if (!grid.at(voxel_of_layer[0][i], voxel_of_layer[1][j], voxel_of_layer[2][k])) continue;
        // VTK order: bottom face counter-clockwise seen from +z, then the top face.
        mesh.hexes.push_back({point(i, j, k), point(i + 1, j, k), point(i + 1, j + 1, k), point(i, j + 1, k),
                              point(i, j, k + 1), point(i + 1, j, k + 1), point(i + 1, j + 1, k + 1),
                              point(i, j + 1, k + 1)});
      }
  return mesh;
}

}  // namespace structmesh
