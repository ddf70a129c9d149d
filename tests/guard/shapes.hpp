// Closed test surfaces for the guarding tests: unions of unit voxels and (bumpy)
// icospheres, all outward-oriented.
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

namespace structmesh::test {

using Cell = std::array<int, 3>;

/// Boundary of a union of unit cubes [i, i+1] x [j, j+1] x [k, k+1], each boundary
/// square cut into n x n smaller squares (n = `subdivisions`), each split along its
/// 0-2 diagonal. Manifold when no two cells touch only along an edge or at a corner.
inline TriMesh voxel_surface(const std::vector<Cell>& cells, int subdivisions = 1) {
  const int n = subdivisions;
  const std::set<Cell> filled(cells.begin(), cells.end());
  TriMesh mesh;
  std::map<Cell, Index> ids;  // positions in units of 1 / n
  const auto vertex = [&](const Cell& c) {
    const auto [it, inserted] = ids.emplace(c, static_cast<Index>(mesh.points.size()));
    if (inserted) mesh.points.emplace_back(double(c[0]) / n, double(c[1]) / n, double(c[2]) / n);
    return it->second;
  };
  for (const Cell& cell : filled)
    for (int axis = 0; axis < 3; ++axis)
      for (const int side : {-1, 1}) {
        Cell neighbour = cell;
        neighbour[axis] += side;
        if (filled.count(neighbour) != 0) continue;
        // e_u x e_w = e_axis: corners base, +u, +u+w, +w face +axis.
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) {
            Cell base{cell[0] * n, cell[1] * n, cell[2] * n};
            if (side > 0) base[axis] += n;
            base[u] += i;
            base[w] += j;
            Cell c1 = base, c2 = base, c3 = base;
            c1[u] += 1;
            c2[u] += 1;
            c2[w] += 1;
            c3[w] += 1;
            std::array<Index, 4> q{vertex(base), vertex(c1), vertex(c2), vertex(c3)};
            if (side < 0) std::swap(q[1], q[3]);
            mesh.triangles.push_back({q[0], q[1], q[2]});
            mesh.triangles.push_back({q[0], q[2], q[3]});
          }
      }
  return mesh;
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
/// vertex then moved to radius radius(direction).
template <class Radius>
TriMesh icosphere(int subdivisions, Radius radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriMesh mesh;
  for (const auto& p : std::vector<Vec3>{{-1, t, 0},
                                         {1, t, 0},
                                         {-1, -t, 0},
                                         {1, -t, 0},
                                         {0, -1, t},
                                         {0, 1, t},
                                         {0, -1, -t},
                                         {0, 1, -t},
                                         {t, 0, -1},
                                         {t, 0, 1},
                                         {-t, 0, -1},
                                         {-t, 0, 1}})
    mesh.points.push_back(p.normalized());
  mesh.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<Index, Index>, Index> middle;
    const auto mid = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = middle.emplace(key, static_cast<Index>(mesh.points.size()));
      if (inserted) mesh.points.push_back((mesh.points[a] + mesh.points[b]).normalized());
      return it->second;
    };
    std::vector<std::array<Index, 3>> next;
    for (const auto& [a, b, c] : mesh.triangles) {
      const Index ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.push_back({a, ab, ca});
      next.push_back({b, bc, ab});
      next.push_back({c, ca, bc});
      next.push_back({ab, bc, ca});
    }
    mesh.triangles = std::move(next);
  }
  for (Vec3& p : mesh.points) p *= radius(p);
  return mesh;
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
