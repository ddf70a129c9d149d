// Closed test surfaces for the guarding tests: unions of unit voxels and (bumpy)
// icospheres, all outward-oriented.
#pragma once

#include "structmesh/mesh.hpp"
#include "structmesh/solids.hpp"

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

namespace structmesh::test {

using Cell = std::array<int, 3>;

/// Boundary of a union of unit cubes (structmesh::voxel_union_surface()), each boundary
/// square cut into n x n smaller squares (n = `subdivisions`).
inline TriMesh voxel_surface(const std::vector<Cell>& cells, int subdivisions = 1) {
  return structmesh::voxel_union_surface(cells, subdivisions);
}

/// The 12 cells of a 4 x 4 square ring one cell thick: a solid torus (genus 1).
inline std::vector<Cell> ring_cells() {
  std::vector<Cell> ring;
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      if (x == 0 || x == 3 || y == 0 || y == 3) ring.push_back({x, y, 0});
  return ring;
}

/// Icosphere of radius 1 about the origin after `subdivisions` 4:1 splits, with every
/// vertex then moved to radius radius(direction) (structmesh::icosphere()).
template <class Radius>
TriMesh icosphere(int subdivisions, Radius radius) {
  return structmesh::icosphere(subdivisions, std::function<double(const Vec3&)>(radius));
}

inline TriMesh unit_icosphere(int subdivisions) {
  return icosphere(subdivisions, [](const Vec3&) { return 1.0; });
}

/// A star-shaped but strongly non-convex blob: radius 1 + 0.45 sin(3x) sin(3y) sin(3z)
/// over the unit sphere's directions (bumps and dents that hide each other).
inline TriMesh bumpy_sphere(int subdivisions) {
  return icosphere(subdivisions, [](const Vec3& d) {
    return 1.0 + 0.45 * std::sin(3 * d.x() + 0.3) * std::sin(3 * d.y() + 0.5) * std::sin(3 * d.z() + 0.7);
  });
}

}  // namespace structmesh::test
