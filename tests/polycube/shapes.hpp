// Closed test surfaces for the polycube tests.
#pragma once

#include "structmesh/mesh.hpp"
#include "structmesh/solids.hpp"

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

namespace structmesh::test {

/// Torus around the z axis (radii R, r), `u` x `v` vertices, vertex 0 at (R + r, 0, 0).
inline TriMesh torus(double big, double small, int u, int v) { return structmesh::torus_surface(big, small, u, v); }

/// The unit cube, two outward triangles per face; triangle 2 is (4, 5, 6) on the top face.
inline TriMesh unit_cube() {
  TriMesh cube;
  for (int k = 0; k < 2; ++k) {
    cube.points.emplace_back(0, 0, k);
    cube.points.emplace_back(1, 0, k);
    cube.points.emplace_back(1, 1, k);
    cube.points.emplace_back(0, 1, k);
  }
  cube.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                    {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  return cube;
}

/// A box [0, a] x [0, b] x [0, c] with each face cut into n x n squares (two triangles each).
inline TriMesh subdivided_box(double a, double b, double c, int n) {
  TriMesh mesh;
  std::map<std::array<int, 3>, Index> ids;
  const auto vertex = [&](std::array<int, 3> k) {
    const auto [it, inserted] = ids.emplace(k, static_cast<Index>(mesh.points.size()));
    if (inserted) mesh.points.emplace_back(a * k[0] / n, b * k[1] / n, c * k[2] / n);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (const int side : {0, n}) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<int, 3> p0{}, p1{}, p2{}, p3{};
          p0[axis] = p1[axis] = p2[axis] = p3[axis] = side;
          p0[u] = i, p0[w] = j;
          p1[u] = i + 1, p1[w] = j;
          p2[u] = i + 1, p2[w] = j + 1;
          p3[u] = i, p3[w] = j + 1;
          std::array<Index, 4> q{vertex(p0), vertex(p1), vertex(p2), vertex(p3)};
          if (side == 0) std::swap(q[1], q[3]);  // e_u x e_w = e_axis points out at the far side
          mesh.triangles.push_back({q[0], q[1], q[2]});
          mesh.triangles.push_back({q[0], q[2], q[3]});
        }
    }
  return mesh;
}

/// A UV sphere of radius r (poles as single vertices).
inline TriMesh sphere(double r, int rings, int segments) {
  TriMesh mesh;
  mesh.points.emplace_back(0, 0, -r);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double polar = std::numbers::pi * i / rings, a = 2 * std::numbers::pi * j / segments;
      mesh.points.emplace_back(r * std::sin(polar) * std::cos(a), r * std::sin(polar) * std::sin(a),
                               -r * std::cos(polar));
    }
  mesh.points.emplace_back(0, 0, r);
  const auto id = [&](int i, int j) { return static_cast<Index>(1 + (i - 1) * segments + (j + segments) % segments); };
  const auto top = static_cast<Index>(mesh.points.size() - 1);
  for (int j = 0; j < segments; ++j) {
    mesh.triangles.push_back({0, id(1, j + 1), id(1, j)});
    mesh.triangles.push_back({top, id(rings - 1, j), id(rings - 1, j + 1)});
  }
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      mesh.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
    }
  return mesh;
}

}  // namespace structmesh::test
