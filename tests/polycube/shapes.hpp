// Closed test surfaces for the polycube tests.
#pragma once

#include "structmesh/mesh.hpp"

#include <cmath>
#include <numbers>

namespace structmesh::test {

/// Torus around the z axis (radii R, r), `u` x `v` vertices, vertex 0 at (R + r, 0, 0).
inline TriMesh torus(double big, double small, int u, int v) {
  TriMesh mesh;
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      const double a = 2 * std::numbers::pi * i / u, b = 2 * std::numbers::pi * j / v;
      mesh.points.emplace_back((big + small * std::cos(b)) * std::cos(a), (big + small * std::cos(b)) * std::sin(a),
                               small * std::sin(b));
    }
  const auto id = [&](int i, int j) { return static_cast<Index>(((i + u) % u) * v + (j + v) % v); };
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return mesh;
}

}  // namespace structmesh::test
