// Helpers of the volumetric map's tests: a tet mesh of a closed surface, and the tets a map
// inverts.
#pragma once

#include "structmesh/mesh.hpp"
#include "structmesh/quality.hpp"
#include "structmesh/tetmesh.hpp"

#include <vector>

namespace structmesh::test {

/// TetGen's tet mesh of `surface` (surface points first), tets about 0.25 long.
inline TetMesh solid(const TriMesh& surface) {
  TetmeshOptions options;
  options.size = 0.25;
  return tetrahedralize(surface, options).mesh;
}

/// Tets of `tets` with non-positive volume when their corners are at `points`.
inline std::size_t flipped(const TetMesh& tets, const std::vector<Vec3>& points) {
  std::size_t count = 0;
  for (const auto& t : tets.tets)
    if (!(tet_signed_volume(points, t) > 0)) ++count;
  return count;
}

}  // namespace structmesh::test
