#include "structmesh/mesh.hpp"
#include "structmesh/error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <string>
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

double enclosed_volume(const TriMesh& surface) {
  // Divergence theorem, relative to the box centre for conditioning.
  const BoundingBox3 box = surface.bounding_box();
  const Vec3 origin = box.empty() ? Vec3::Zero() : Vec3(0.5 * (box.min + box.max));
  double six_volume = 0;
  for (const auto& t : surface.triangles) {
    const Vec3 a = surface.points[t[0]] - origin, b = surface.points[t[1]] - origin, c = surface.points[t[2]] - origin;
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
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

// Number of vertex slots to index: the point count, or more if an element refers
// past it (adjacency may be built before validation; never index out of range).
template <std::size_t N>
std::size_t vertex_slots(std::span<const std::array<Index, N>> elements, std::size_t point_count) {
  Index largest = 0;
  for (const auto& e : elements)
    for (Index v : e) largest = std::max(largest, v);
  return elements.empty() ? point_count : std::max<std::size_t>(point_count, std::size_t{largest} + 1);
}

// What one vertex owns in the output: entries (edges or faces), items (their
// elements) and extras (cells beyond two on a non-manifold face).
using Counts = std::array<std::size_t, 3>;

// Calls gather(v, buffer) -> Counts for every vertex twice: once to count what each
// vertex owns, then, after allocate(totals), write(v, buffer, offsets) at its
// prefix-sum offsets. A vertex only reads its own element row, so both passes run
// in parallel without a global sort, and the output does not depend on the thread
// count: the same as sorting all (vertex, ...) keys, at a fraction of the cost.
template <typename Entry, typename Gather, typename Allocate, typename Write>
void two_pass_over_vertices(std::size_t vertex_count, Gather&& gather, Allocate&& allocate, Write&& write) {
  std::vector<Counts> offsets(vertex_count + 1, Counts{0, 0, 0});
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertex_count, 1024),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::vector<Entry> buffer;
                      for (std::size_t v = range.begin(); v != range.end(); ++v) offsets[v + 1] = gather(v, buffer);
                    });
  for (std::size_t v = 0; v < vertex_count; ++v)
    for (int k = 0; k < 3; ++k) offsets[v + 1][k] += offsets[v][k];
  allocate(offsets[vertex_count]);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertex_count, 1024),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      std::vector<Entry> buffer;
                      for (std::size_t v = range.begin(); v != range.end(); ++v) {
                        gather(v, buffer);
                        write(v, buffer, offsets[v]);
                      }
                    });
}

// Edges from a per-element edge table. Vertex v owns the edges (v, u) with u > v and
// finds them among its own elements, so edges come out sorted by (v, u) and each
// edge's elements ascending. Collapsed edges (u == v) are not edges.
template <std::size_t N, std::size_t E>
EdgeAdjacency edges_from_table(std::span<const std::array<Index, N>> elements, std::size_t point_count,
                               const std::array<std::array<int, 2>, E>& table) {
  using Entry = std::pair<Index, Index>;  // (other vertex, element)
  const std::size_t slots = vertex_slots<N>(elements, point_count);
  const CompressedRows rows = vertex_elements<N>(elements, slots);
  const auto gather = [&](std::size_t v, std::vector<Entry>& out) -> Counts {
    out.clear();
    for (Index c : rows.row(v)) {
      for (const auto& [i, j] : table) {
        const Index a = elements[c][i], b = elements[c][j];
        if (a == v && b > v) out.emplace_back(b, c);
        if (b == v && a > v) out.emplace_back(a, c);
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());  // an element lists an edge once
    std::size_t distinct = 0;
    for (std::size_t k = 0; k < out.size(); ++k) distinct += k == 0 || out[k].first != out[k - 1].first;
    return {distinct, out.size(), 0};
  };
  EdgeAdjacency adjacency;
  two_pass_over_vertices<Entry>(
      slots, gather,
      [&](const Counts& totals) {
        adjacency.edges.resize(totals[0]);
        adjacency.edge_elements.offsets.assign(totals[0] + 1, 0);
        adjacency.edge_elements.items.resize(totals[1]);
      },
      [&](std::size_t v, const std::vector<Entry>& entries, const Counts& at) {
        std::size_t edge = at[0];
        for (std::size_t k = 0; k < entries.size(); ++k) {
          if (k > 0 && entries[k].first != entries[k - 1].first) ++edge;
          adjacency.edges[edge] = {static_cast<Index>(v), entries[k].first};
          adjacency.edge_elements.items[at[1] + k] = entries[k].second;
          adjacency.edge_elements.offsets[edge + 1] = static_cast<Index>(at[1] + k + 1);
        }
      });
  return adjacency;
}

// Faces from a per-cell face table. A face belongs to its smallest vertex, which
// finds the face's cells among its own cells; faces come out sorted by their sorted
// vertex keys, cells ascending, each face oriented as in its first (smallest) cell.
template <std::size_t N, std::size_t F, std::size_t K>
FaceAdjacency<N> faces_from_table(std::span<const std::array<Index, K>> cells, std::size_t point_count,
                                  const std::array<std::array<int, N>, F>& table) {
  struct Entry {
    std::array<Index, N> key;  // sorted vertex ids
    Index cell;
    std::uint8_t local;
    bool operator<(const Entry& o) const { return std::tie(key, cell, local) < std::tie(o.key, o.cell, o.local); }
  };
  const std::size_t slots = vertex_slots<K>(cells, point_count);
  const CompressedRows rows = vertex_elements<K>(cells, slots);
  const auto gather = [&](std::size_t v, std::vector<Entry>& out) -> Counts {
    out.clear();
    for (Index c : rows.row(v)) {
      for (std::size_t f = 0; f < F; ++f) {
        Entry e{};
        Index smallest = kInvalidIndex;
        for (std::size_t i = 0; i < N; ++i) smallest = std::min(smallest, e.key[i] = cells[c][table[f][i]]);
        if (smallest != v) continue;  // another vertex owns this face
        std::sort(e.key.begin(), e.key.end());
        e.cell = c;
        e.local = static_cast<std::uint8_t>(f);
        out.push_back(e);
      }
    }
    std::sort(out.begin(), out.end());
    Counts counts{0, 0, 0};
    for (std::size_t k = 0; k < out.size();) {
      std::size_t end = k + 1;
      while (end < out.size() && out[end].key == out[k].key) ++end;
      ++counts[0];
      counts[2] += end - k > 2 ? end - k - 2 : 0;
      k = end;
    }
    return counts;
  };
  FaceAdjacency<N> adjacency;
  two_pass_over_vertices<Entry>(
      slots, gather,
      [&](const Counts& totals) {
        adjacency.faces.resize(totals[0]);
        adjacency.face_cells.resize(totals[0]);
        adjacency.extra_cells.resize(totals[2]);
        adjacency.extra_faces.resize(totals[2]);
      },
      [&](std::size_t, const std::vector<Entry>& entries, const Counts& at) {
        std::size_t face = at[0], extra = at[2];
        for (std::size_t k = 0; k < entries.size(); ++face) {
          std::size_t end = k + 1;
          while (end < entries.size() && entries[end].key == entries[k].key) ++end;
          for (std::size_t i = 0; i < N; ++i)
            adjacency.faces[face][i] = cells[entries[k].cell][table[entries[k].local][i]];
          adjacency.face_cells[face] = {entries[k].cell, end > k + 1 ? entries[k + 1].cell : kInvalidIndex};
          for (std::size_t x = k + 2; x < end; ++x, ++extra) {
            adjacency.extra_cells[extra] = entries[x].cell;
            adjacency.extra_faces[extra] = static_cast<Index>(face);
          }
          k = end;
        }
      });
  return adjacency;
}

constexpr std::array<std::array<int, 2>, 3> kTriangleEdges{{{0, 1}, {1, 2}, {2, 0}}};
constexpr std::array<std::array<int, 2>, 4> kQuadEdges{{{0, 1}, {1, 2}, {2, 3}, {3, 0}}};

}  // namespace

EdgeAdjacency build_edges(const TriMesh& mesh) {
  return edges_from_table<3>(mesh.triangles, mesh.points.size(), kTriangleEdges);
}
EdgeAdjacency build_edges(const QuadMesh& mesh) {
  return edges_from_table<4>(mesh.quads, mesh.points.size(), kQuadEdges);
}
EdgeAdjacency build_edges(const TetMesh& mesh) { return edges_from_table<4>(mesh.tets, mesh.points.size(), kTetEdges); }
EdgeAdjacency build_edges(const HexMesh& mesh) {
  return edges_from_table<8>(mesh.hexes, mesh.points.size(), kHexEdges);
}

FaceAdjacency<3> build_faces(const TetMesh& mesh) {
  return faces_from_table<3>(std::span(mesh.tets), mesh.points.size(), kTetFaces);
}
FaceAdjacency<4> build_faces(const HexMesh& mesh) {
  return faces_from_table<4>(std::span(mesh.hexes), mesh.points.size(), kHexFaces);
}

TriMesh boundary_surface(const TetMesh& mesh, std::vector<Index>* point_of) {
  const FaceAdjacency<3> faces = build_faces(mesh);
  TriMesh surface;
  std::vector<Index> renumber(mesh.points.size(), kInvalidIndex);
  for (std::size_t f = 0; f < faces.faces.size(); ++f)
    if (faces.face_cells[f][1] == kInvalidIndex) {
      surface.triangles.push_back(faces.faces[f]);  // outward from its one tet
      for (const Index v : faces.faces[f]) {
        if (v >= mesh.points.size())
          throw InputError("boundary_surface: a tet refers to point " + std::to_string(v) + " of " +
                           std::to_string(mesh.points.size()));
        renumber[v] = 0;
      }
    }
  if (point_of) point_of->clear();
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    if (renumber[v] == 0) {
      renumber[v] = static_cast<Index>(surface.points.size());
      surface.points.push_back(mesh.points[v]);
      if (point_of) point_of->push_back(static_cast<Index>(v));
    }
  for (auto& t : surface.triangles)
    for (Index& v : t) v = renumber[v];
  return surface;
}

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
