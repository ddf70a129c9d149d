// Tessellation builders for the cell graph and graph partitioning tests: grids of unit
// squares (optionally with missing squares = holes, optionally several squares per
// cell) and patches of regular hexagons (the Voronoi diagram of a triangular lattice,
// so interior vertices are 3-valent with 120° sectors like a generic CVT).
//
// All builders are O(n log n) and deterministic, so they also serve as larger graphs
// (e.g. 100 x 100) for the partitioning tests. Names differ from those of
// part_geometry_fixtures.hpp so both headers can be included in one test file.
#pragma once

#include "partition2d/partition_internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

namespace structmesh::partition2d::testing {

/// A tessellation from counter-clockwise polygons (normalised coordinates), one per
/// face. Vertices are merged when their coordinates agree to 1e-9 (so irrational
/// coordinates computed along different faces still merge); twins are matched by
/// vertex pairs. Every region-boundary half-edge gets boundary_ring 0.
/// `face_cell` empty = one cell per face; otherwise cell_count = max + 1.
inline Tessellation polygon_tessellation(const std::vector<std::vector<Vec2>>& faces,
                                         const std::vector<Index>& face_cell = {}) {
  Tessellation t;
  std::map<std::pair<std::int64_t, std::int64_t>, Index> vertex_id;
  for (const auto& face : faces) {
    for (const Vec2& p : face) {
      const std::pair<std::int64_t, std::int64_t> key{std::llround(p.x() * 1e9), std::llround(p.y() * 1e9)};
      const auto [it, inserted] = vertex_id.try_emplace(key, static_cast<Index>(t.vertices.size()));
      if (inserted) {
        t.vertices.push_back(p);
        t.input_vertex.push_back(-1);
      }
      t.face_vertices.push_back(it->second);
    }
    t.face_offsets.push_back(static_cast<Index>(t.face_vertices.size()));
  }
  if (face_cell.empty()) {
    for (std::size_t f = 0; f < faces.size(); ++f) t.face_cell.push_back(static_cast<Index>(f));
    t.cell_count = faces.size();
  } else {
    t.face_cell = face_cell;
    Index max_cell = 0;
    for (Index c : face_cell) max_cell = std::max(max_cell, c);
    t.cell_count = face_cell.empty() ? 0 : static_cast<std::size_t>(max_cell) + 1;
  }
  const auto key = [](Index a, Index b) { return (static_cast<std::uint64_t>(a) << 32) | b; };
  std::unordered_map<std::uint64_t, Index> half_edge;
  half_edge.reserve(t.face_vertices.size());
  for (Index f = 0; f < t.face_count(); ++f)
    for (Index h = t.face_offsets[f]; h < t.face_offsets[f + 1]; ++h)
      half_edge[key(t.face_vertices[h], t.face_vertices[t.next(h, f)])] = h;
  t.twin.assign(t.face_vertices.size(), kInvalidIndex);
  t.boundary_ring.assign(t.face_vertices.size(), -1);
  for (Index f = 0; f < t.face_count(); ++f)
    for (Index h = t.face_offsets[f]; h < t.face_offsets[f + 1]; ++h) {
      const auto it = half_edge.find(key(t.face_vertices[t.next(h, f)], t.face_vertices[h]));
      if (it != half_edge.end())
        t.twin[h] = it->second;
      else
        t.boundary_ring[h] = 0;
    }
  return t;
}

/// Column i, row j of a grid square.
struct GridSquare {
  int i = 0, j = 0;
  bool operator==(const GridSquare&) const = default;
};

/// An nx x ny grid of unit squares with lower-left corner (0, 0). Faces row by row,
/// squares listed in `missing` left out (they become holes, or notches on the
/// boundary): without missing squares face = j * nx + i. `cell_of(i, j)` gives the
/// cell of a square (default: one cell per face, in face order). boundary_ring is 0
/// on the outer rectangle and 1 on every other boundary edge (the holes).
inline Tessellation grid_tessellation(int nx, int ny, const std::vector<GridSquare>& missing = {},
                                      const std::function<Index(int, int)>& cell_of = {}) {
  std::vector<std::vector<Vec2>> faces;
  std::vector<Index> face_cell;
  std::vector<std::uint8_t> skip(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0);
  for (const GridSquare& s : missing)
    if (s.i >= 0 && s.i < nx && s.j >= 0 && s.j < ny) skip[static_cast<std::size_t>(s.j) * nx + s.i] = 1;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (skip[static_cast<std::size_t>(j) * nx + i]) continue;
      const Vec2 p(i, j);
      faces.push_back({p, p + Vec2(1, 0), p + Vec2(1, 1), p + Vec2(0, 1)});
      face_cell.push_back(cell_of ? cell_of(i, j) : static_cast<Index>(face_cell.size()));
    }
  Tessellation t = polygon_tessellation(faces, face_cell);
  for (Index f = 0; f < t.face_count(); ++f)
    for (Index h = t.face_offsets[f]; h < t.face_offsets[f + 1]; ++h) {
      if (t.twin[h] != kInvalidIndex) continue;
      const Vec2 &a = t.vertices[t.face_vertices[h]], &b = t.vertices[t.face_vertices[t.next(h, f)]];
      const bool outer = (a.x() == 0 && b.x() == 0) || (a.x() == nx && b.x() == nx) || (a.y() == 0 && b.y() == 0) ||
                         (a.y() == ny && b.y() == ny);
      t.boundary_ring[h] = outer ? 0 : 1;
    }
  return t;
}

/// Centre of hexagon (column q, row r) of hex_tessellation.
inline Vec2 hex_center(int q, int r) { return {std::sqrt(3.0) * (q + 0.5 * (r & 1)), 1.5 * r}; }

/// `rows` rows of `cols` pointy-top regular hexagons of circumradius 1 (edge length 1),
/// odd rows shifted right by half a hexagon; face (= cell) index = r * cols + q.
/// Interior vertices have three 120° sectors; boundary vertices have one or two
/// hexagons. Vertex k of a hexagon is at angle 30° + 60° k from its centre.
inline Tessellation hex_tessellation(int cols, int rows) {
  std::vector<std::vector<Vec2>> faces;
  const double pi = std::acos(-1.0);
  for (int r = 0; r < rows; ++r)
    for (int q = 0; q < cols; ++q) {
      const Vec2 c = hex_center(q, r);
      std::vector<Vec2> face;
      for (int k = 0; k < 6; ++k) {
        const double a = pi / 6 + k * pi / 3;
        face.push_back(c + Vec2(std::cos(a), std::sin(a)));
      }
      faces.push_back(face);
    }
  return polygon_tessellation(faces);
}

/// The cell graph of an nx x ny grid of unit squares (node = face = j * nx + i).
inline CellGraph grid_graph(int nx, int ny, double contraction_length = 1e-3) {
  return build_cell_graph(grid_tessellation(nx, ny), contraction_length);
}

}  // namespace structmesh::partition2d::testing
