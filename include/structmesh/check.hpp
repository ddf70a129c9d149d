// Validation of inputs for use as a solid boundary, a volume mesh or a region.
// Each problem says what is wrong and where (element or vertex index, file line).
#pragma once

#include "structmesh/io.hpp"
#include "structmesh/mesh.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace structmesh {

struct Problem {
  std::string kind;           // short machine-readable tag: "open-edge", "self-intersection", ...
  std::string message;        // human-readable, names element/vertex indices
  std::uint32_t line = 0;     // 1-based source line where known, else 0
  std::int64_t element = -1;  // element (face/cell/ring) index where relevant
};

struct SurfaceReport {
  std::size_t vertices = 0, faces = 0, edges = 0;
  std::size_t boundary_edges = 0;         // edges with one face
  std::size_t non_manifold_edges = 0;     // edges with more than two faces
  std::size_t non_manifold_vertices = 0;  // vertices whose face fan is not one disk/half-disk
  std::size_t degenerate_faces = 0;       // repeated index or zero area
  std::size_t inconsistent_edges = 0;     // manifold edges traversed twice in the same direction
  std::size_t flipped_faces = 0;          // fewest faces to flip to make every part consistent
  std::size_t self_intersections = 0;     // intersecting pairs of faces sharing no vertex
  std::size_t adjacent_overlaps = 0;      // triangles sharing a vertex/edge that overlap beyond it (folds)
  std::size_t components = 0;
  std::size_t isolated_vertices = 0;  // vertices used by no face
  long euler_characteristic = 0;      // V - E + F (V counts used vertices only)
  bool closed = false, edge_manifold = false, oriented = false;
  int genus = -1;                     // closed, oriented, manifold only (sum over components); else -1
  double signed_volume = 0;           // > 0 for outward normals (closed meshes)
  bool valid_solid_boundary = false;  // closed, manifold, oriented, outward, no self-intersection,
                                      // no adjacent overlap, no degenerate face
  std::vector<Problem> problems;      // capped at max_problems per kind
};

struct CheckOptions {
  std::size_t max_problems_per_kind = 20;
  bool self_intersections = true;  // the costly test (CGAL box intersection + exact predicates);
                                   // when off, validity does not consider it
  // Regions only: the polygons are the parts of a partition, so two polygons may
  // share boundary (touching or collinear segments of different polygons are fine;
  // crossings are not). The containment test between polygons is skipped: a
  // vertex on a shared boundary cannot tell inside from outside.
  bool shared_boundaries = false;
};

SurfaceReport check_surface(const MeshBundle& mesh, const CheckOptions& options = {});

/// Why a surface the report rejects does not bound a solid, for an error message: each kind
/// of problem with its count (" open (3 boundary edges); self-intersecting (2 face pairs);"),
/// then the first problem found. Empty for a valid solid boundary.
std::string solid_boundary_problems(const SurfaceReport& report);

/// A surface with its holes closed (fill_holes()).
struct HoleFilling {
  TriMesh surface;  ///< the input's points and triangles first, unchanged; new ones after them
  std::size_t holes = 0, added_faces = 0, added_vertices = 0;
};

/// Closes every hole (border cycle) of a manifold, consistently oriented triangle surface
/// with CGAL's minimum-area hole triangulation (no new vertices), or, where that fails,
/// a fan around the hole's centroid. InputError for a non-manifold or inconsistently
/// oriented surface. Self-intersections are neither looked for nor removed.
HoleFilling fill_holes(const TriMesh& surface);

struct VolumeReport {
  std::size_t vertices = 0, tets = 0, hexes = 0, quads = 0, triangles = 0;
  std::size_t inverted = 0;            // tets with volume <= 1e-12 (longest edge)^3, hexes with scaled Jacobian <= 0
  std::size_t degenerate = 0;          // repeated vertex index in an element / invalid hex
  std::size_t non_manifold_faces = 0;  // faces shared by more than two cells
  std::size_t unused_vertices = 0;     // used by no tet or hex (a warning: does not invalidate)
  double min_tet_volume = 0;           // over non-degenerate tets (0 when there are none)
  double min_hex_scaled_jacobian = 0;  // over valid hexes (0 when there are none)
  bool valid = false;
  std::vector<Problem> problems;
};
VolumeReport check_volume(const MeshBundle& mesh, const CheckOptions& options = {});

/// A planar 2D mesh (triangles and/or quads, all z equal): what a quad mesher must
/// deliver. Conforming means every edge is used by one element (boundary) or two
/// elements traversing it in opposite directions (interior).
struct PlanarMeshReport {
  std::size_t vertices = 0, triangles = 0, quads = 0, edges = 0;
  std::size_t boundary_edges = 0;       // used by one element
  std::size_t non_manifold_edges = 0;   // used by more than two elements
  std::size_t inconsistent_edges = 0;   // interior edges traversed in the same direction twice
  std::size_t inverted = 0;             // quads with scaled Jacobian <= 0 (+z reference), triangles with area <= 0
  std::size_t degenerate = 0;           // an element repeating a vertex
  std::size_t unused_vertices = 0;      // used by no element (a warning: does not invalidate)
  std::size_t components = 0;           // connected through shared edges
  std::size_t holes = 0;                // components - Euler characteristic (each component a disk with holes)
  long euler_characteristic = 0;        // V - E + F over used vertices
  double area = 0;                      // sum of signed element areas
  double min_quad_scaled_jacobian = 0;  // over non-degenerate quads (0 when there are none)
  bool planar = false;                  // all z equal
  bool valid = false;                   // planar, no inverted/degenerate element, no non-manifold or inconsistent edge
  std::vector<Problem> problems;
};
PlanarMeshReport check_planar_mesh(const MeshBundle& mesh, const CheckOptions& options = {});

struct RegionReport {
  std::size_t polygons = 0, rings = 0, holes = 0, vertices = 0;
  double area = 0;
  std::size_t self_intersections = 0;    // crossing or touching segment pairs (within or between rings)
  std::size_t holes_outside = 0;         // holes not inside their outer ring
  std::size_t nested_holes = 0;          // holes inside or overlapping other holes
  std::size_t short_rings = 0;           // fewer than 3 distinct points
  std::size_t duplicate_points = 0;      // consecutive repeated points
  std::size_t overlapping_polygons = 0;  // polygons lying inside another polygon's interior
  bool valid = false;
  std::vector<Problem> problems;
};
RegionReport check_region(const std::vector<Polygon2>& polygons, const CheckOptions& options = {});

}  // namespace structmesh
