// Small structured meshes for the quality tests.
#pragma once

#include "structmesh/mesh.hpp"

#include <cmath>
#include <map>
#include <utility>

namespace structmesh::test {

/// nx by ny unit quads in the z = 0 plane, counter-clockwise.
inline QuadMesh quad_grid(int nx, int ny) {
  QuadMesh mesh;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) mesh.points.emplace_back(i, j, 0);
  const auto id = [nx](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) mesh.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return mesh;
}

/// nx by ny by nz unit hexes, VTK order.
inline HexMesh hex_grid(int nx, int ny, int nz) {
  HexMesh mesh;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) mesh.points.emplace_back(i, j, k);
  const auto id = [&](int i, int j, int k) { return static_cast<Index>((k * (ny + 1) + j) * (nx + 1) + i); };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        mesh.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                              id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  return mesh;
}

/// A regular polygon with `sides` corners split into `sides` quads around its centre
/// (corner, edge midpoint, centre, previous edge midpoint): the centre has valence
/// `sides`, every other vertex is on the boundary.
inline QuadMesh polygon_fan(int sides) {
  QuadMesh mesh;
  mesh.points.emplace_back(0, 0, 0);
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * 3.14159265358979323846 * i / sides;
    mesh.points.emplace_back(std::cos(a), std::sin(a), 0);
  }
  for (int i = 0; i < sides; ++i) mesh.points.push_back(0.5 * (mesh.points[1 + i] + mesh.points[1 + (i + 1) % sides]));
  for (int i = 0; i < sides; ++i) {
    const Index corner = 1 + i, next_mid = 1 + sides + i, previous_mid = 1 + sides + (i + sides - 1) % sides;
    mesh.quads.push_back({corner, next_mid, 0, previous_mid});
  }
  return mesh;
}

/// Splits every quad into 4 (edge midpoints and centre): new vertices are regular,
/// old ones keep their valence.
inline QuadMesh subdivide(const QuadMesh& mesh) {
  QuadMesh out;
  out.points = mesh.points;
  std::map<std::pair<Index, Index>, Index> midpoints;
  const auto midpoint = [&](Index a, Index b) {
    const auto key = std::minmax(a, b);
    const auto [it, inserted] = midpoints.emplace(key, static_cast<Index>(out.points.size()));
    if (inserted) out.points.push_back(0.5 * (mesh.points[a] + mesh.points[b]));
    return it->second;
  };
  for (const auto& q : mesh.quads) {
    const Index centre = static_cast<Index>(out.points.size());
    out.points.push_back(0.25 * (mesh.points[q[0]] + mesh.points[q[1]] + mesh.points[q[2]] + mesh.points[q[3]]));
    std::array<Index, 4> mid{};
    for (int i = 0; i < 4; ++i) mid[i] = midpoint(q[i], q[(i + 1) % 4]);
    for (int i = 0; i < 4; ++i) out.quads.push_back({q[i], mid[i], centre, mid[(i + 3) % 4]});
  }
  return out;
}

/// Extrudes a planar quad mesh into `layers` unit layers of hexes.
inline HexMesh extrude(const QuadMesh& base, int layers) {
  HexMesh mesh;
  const Index n = static_cast<Index>(base.points.size());
  for (int k = 0; k <= layers; ++k)
    for (const Vec3& p : base.points) mesh.points.push_back(p + Vec3(0, 0, k));
  for (int k = 0; k < layers; ++k)
    for (const auto& q : base.quads) {
      const Index lo = static_cast<Index>(k) * n, hi = lo + n;
      mesh.hexes.push_back({lo + q[0], lo + q[1], lo + q[2], lo + q[3], hi + q[0], hi + q[1], hi + q[2], hi + q[3]});
    }
  return mesh;
}

}  // namespace structmesh::test
