#include "structmesh/mesh.hpp"

#include <algorithm>
#include <tuple>

namespace structmesh {

BoundingBox3 bounding_box(std::span<const Vec3> points) {
  BoundingBox3 box;
  for (const Vec3& p : points) box.extend(p);
  return box;
}

BoundingBox2 bounding_box(std::span<const Vec2> points) {
  BoundingBox2 box;
  for (const Vec2& p : points) box.extend(p);
  return box;
}

void Polygon2::add_ring(std::span<const Vec2> ring_points) {
  points.insert(points.end(), ring_points.begin(), ring_points.end());
  ring_offsets.push_back(static_cast<Index>(points.size()));
}

double signed_area(std::span<const Vec2> ring) {
  // Shoelace formula relative to the first point, which keeps the sum well
  // conditioned for coordinates far from the origin (lon/lat, UTM).
  if (ring.size() < 3) return 0.0;
  const Vec2 origin = ring[0];
  double twice_area = 0.0;
  for (std::size_t i = 1; i + 1 < ring.size(); ++i) {
    const Vec2 a = ring[i] - origin;
    const Vec2 b = ring[i + 1] - origin;
    twice_area += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * twice_area;
}

double area(const Polygon2& polygon) {
  double total = 0.0;
  for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
    const double a = std::abs(signed_area(polygon.ring(r)));
    total += r == 0 ? a : -a;
  }
  return total;
}

namespace {

// Rows of a CSR from (row, item) pairs sorted by row then item.
CompressedRows rows_from_pairs(const std::vector<std::pair<Index, Index>>& pairs, std::size_t row_count) {
  CompressedRows rows;
  rows.offsets.assign(row_count + 1, 0);
  for (const auto& [row, item] : pairs) ++rows.offsets[row + 1];
  for (std::size_t i = 0; i < row_count; ++i) rows.offsets[i + 1] += rows.offsets[i];
  rows.items.resize(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) rows.items[i] = pairs[i].second;
  return rows;
}

// Edges from a per-element edge table: sort (a, b, element) triples once.
template <std::size_t N, std::size_t E>
EdgeAdjacency edges_from_table(std::span<const std::array<Index, N>> elements,
                               const std::array<std::array<int, 2>, E>& table) {
  struct Entry {
    Index a, b, element;
  };
  std::vector<Entry> entries;
  entries.reserve(elements.size() * E);
  for (std::size_t c = 0; c < elements.size(); ++c) {
    for (const auto& [i, j] : table) {
      const Index u = elements[c][i], v = elements[c][j];
      if (u == v) continue;  // a collapsed edge is not an edge
      entries.push_back({std::min(u, v), std::max(u, v), static_cast<Index>(c)});
    }
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return std::tie(x.a, x.b, x.element) < std::tie(y.a, y.b, y.element);
  });
  EdgeAdjacency adjacency;
  adjacency.edge_elements.items.reserve(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const bool new_edge = k == 0 || entries[k].a != entries[k - 1].a || entries[k].b != entries[k - 1].b;
    if (new_edge) {
      if (k != 0) adjacency.edge_elements.offsets.push_back(static_cast<Index>(adjacency.edge_elements.items.size()));
      adjacency.edges.push_back({entries[k].a, entries[k].b});
    } else if (entries[k].element == entries[k - 1].element) {
      continue;  // the same element lists this edge twice (only in degenerate elements)
    }
    adjacency.edge_elements.items.push_back(entries[k].element);
  }
  if (!entries.empty())
    adjacency.edge_elements.offsets.push_back(static_cast<Index>(adjacency.edge_elements.items.size()));
  return adjacency;
}

constexpr std::array<std::array<int, 2>, 3> kTriangleEdges{{{0, 1}, {1, 2}, {2, 0}}};
constexpr std::array<std::array<int, 2>, 4> kQuadEdges{{{0, 1}, {1, 2}, {2, 3}, {3, 0}}};

template <std::size_t N, std::size_t F, std::size_t K>
FaceAdjacency<N> faces_from_table(std::span<const std::array<Index, K>> cells,
                                  const std::array<std::array<int, N>, F>& table) {
  struct Entry {
    std::array<Index, N> key;  // sorted vertex ids
    Index cell;
    std::uint8_t local;
  };
  std::vector<Entry> entries;
  entries.reserve(cells.size() * F);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    for (std::size_t f = 0; f < F; ++f) {
      Entry e{};
      for (std::size_t i = 0; i < N; ++i) e.key[i] = cells[c][table[f][i]];
      std::sort(e.key.begin(), e.key.end());
      e.cell = static_cast<Index>(c);
      e.local = static_cast<std::uint8_t>(f);
      entries.push_back(e);
    }
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return std::tie(x.key, x.cell, x.local) < std::tie(y.key, y.cell, y.local);
  });
  FaceAdjacency<N> adjacency;
  for (std::size_t k = 0; k < entries.size();) {
    std::size_t end = k + 1;
    while (end < entries.size() && entries[end].key == entries[k].key) ++end;
    const Index face = static_cast<Index>(adjacency.faces.size());
    std::array<Index, N> oriented{};
    for (std::size_t i = 0; i < N; ++i) oriented[i] = cells[entries[k].cell][table[entries[k].local][i]];
    adjacency.faces.push_back(oriented);
    adjacency.face_cells.push_back({entries[k].cell, end > k + 1 ? entries[k + 1].cell : kInvalidIndex});
    for (std::size_t x = k + 2; x < end; ++x) {
      adjacency.extra_cells.push_back(entries[x].cell);
      adjacency.extra_faces.push_back(face);
    }
    k = end;
  }
  return adjacency;
}

template <std::size_t N>
CompressedRows vertex_elements(std::span<const std::array<Index, N>> elements, std::size_t point_count) {
  CompressedRows rows;
  rows.offsets.assign(point_count + 1, 0);
  for (const auto& e : elements)
    for (std::size_t i = 0; i < N; ++i)
      if (e[i] < point_count) ++rows.offsets[e[i] + 1];
  for (std::size_t i = 0; i < point_count; ++i) rows.offsets[i + 1] += rows.offsets[i];
  rows.items.resize(rows.offsets.back());
  std::vector<Index> fill(rows.offsets.begin(), rows.offsets.end() - 1);
  // Elements are visited in ascending order, so every row comes out sorted;
  // an element that repeats a vertex is listed once in that vertex's row.
  for (std::size_t c = 0; c < elements.size(); ++c) {
    for (std::size_t i = 0; i < N; ++i) {
      const Index v = elements[c][i];
      if (v >= point_count) continue;
      if (fill[v] > rows.offsets[v] && rows.items[fill[v] - 1] == c) continue;
      rows.items[fill[v]++] = static_cast<Index>(c);
    }
  }
  // Compact rows shortened by repeated vertices.
  std::size_t write = 0;
  for (std::size_t v = 0; v < point_count; ++v) {
    const std::size_t begin = rows.offsets[v];
    rows.offsets[v] = static_cast<Index>(write);
    for (std::size_t k = begin; k < fill[v]; ++k) rows.items[write++] = rows.items[k];
  }
  rows.offsets[point_count] = static_cast<Index>(write);
  rows.items.resize(write);
  return rows;
}

}  // namespace

EdgeAdjacency build_edges(const TriMesh& mesh) { return edges_from_table<3>(mesh.triangles, kTriangleEdges); }
EdgeAdjacency build_edges(const QuadMesh& mesh) { return edges_from_table<4>(mesh.quads, kQuadEdges); }
EdgeAdjacency build_edges(const TetMesh& mesh) { return edges_from_table<4>(mesh.tets, kTetEdges); }
EdgeAdjacency build_edges(const HexMesh& mesh) { return edges_from_table<8>(mesh.hexes, kHexEdges); }

FaceAdjacency<3> build_faces(const TetMesh& mesh) { return faces_from_table<3>(std::span(mesh.tets), kTetFaces); }
FaceAdjacency<4> build_faces(const HexMesh& mesh) { return faces_from_table<4>(std::span(mesh.hexes), kHexFaces); }

CompressedRows build_vertex_elements(std::span<const std::array<Index, 3>> elements, std::size_t point_count) {
  return vertex_elements<3>(elements, point_count);
}
CompressedRows build_vertex_elements(std::span<const std::array<Index, 4>> elements, std::size_t point_count) {
  return vertex_elements<4>(elements, point_count);
}
CompressedRows build_vertex_elements(std::span<const std::array<Index, 8>> elements, std::size_t point_count) {
  return vertex_elements<8>(elements, point_count);
}

CompressedRows build_vertex_neighbors(const EdgeAdjacency& edges, std::size_t point_count) {
  std::vector<std::pair<Index, Index>> pairs;
  pairs.reserve(edges.edges.size() * 2);
  for (const auto& [a, b] : edges.edges) {
    if (a >= point_count || b >= point_count) continue;
    pairs.emplace_back(a, b);
    pairs.emplace_back(b, a);
  }
  std::sort(pairs.begin(), pairs.end());
  return rows_from_pairs(pairs, point_count);
}

}  // namespace structmesh
