// Mesh types: flat arrays with 32-bit indices, no per-element heap objects.
//
// Every element type stores its points once (`points`) and its connectivity as a
// contiguous array of fixed-size index tuples. Node orders follow VTK:
//  - quad: 0-1-2-3 counter-clockwise seen from the side the normal points to;
//  - tet:  0-1-2 counter-clockwise seen from vertex 3 (positive volume);
//  - hex:  0-3 bottom face counter-clockwise seen from above, node i+4 above node i.
// Adjacency is not cached inside the meshes: build it once with the functions
// below and pass it to whoever needs it (see STYLE.md).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace structmesh {

using Index = std::uint32_t;
inline constexpr Index kInvalidIndex = std::numeric_limits<Index>::max();

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

struct BoundingBox2 {
  Vec2 min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2 max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  bool empty() const { return !(min.x() <= max.x()); }
  double diagonal() const { return empty() ? 0.0 : (max - min).norm(); }
  void extend(const Vec2& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

struct BoundingBox3 {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());
  bool empty() const { return !(min.x() <= max.x()); }
  double diagonal() const { return empty() ? 0.0 : (max - min).norm(); }
  void extend(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

BoundingBox3 bounding_box(std::span<const Vec3> points);
BoundingBox2 bounding_box(std::span<const Vec2> points);

/// A planar region: one outer ring and any number of holes.
/// Rings are stored back to back in `points`; ring r spans
/// points[ring_offsets[r] .. ring_offsets[r+1]). Ring 0 is the outer ring.
/// Rings are implicitly closed (the first point is not repeated at the end).
/// Orientation convention after reading: outer ring counter-clockwise, holes clockwise.
struct Polygon2 {
  enum class Coordinates : std::uint8_t { Planar, LonLat };

  std::vector<Vec2> points;
  std::vector<Index> ring_offsets{0};
  Coordinates coordinates = Coordinates::Planar;

  std::size_t ring_count() const { return ring_offsets.size() - 1; }
  std::size_t hole_count() const { return ring_count() == 0 ? 0 : ring_count() - 1; }
  std::span<const Vec2> ring(std::size_t r) const {
    return {points.data() + ring_offsets[r], points.data() + ring_offsets[r + 1]};
  }
  /// Appends a ring (the first appended ring is the outer one).
  void add_ring(std::span<const Vec2> ring_points);
  BoundingBox2 bounding_box() const { return structmesh::bounding_box(points); }
};

/// Signed area of a closed ring (positive when counter-clockwise).
double signed_area(std::span<const Vec2> ring);
/// Area of the region: outer ring area minus hole areas.
double area(const Polygon2& polygon);

struct TriMesh {
  std::vector<Vec3> points;
  std::vector<std::array<Index, 3>> triangles;
  BoundingBox3 bounding_box() const { return structmesh::bounding_box(points); }
};

/// Signed volume enclosed by a triangle surface (> 0 when its normals point outward).
double enclosed_volume(const TriMesh& surface);

struct QuadMesh {
  std::vector<Vec3> points;  // planar meshes use z = 0
  std::vector<std::array<Index, 4>> quads;
  BoundingBox3 bounding_box() const { return structmesh::bounding_box(points); }
};

struct TetMesh {
  std::vector<Vec3> points;
  std::vector<std::array<Index, 4>> tets;
  BoundingBox3 bounding_box() const { return structmesh::bounding_box(points); }
};

struct HexMesh {
  std::vector<Vec3> points;
  std::vector<std::array<Index, 8>> hexes;
  BoundingBox3 bounding_box() const { return structmesh::bounding_box(points); }
};

/// Compressed rows: row i is items[offsets[i] .. offsets[i+1]).
struct CompressedRows {
  std::vector<Index> offsets{0};
  std::vector<Index> items;
  std::size_t row_count() const { return offsets.size() - 1; }
  std::span<const Index> row(std::size_t i) const { return {items.data() + offsets[i], items.data() + offsets[i + 1]}; }
};

/// Unique undirected edges of a mesh and, for each edge, the elements that use it.
struct EdgeAdjacency {
  std::vector<std::array<Index, 2>> edges;  // edges[e][0] < edges[e][1], sorted
  CompressedRows edge_elements;             // edge -> elements using it (ascending)
};

/// Unique faces of a volume mesh and the (one or two) cells on each side.
/// faces[f] holds the face's vertices as first seen (oriented outward from
/// face_cells[f][0]); face_cells[f][1] is kInvalidIndex on the boundary.
template <std::size_t N>
struct FaceAdjacency {
  std::vector<std::array<Index, N>> faces;
  std::vector<std::array<Index, 2>> face_cells;
  std::vector<Index> extra_cells;  // cells beyond the second on a face (non-manifold input)
  std::vector<Index> extra_faces;  // ... and the face each of those belongs to
};

EdgeAdjacency build_edges(const TriMesh& mesh);
EdgeAdjacency build_edges(const QuadMesh& mesh);
EdgeAdjacency build_edges(const TetMesh& mesh);
EdgeAdjacency build_edges(const HexMesh& mesh);

FaceAdjacency<3> build_faces(const TetMesh& mesh);
FaceAdjacency<4> build_faces(const HexMesh& mesh);
/// The boundary of a tet mesh: its faces that belong to one tet, oriented outward, in
/// build_faces() order, on the points they use (renumbered in ascending order of the
/// tet mesh's point index; `point_of[v]` gives that index when `point_of` is given).
TriMesh boundary_surface(const TetMesh& mesh, std::vector<Index>* point_of = nullptr);

/// Vertex -> incident elements (the one-ring of elements), ascending element ids.
CompressedRows build_vertex_elements(std::span<const std::array<Index, 3>> elements, std::size_t point_count);
CompressedRows build_vertex_elements(std::span<const std::array<Index, 4>> elements, std::size_t point_count);
CompressedRows build_vertex_elements(std::span<const std::array<Index, 8>> elements, std::size_t point_count);

/// Vertex -> neighbouring vertices along edges (the one-ring of vertices), ascending.
CompressedRows build_vertex_neighbors(const EdgeAdjacency& edges, std::size_t point_count);

/// The 12 edges of a hex and its 6 faces (outward, VTK order), and the 4 faces of a tet.
inline constexpr std::array<std::array<int, 2>, 12> kHexEdges{
    {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}}};
inline constexpr std::array<std::array<int, 4>, 6> kHexFaces{
    {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};
inline constexpr std::array<std::array<int, 3>, 4> kTetFaces{{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
inline constexpr std::array<std::array<int, 2>, 6> kTetEdges{{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};

}  // namespace structmesh
