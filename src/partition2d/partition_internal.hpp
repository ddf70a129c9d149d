// Internal stages of partition_region (docs/design/partition2d.md). Each stage is a
// plain function from data to data; the driver (partition_region.cpp) calls them top
// to bottom:
//
//   DomainMesh ──► L_p-CVT sites ──► Tessellation (restricted Voronoi pieces)
//     ──► CellGraph ──► node labels (recursive bisection + refinement)
//     ──► face labels ──► Partition geometry ──► metrics, files
//
// All geometry here is in the *normalised frame*: metric coordinates minus the
// domain centre, divided by the cell size, so a CVT cell has size about 1.
#pragma once

#include "structmesh/mesh.hpp"
#include "structmesh/partition2d.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace structmesh::partition2d {

// ---------------------------------------------------------------------------------
// Domain: constrained Delaunay triangulation of the region (+ a Steiner grid), flat.
// ---------------------------------------------------------------------------------

struct Frame {
  Vec2 center = Vec2::Zero();
  double scale = 1;  ///< normalised = (metric - center) / scale
  Vec2 to_normalised(const Vec2& metric) const { return (metric - center) / scale; }
  Vec2 to_metric(const Vec2& normalised) const { return normalised * scale + center; }
};

struct DomainMesh {
  /// Normalised coordinates. Points [0, input_point_count) are the region's points
  /// in input order (point i is Polygon2::points[i]); later points are Steiner points.
  std::vector<Vec2> points;
  std::size_t input_point_count = 0;
  /// Counter-clockwise triangles inside the region, in a deterministic spatial order.
  std::vector<std::array<Index, 3>> triangles;
  /// neighbors[t][k]: triangle across edge k (from vertex k to vertex (k+1)%3), or
  /// kInvalidIndex when that edge is on the region boundary.
  std::vector<std::array<Index, 3>> neighbors;
  double area = 0;  ///< normalised units
  Frame frame;
};

/// Lambert azimuthal equal-area projection for lon/lat regions (design §2.0):
/// equal-area keeps R_W honest over the Gulf of Mexico's 13° of latitude.
struct Projection {
  bool active = false;
  double lat0 = 0, lon0 = 0;               ///< degrees, the centre of the region's bounding box
  Vec2 forward(const Vec2& lonlat) const;  ///< degrees -> metres
  Vec2 inverse(const Vec2& xy) const;      ///< metres -> degrees
  std::string describe() const;            ///< "" when inactive
};
/// Active for Polygon2::Coordinates::LonLat, centred on the bounding box.
Projection choose_projection(const Polygon2& region);
Polygon2 project_region(const Polygon2& region, const Projection& projection);

/// Triangulates the metric region with a Steiner grid of the given spacing (metric
/// units; 0 = none) and expresses it in `frame`.
DomainMesh build_domain_mesh(const Polygon2& metric_region, const Frame& frame, double steiner_spacing);

/// A simplified copy of the region for the CVT optimisation (design §2.4): rings
/// simplified by Douglas-Peucker to `tolerance`, rings of area below `min_area`
/// dropped. Returns the region itself when simplification changes nothing or would
/// make it invalid.
Polygon2 proxy_region(const Polygon2& metric_region, double tolerance, double min_area);

// ---------------------------------------------------------------------------------
// Tessellation: a conforming polygonal subdivision of the domain (restricted Voronoi
// pieces, or triangles for the METIS/MADD baselines).
// ---------------------------------------------------------------------------------

struct Tessellation {
  std::vector<Vec2> vertices;              ///< normalised frame
  std::vector<std::int64_t> input_vertex;  ///< region point index, or -1
  /// Faces: CSR, counter-clockwise, no repeated consecutive vertex. Half-edge h of
  /// face f goes from face_vertices[h] to the next vertex of f (cyclically).
  std::vector<Index> face_offsets{0};
  std::vector<Index> face_vertices;
  std::vector<Index> face_cell;  ///< cell (site / triangle group) of each face
  /// Per half-edge: the opposite half-edge (same two vertices reversed), or
  /// kInvalidIndex on the region boundary. Every interior half-edge has exactly one twin.
  std::vector<Index> twin;
  /// Per half-edge on the region boundary: the region ring it lies on (else -1).
  std::vector<std::int32_t> boundary_ring;
  std::size_t cell_count = 0;

  std::size_t face_count() const { return face_cell.size(); }
  Index next(Index half_edge, Index face) const {
    return half_edge + 1 == face_offsets[face + 1] ? face_offsets[face] : half_edge + 1;
  }
};

/// The fine triangulation of the METIS and MADD baselines (design §2.9): a quality
/// constrained Delaunay triangulation of about `target_triangles` triangles, one
/// face per triangle. face_cell = triangle, or with `madd` the triangle's group after
/// MADD-style merging (§3.1.1: a triangle whose smallest angle is below 30° is merged
/// with its neighbour across the edge opposite that angle; groups of at most 4).
Tessellation triangle_tessellation(const Polygon2& metric_region, const Frame& frame, std::size_t target_triangles,
                                   bool madd);

/// Sets boundary_ring of every region-boundary half-edge from the input ring of
/// its endpoints or, for a piece strictly inside a boundary segment, of the
/// segment it lies on (found through the neighbouring boundary half-edges).
void assign_boundary_rings(Tessellation& tessellation, const Polygon2& region);

/// Signed area of each face (normalised units).
std::vector<double> face_areas(const Tessellation& tessellation);

// ---------------------------------------------------------------------------------
// L_p-CVT (eq. 3.11-3.12) on the domain: restricted Voronoi diagram, energy, gradient.
// ---------------------------------------------------------------------------------

/// F(X) of eq. (3.12) with the exact gradient (interior term plus the bisector term,
/// design §1.7). `gradient` (2n, x0 y0 x1 y1 ...) may be null. Sites whose cell is
/// empty get a zero gradient and are counted in *empty_cells.
double lp_energy(const DomainMesh& domain, std::span<const Vec2> sites, int p, std::vector<double>* gradient,
                 std::size_t* empty_cells = nullptr);

/// The restricted Voronoi diagram of `sites` in the domain as a conforming
/// tessellation: face_cell = site index; vertices shared by construction.
Tessellation restricted_voronoi(const DomainMesh& domain, std::span<const Vec2> sites);

/// About `count` sites on a square grid inside the domain, deterministically jittered
/// by 1e-6 of the spacing (hash of seed and index) so no four sites are co-circular.
std::vector<Vec2> initial_grid_sites(const DomainMesh& domain, std::size_t count, std::uint64_t seed);

struct LpCvtOptions {
  int p = 8;
  int max_iterations = 200;
  double gradient_tolerance = 1e-6;
  bool progress = false;
};

struct LpCvtResult {
  std::vector<Vec2> sites;
  double energy_initial = 0, energy_final = 0;
  int iterations = 0;
  std::string stop_reason;  ///< "converged", "max iterations", "line search stopped"
  std::size_t empty_cells = 0;
};

/// Minimises eq. (3.12) with L-BFGS (LBFGS++), keeping the best point seen.
LpCvtResult optimise_lp_cvt(const DomainMesh& domain, std::vector<Vec2> sites, const LpCvtOptions& options);

// ---------------------------------------------------------------------------------
// Cell graph: the dual graph G of the tessellation (§3.2.1) plus the corner
// structure needed by eq. (3.6)-(3.8).
// ---------------------------------------------------------------------------------

struct CellGraph {
  /// Node = a connected component (across interior half-edges) of the faces of one
  /// cell: a cell cut in two by a hole becomes two nodes.
  std::vector<Index> face_node;
  std::vector<Index> node_cell;
  std::vector<double> node_area;  ///< normalised units
  /// Symmetric CSR adjacency without self loops or duplicates; arc weight = total
  /// length of the half-edges shared by the two nodes.
  std::vector<Index> adjacency_offsets{0};
  std::vector<Index> adjacency;
  std::vector<double> arc_length;
  /// Corner vertices (design §1.4): tessellation vertices where edges between
  /// different nodes meet, after contracting such edges shorter than the
  /// contraction length (a cluster is one corner vertex). Pass-through vertices
  /// (two collinear spokes, not on the boundary) are left out.
  /// Spokes of corner c: spokes[corner_offsets[c] .. corner_offsets[c+1]), sorted
  /// by angle counter-clockwise. Spoke s leaves the corner in direction `angle`;
  /// the sector from spoke s to spoke s+1 (cyclically) belongs to node `left_node`
  /// (kInvalidIndex when that sector is outside the region).
  struct Spoke {
    double angle = 0;
    Index left_node = kInvalidIndex;
  };
  std::vector<Index> corner_offsets{0};
  std::vector<Spoke> spokes;
  std::vector<Vec2> corner_position;
  /// node -> corners on its boundary (CSR), for local updates of D_theta.
  std::vector<Index> node_corner_offsets{0};
  std::vector<Index> node_corners;
  double mean_arc_length = 0;  ///< mean length of node-separating edges (normalised)
  // (cell_graph.cpp) "Edges" are those of the partition's primal graph, i.e. the
  // Voronoi edges of design §1.9: pieces meeting at a pass-through vertex count as one
  // edge and contracted edges as none; total separating length / that count.

  std::size_t node_count() const { return node_area.size(); }
};

/// Builds the cell graph; edges between different nodes shorter than
/// `contraction_length` are contracted for the corner structure (design §1.4).
CellGraph build_cell_graph(const Tessellation& tessellation, double contraction_length);
// (cell_graph.cpp) Nodes are numbered in order of their first face, so with one
// face per cell and no cell split, node = face. Corners are ordered by their
// smallest vertex; a contracted cluster's spoke directions are those of its edges
// leaving the cluster, measured from their own end inside the cluster. Spokes are the
// node-separating and region-boundary edges only: edges inside one node are not.

/// Eq. (3.6): deviation of angle theta (radians, any value) from the nearest
/// multiple of pi/2, in [0, pi/4].
double angle_deviation(double theta);

struct CornerCost {
  double separator_sum = 0;  ///< sum of delta over corners of incident separators (3.8)
  std::size_t separator_corners = 0;
  double boundary_sum = 0;  ///< sum of delta over separator/boundary corners
  std::size_t boundary_corners = 0;
  CornerCost& operator+=(const CornerCost& other) {
    separator_sum += other.separator_sum;
    separator_corners += other.separator_corners;
    boundary_sum += other.boundary_sum;
    boundary_corners += other.boundary_corners;
    return *this;
  }
};

/// Corner costs of a labelling (label per node; outside counts as its own label).
/// At a corner with s >= 2 active spokes (spokes between different labels): s = 2
/// gives one corner, s >= 3 gives s corners (consecutive sectors); a corner between
/// two separator spokes is a separator corner, between a separator and a boundary
/// spoke a boundary corner, between two boundary spokes nothing.
CornerCost corner_cost(const CellGraph& graph, std::span<const std::int32_t> node_label);
/// The same for one corner (used for local updates by the refinement).
CornerCost corner_cost_at(const CellGraph& graph, Index corner, std::span<const std::int32_t> node_label);

// ---------------------------------------------------------------------------------
// Graph partitioning: recursive bisection (METIS) + refinement + connectivity.
// ---------------------------------------------------------------------------------

struct GraphPartitionOptions {
  enum class Engine : std::uint8_t {
    RecursiveGp,     ///< CVT-GP: METIS 2-way per bisection + refinement of J = L_S + lambda D_theta
    MetisKway,       ///< METIS_PartGraphKway with CONTIG (baselines), + connectivity repair
    MetisRecursive,  ///< METIS_PartGraphRecursive (MADD baseline), + connectivity repair
    Exact,           ///< MILP per bisection with CBC (small graphs)
  };
  Engine engine = Engine::RecursiveGp;
  std::size_t parts = 2;
  double imbalance = 0.05;
  double angle_weight = 1.0;  ///< lambda = angle_weight * graph.mean_arc_length
  bool boundary_corners = true;
  int refinement_passes = 10;
  double exact_time_limit = 60;  ///< seconds for the whole run (Exact), shared by the bisections
  std::uint64_t seed = 0;
};

struct GraphPartitionReport {
  std::size_t components_before_repair = 0;  ///< max components of a part before repair
  std::size_t moved_by_repair = 0;
  double exact_gap = 0;  ///< Exact: worst relative gap
  bool exact_proven = true;
  bool balanced = false;  ///< R_W (3.2) = max / min part area <= 1 + imbalance
};

/// Labels every node with a part in [0, parts). Every part non-empty and connected
/// in the graph (Error otherwise). InputError when the graph has fewer than
/// 2 nodes per part.
std::vector<std::int32_t> partition_cell_graph(const CellGraph& graph, const GraphPartitionOptions& options,
                                               GraphPartitionReport* report = nullptr);

/// Moves every component of a part other than its largest (by area) to the
/// neighbouring part sharing the longest boundary with it; returns nodes moved.
/// Used after direct CVT (one part per cell) and after METIS.
std::size_t repair_connectivity(const CellGraph& graph, std::span<std::int32_t> node_label, std::size_t parts);
// (cell_graph.cpp) Ties: the largest component with the smallest node stays; the
// target with the smallest label wins. Repeats until no component can move, so
// the count returned may include nodes moved twice. A part empty on entry stays empty
// (the caller's problem); a component with no neighbour in another part (the graph
// itself is disconnected) cannot be moved and stays. Error when a label is outside
// [0, parts). Deterministic.

/// Connected components of each part in the graph (max over parts).
std::size_t max_components_per_part(const CellGraph& graph, std::span<const std::int32_t> node_label,
                                    std::size_t parts);

// ---------------------------------------------------------------------------------
// Part geometry, metrics and files.
// ---------------------------------------------------------------------------------

/// Maps a normalised tessellation vertex to input coordinates and the metric plane.
struct CoordinateMaps {
  std::function<Vec2(const Vec2&)> normalised_to_metric;
  std::function<Vec2(const Vec2&)> metric_to_input;  ///< identity for planar input
};

/// Fills vertices, metric_vertices, input_vertex, junction, curves, part_loops,
/// parts and part_areas of `partition` from the tessellation and a part per face.
/// Input vertices are copied from `region` by index. Vertices interior to a straight
/// stretch of a part boundary (neither input vertex nor junction nor a turn) are
/// dropped, the same way for both sides. Error when a part is not one piece.
void build_part_geometry(const Tessellation& tessellation, std::span<const std::int32_t> face_part, std::size_t parts,
                         const Polygon2& region, const CoordinateMaps& maps, Partition& partition);

/// R_W, L_S, R^_C (both), junction deviation (chord rule, chord length
/// `chord_length` metric units), area error and components, from the geometry.
/// The separator-corner deviation (3.8) comes from corner_cost on the cell graph.
void measure_partition_geometry(Partition& partition, double region_area, double chord_length);

}  // namespace structmesh::partition2d
