// Geometry-aware partitioning of a planar region into k balanced, compact parts
// whose separators meet at angles near multiples of 90° (dissertation ch. 3.2;
// design: docs/design/partition2d.md).
//
// partition_region() runs the whole pipeline: lon/lat projection, constrained
// Delaunay triangulation, L_p-CVT (eq. 3.11-3.12), the CVT's dual graph, recursive
// bisection with METIS plus our own refinement of separator length (3.3) and angle
// deviation (3.7) under the balance constraint (3.1), connectivity repair (§3.2.5),
// and the part geometry. The baselines of Tables 3.1/3.2 run through the same path.
#pragma once

#include "structmesh/mesh.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace structmesh {

enum class PartitionMethod : std::uint8_t {
  CvtGp,  ///< L_p-CVT + graph partitioning (the dissertation's method, §3.2.6)
  Cvt,    ///< direct L_p-CVT with k sites, one cell per part
  Metis,  ///< METIS k-way on the dual graph of a fine constrained Delaunay triangulation
  Madd,   ///< MADD-style: triangles merged across edges opposite small angles, then METIS
  Exact,  ///< MILP per bisection (§3.2.4-3.2.5) with COIN-OR CBC; small graphs only
};

const char* method_name(PartitionMethod method);
/// Parses "cvtgp", "cvt", "metis", "madd", "exact"; InputError otherwise.
PartitionMethod parse_method(const std::string& name);

struct PartitionOptions {
  std::size_t parts = 16;  ///< k >= 1 (k = 1 returns the region as one part)
  PartitionMethod method = PartitionMethod::CvtGp;
  /// CVT sites (CvtGp, Exact) or fine triangles (Metis, Madd). Raised to
  /// 24 * parts unless exact_cells, so that balance is achievable (design §1.9).
  std::size_t cells = 4000;
  bool exact_cells = false;
  int p = 8;                ///< L_p exponent of eq. (3.12): even, >= 2
  double imbalance = 0.05;  ///< target R_W <= 1 + imbalance (eq. 3.1/3.2)
  /// lambda = angle_weight * mean separator edge length (beta of design §1.9). 3 was
  /// chosen on the Key and the Pipe at k = 128 (bench/partition2d/notes.md): it
  /// keeps the separator length within 2% of beta = 1 and lowers delta (3.8) by 15%.
  double angle_weight = 3.0;
  bool boundary_corners = true;          ///< separator/boundary corners in the objective
  int cvt_max_iterations = 80;           ///< L-BFGS iterations
  double cvt_gradient_tolerance = 1e-6;  ///< in the normalised frame (cell size 1)
  int refinement_passes = 10;
  double exact_time_limit = 60;  ///< seconds for the whole Exact run, shared by the bisections
  std::size_t exact_max_nodes = 400;
  /// Simplify boundaries for the CVT optimisation when they have more than
  /// 20 segments per cell (the final clip always uses the full boundary).
  bool proxy_domain = true;
  std::uint64_t seed = 0;
  bool progress = false;  ///< progress on stderr
  /// > 0: before partitioning, close water narrower than this (metric units) and drop
  /// islands below min_island_area (remove_narrow_water()); quad2d sets both from the
  /// element size, since a uniform mesh cannot hold narrower features.
  double min_channel_width = 0;
  double min_island_area = 0;
};

struct PartitionMetrics {
  std::size_t parts = 0;
  double workload_ratio = 0;          ///< R_W = A_max / A_min (3.2)
  double separator_length = 0;        ///< L_S (3.3), metric units
  double compactness = 0;             ///< R^_C = L_S / (k A_M) (3.5), as printed
  double compactness_normalized = 0;  ///< L_S / sqrt(k A_M), dimensionless
  /// delta^_theta (3.8), radians, over the corners formed by incident separators,
  /// with straight separator edges shorter than corner_resolution cell sizes
  /// contracted (design §1.4: such edges, e.g. between the two degree-3 vertices
  /// that replace a four-cell junction of a near-grid CVT, have arbitrary directions).
  double angle_deviation = 0;
  std::size_t corners = 0;              ///< N_C of (3.8)
  double corner_resolution = 0;         ///< the contraction length, in cell sizes
  double angle_deviation_fine = 0;      ///< (3.8) with contraction only below 1e-3 cell sizes
  double junction_angle_deviation = 0;  ///< corners at junctions only (chord rule)
  std::size_t junction_corners = 0;
  double region_area = 0;                    ///< A_M, metric units
  double area_error = 0;                     ///< |sum of part areas - A_M| / A_M
  std::size_t max_components_per_part = 0;   ///< after repair (1 when valid)
  std::size_t components_before_repair = 0;  ///< max over parts, before repair
  std::size_t cells = 0, graph_nodes = 0, graph_arcs = 0;
  double cvt_energy_initial = 0, cvt_energy_final = 0;
  int cvt_iterations = 0;
  std::string cvt_stop_reason;
  double exact_gap = 0;  ///< Exact: worst relative MIP gap over bisections
  std::vector<std::pair<std::string, double>> stage_seconds;
  double peak_rss_mb = 0;
};

/// A maximal chain of part-boundary edges between two junctions: a separator
/// between two parts, or a piece of the region boundary with one part on its left.
struct PartitionCurve {
  enum class Kind : std::uint8_t { Separator, Boundary };
  Kind kind = Kind::Separator;
  std::int32_t left_part = -1;   ///< part on the left walking first -> last vertex
  std::int32_t right_part = -1;  ///< -1: outside the region
  std::int32_t ring = -1;        ///< Boundary curves: the input ring
  std::vector<Index> vertices;   ///< into Partition::vertices; first/last are junctions
};

/// What remove_narrow_water() changed (areas in the region's units squared).
struct NarrowWaterReport {
  double channel_width = 0;    ///< water narrower than this was closed
  double min_island_area = 0;  ///< islands smaller than this were dropped
  bool changed = false;
  std::size_t islands_dropped = 0;
  double island_area = 0;
  std::size_t pinch_chords = 0;      ///< triangulation edges spanning a channel narrower than the width
  std::size_t pinch_vertices = 0;    ///< points where the water met itself, opened
  std::size_t closed_triangles = 0;  ///< triangles of narrow water closed
  double closed_area = 0;
  std::size_t pieces_dropped = 0;  ///< water cut off behind a closed channel
  double dropped_area = 0;
  std::size_t tips_removed = 0;  ///< land tips cut back to widen a gap narrower than the width
  double tip_area = 0;           ///< land given to the water by that
  double area_before = 0, area_after = 0;
};

struct Partition {
  /// Vertices of the part boundaries in input coordinates; input vertices are
  /// copied bit-identically, so neighbouring parts share identical vertices.
  std::vector<Vec2> vertices;
  std::vector<Vec2> metric_vertices;       ///< the same in the metric plane
  std::vector<std::int64_t> input_vertex;  ///< input point index, or -1 for new vertices
  std::vector<std::uint8_t> junction;      ///< 1 where >= 3 parts meet or a separator meets the boundary
  std::vector<PartitionCurve> curves;
  /// part -> loops -> signed curve references: c >= 0 is curve c forwards,
  /// c < 0 is curve (-c - 1) reversed. Loop 0 is the outer loop (counter-clockwise).
  std::vector<std::vector<std::vector<std::int64_t>>> part_loops;
  std::vector<Polygon2> parts;     ///< each part as a region, input coordinates
  std::vector<double> part_areas;  ///< metric plane
  std::vector<Vec2> sites;         ///< CVT sites (metric plane), for pictures
  PartitionMetrics metrics;
  NarrowWaterReport simplification;  ///< what the narrow-water filter changed (options.min_channel_width)
  std::string projection;            ///< "" or "LAEA lat0=... lon0=... R=6371008.8"
};

struct NarrowWaterResult {
  Polygon2 region;  ///< outer ring counter-clockwise first, then the holes (clockwise)
  /// The rings as indices of the input points: every vertex is an input vertex.
  std::vector<std::vector<Index>> rings;
  NarrowWaterReport report;
};

/// Closes channels, passes and inlets of `region` (a planar, metric region) narrower
/// than `channel_width`, drops islands of area below `min_island_area`, and keeps the
/// largest connected piece of the water (src/partition2d/remove_narrow_water.cpp has
/// the rules). A region with nothing to remove is returned unchanged.
NarrowWaterResult remove_narrow_water(const Polygon2& region, double channel_width, double min_island_area);
/// The region whose rings are these indices of `region`'s points.
Polygon2 select_rings(const Polygon2& region, const std::vector<std::vector<Index>>& rings);

/// Partitions `region` into options.parts parts. InputError for an invalid region
/// or options (odd p, k < 1, too few cells for k parts).
Partition partition_region(const Polygon2& region, const PartitionOptions& options = {});

/// GeoJSON FeatureCollection: one Polygon Feature per part (properties part, area,
/// kind "part"), then one LineString Feature per separator (kind "separator", left, right).
std::string write_partition_geojson(const Partition& partition);
/// Parts coloured (neighbours differ), separators drawn, holes white.
std::string partition_svg(const Partition& partition, double width_px = 1200);
std::string partition_png(const Partition& partition, int width_px = 1200);

}  // namespace structmesh
