// Parallel all-quad meshing of large planar regions (dissertation ch. 3.3-3.4):
// partition the region (partition2d.hpp), sample every part boundary consistently
// with an even vertex count per part (§3.3.1), mesh every part with our own
// advancing-front paving (Blacker & Stephenson 1991), merge by construction and
// relax near the separators (§3.3.2).
//
// The stages are plain functions so that the threaded driver (mesh_region_quads)
// and the MPI driver (apps/structmesh/cmd_quad2d.cpp) run the same code: both
// produce bit-identical meshes.
#pragma once

#include "structmesh/mesh.hpp"
#include "structmesh/partition2d.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace structmesh {

// ---------------------------------------------------------------------------
// Per-part mesher: paving

struct PavingOptions {
  /// Target edge length; 0 = the mean boundary edge length of the part.
  double size = 0;
  /// Smoothing sweeps after every row and at the end (interior vertices only).
  int smoothing_iterations = 3;
  int final_smoothing_iterations = 20;
  /// A part of at least this many expected quads (area / size²) gets a structured grid
  /// of squares in its interior and is paved only in a band along its boundary (paving
  /// is ~90k quads/s per core, the grid millions); 0 paves every part whole.
  std::size_t grid_interior_quads = 20000;
};

struct PavingStats {
  std::size_t rows = 0;            // rows (layers) generated
  std::size_t seams = 0;           // seam closures of small front angles
  std::size_t splits = 0;          // front loops split or joined by a chord
  std::size_t templates = 0;       // small loops closed by a template
  std::size_t fallback_loops = 0;  // loops closed by the fallback (not by paving)
  std::size_t repairs = 0;         // neighbourhoods of inverted quads remeshed by the fallback
  std::size_t untangled = 0;       // zones of inverted quads made valid by untangle_quads()
  std::size_t mapped = 0;          // parts meshed as a structured grid (mapped_mesh), not paved
  std::size_t polar = 0;           // parts meshed as polar blocks (polar_mesh)
  /// Of those, parts whose blocks the interval assignment had not planned or that failed
  /// the quality check as planned: polar blocks chosen for their fixed counts
  /// (polar_block_candidates) instead of paving.
  std::size_t unplanned_blocks = 0;
  /// 1 when the first run failed (a quad it could not untangle, a loop nothing closed)
  /// and a run with a slightly different target size gave this mesh.
  std::size_t retries = 0;
  /// Topological cleanup after paving (edge rotations, diagonal collapses, doublets).
  std::size_t cleanup_operations = 0;
  /// Quads of the structured grid inside a large part (pave_with_grid_interior).
  std::size_t grid_interior_quads = 0;
};

struct PavedPart {
  /// The input boundary points first, unchanged (bit-identical) and in input
  /// order, then the new interior points.
  std::vector<Vec2> points;
  /// Counter-clockwise quads (positive area).
  std::vector<std::array<Index, 4>> quads;
  PavingStats stats;
};

/// All-quad mesh of one part. `boundary` holds the loops like a region: ring 0 is
/// the outer loop (counter-clockwise), the others are holes (clockwise); every
/// boundary point is kept and no point is added on the boundary, so each boundary
/// edge is an edge of exactly one quad. InputError when the total number of boundary
/// points is odd or a loop has fewer than 3 points; Error when the front cannot be
/// closed (reported, never silent).
PavedPart pave(const Polygon2& boundary, const PavingOptions& options = {});

// ---------------------------------------------------------------------------
// Per-part mesher: mapped (structured) grid of a four-sided part

struct MappedMeshOptions {
  int smoothing_iterations = 60;     ///< elliptic (Winslow) smoothing sweeps of the interior (over-relaxed)
  double min_scaled_jacobian = 0.6;  ///< below this anywhere: return std::nullopt (the caller paves instead)
};

/// Structured mesh of a part whose single loop (ring 0 of `boundary`, counter-clockwise,
/// no holes) has four corners at loop positions corners[0] < corners[1] < corners[2] < corners[3],
/// with side point counts matching: (corners[1]-corners[0]) == (corners[3]-corners[2]) and
/// (corners[2]-corners[1]) == (n - corners[3] + corners[0]). Returns the grid (input points first,
/// bit-identical, in input order, then interior points; counter-clockwise quads, every boundary edge
/// in exactly one quad), or std::nullopt when the map folds or a quad's scaled Jacobian stays below
/// options.min_scaled_jacobian after smoothing and an optimisation of the best smoothed grid.
/// InputError for inconsistent corners.
std::optional<PavedPart> mapped_mesh(const Polygon2& boundary, const std::array<std::size_t, 4>& corners,
                                     const MappedMeshOptions& options = {});

/// A part with n >= 3 corners cut into n four-sided blocks around a centre point
/// (midpoint subdivision): block i has corner i, the split points of the sides
/// before and after it, and the centre. Side i runs from corner i to corner i+1 and
/// is split at loop position splits[i]; the straight chord from that split point to
/// the centre has chord_segments[i] segments. The blocks' opposite sides match when
/// (splits[i] - corners[i]) == chord_segments[i-1] and
/// (corners[i+1] - splits[i]) == chord_segments[i+1] (indices modulo n).
///
/// A block may instead be a triangle (triangle[i] = 1): its corner is only a point of a
/// straight side between the split points i-1 and i, and the block (that stretch of the
/// loop, chord i, chord i-1) is meshed as three blocks around a centre of its own. Its
/// counts need only an even sum and strict triangle inequalities. One such block in a
/// four-cornered part gives the transition layout of transition_block_candidates().
struct PolarBlocks {
  std::vector<std::int64_t> corners;  ///< loop positions, ascending; empty = not used
  std::vector<std::int64_t> splits;
  std::vector<Index> chord_segments;
  std::vector<std::uint8_t> triangle;  ///< per block: 1 = a triangle block; empty = none
};

/// The mesh of a PolarBlocks decomposition: every block a structured grid
/// (mapped_mesh), so the only interior singular vertex is the centre (valence n).
/// Input points first and bit-identical, like pave(). std::nullopt when the centre
/// (the area centroid) is outside the part or a block's grid folds; InputError for
/// inconsistent blocks.
/// `polished_min`, when given, receives the smallest scaled Jacobian the blocks reached
/// after their polish (-inf when they were not made: the centre outside, a block folded).
std::optional<PavedPart> polar_mesh(const Polygon2& boundary, const PolarBlocks& blocks,
                                    const MappedMeshOptions& options = {}, double* polished_min = nullptr);

/// Polar layouts that fit a part's boundary as it is sampled (its point count fixed and
/// even, one loop), for the parts the interval assignment gave no layout or whose layout
/// failed polar_mesh()'s quality check. Corners are where the loop turns by more than
/// 30° (over consecutive points bent by more than 10° each, at the sharpest of them);
/// with k of them (odd, 3 <= k <= 7, chosen from the 7 sharpest; none for a part with
/// more than 8) side i has r_{i-1} + r_{i+1} points, which fixes the chord counts r.
/// A corner set whose r are not positive integers is tried with one corner moved by one
/// point. Layouts come best first by the turn of the corners they leave out plus the
/// chords' deviation from their length to the loop's mean point; at most `max_candidates`; empty
/// for a part with holes, an odd loop or fewer than 3 corners.
std::vector<PolarBlocks> polar_block_candidates(const Polygon2& boundary, std::size_t max_candidates = 3);

/// Transition layouts for a part with four corners (found as in polar_block_candidates();
/// of a part with more, the four that leave out the least turn) whose opposite sides
/// differ, so that no grid fits: grid blocks at the corners around a centre of valence 5
/// and a triangle block (PolarBlocks::triangle) on a long side, which takes up the
/// difference of that side and the one opposite; the triangle's own centre has valence
/// 3. So the part gets two interior singular vertices (a 3-5 pair) where a three-block
/// layout must leave a corner inside a block side and paving leaves dozens. With s_0 the
/// long side and s_2 the one opposite, the triangle's base is s_0 - s_2 and its legs
/// s_3 - h and s_1 - h (h the chord to side 2). Layouts come best first: least turn
/// left out, then the triangle closest to equilateral; at most `max_candidates`, one
/// per corner set and side; empty for a part with holes, an odd loop or fewer than four
/// corners.
std::vector<PolarBlocks> transition_block_candidates(const Polygon2& boundary, std::size_t max_candidates = 3);

// ---------------------------------------------------------------------------
// Boundary sampling shared by neighbouring parts

struct SampledPartition {
  /// All boundary sample points of all parts (metric plane); each is stored once,
  /// so neighbouring parts refer to the same index.
  std::vector<Vec2> points;
  std::vector<std::uint8_t> on_region_boundary;  ///< 1 on the region's boundary
  std::vector<std::uint8_t> fixed;               ///< 1 where relaxation may not move it
  /// part -> its loops as a region (outer first) in point indices.
  std::vector<std::vector<std::vector<Index>>> part_loops;
  /// Per part: the loop positions of its four corners when the part is four-sided
  /// with equal point counts on opposite sides (a structured grid fits), else all -1.
  std::vector<std::array<std::int64_t, 4>> part_corners;
  /// Per part: a polar block decomposition for the one-loop parts with 3 or more
  /// corners that are not four-sided (corners empty when none).
  std::vector<PolarBlocks> part_polar;
  double size = 0;  ///< the target edge length used
};

/// Samples every curve of the partition with segments of about `size`; separator
/// curves are sampled once and used by both parts. Region boundary curves keep their
/// corners (turning angle above 25°) as samples. The segment counts are chosen
/// together (interval assignment, an MILP with CBC) so that every part boundary has
/// an even number of points (§3.3.1) and every four-sided part (four corners below
/// 135°, no other break outside 150°..225°) has equal counts on opposite sides where
/// that costs little (blocks = true); if CBC finds nothing, rounding plus a parity repair.
SampledPartition sample_partition(const Partition& partition, double size, bool blocks = true);

/// Merges the two end junctions of every separator curve shorter than `min_length`
/// (metric plane) and drops the curve from the partition and its parts' loops, so that
/// sampling leaves no boundary edge of almost no length at a corner. The end on the
/// region's boundary is the one kept; a curve with both ends on it, or whose removal
/// would leave a loop of fewer than three curves, stays. Partition::parts, part_areas
/// and metrics are left as they were (they move by less than `min_length`). Returns the
/// curves removed.
std::size_t collapse_tiny_separators(Partition& partition, double min_length);

/// The part's boundary as a Polygon2 for pave(), and the map from its points to
/// the SampledPartition's point indices.
std::pair<Polygon2, std::vector<Index>> part_boundary(const SampledPartition& sampled, std::size_t part);

// ---------------------------------------------------------------------------
// Merge and relaxation

struct MergedMesh {
  QuadMesh mesh;  ///< z = 0
  std::vector<std::int32_t> part_of_quad;
  std::vector<std::uint8_t> fixed;      ///< per point: region boundary (never moved)
  std::vector<std::uint8_t> separator;  ///< per point: on a separator
  double size = 0;                      ///< the sampling size (relaxation's length scale)
};

/// Glues the paved parts: boundary points are the sampled points (identified by
/// construction), interior points follow part by part in part order.
MergedMesh merge_parts(const SampledPartition& sampled, std::span<const PavedPart> parts,
                       std::span<const std::vector<Index>> boundary_maps);

struct RelaxOptions {
  int rings = 5;        ///< vertices within this many edge rings of a separator move
  int iterations = 50;  ///< Laplacian sweeps (§3.3.2)
};
struct RelaxStats {
  std::size_t moved_vertices = 0;  ///< vertices in the relaxation zone
  std::size_t rejected_moves = 0;  ///< moves refused (summed over sweeps) because a quad would invert
  int iterations = 0;
};

/// One process's share of a mesh for relax_piece(): its own quads first, then ghost
/// quads (other processes' quads that touch its points) so that every owned vertex
/// sees its whole one-ring. Points are local; `global` gives their merged-mesh index.
struct RelaxPiece {
  std::vector<Vec3> points;
  std::vector<std::array<Index, 4>> quads;
  std::size_t own_quads = 0;
  std::vector<Index> global;
  std::vector<std::uint8_t> owned;      ///< 1: this process decides this point
  std::vector<std::uint8_t> fixed;      ///< region boundary
  std::vector<std::uint8_t> separator;  ///< on a separator
  double size = 0;                      ///< length scale of the convergence test
};

/// Exchanges between the processes that hold copies of a point. The defaults are
/// those of a single process (nothing to exchange).
struct RelaxComm {
  std::function<void(std::vector<Vec3>&)> sync_points = [](std::vector<Vec3>&) {};                 ///< owner -> copies
  std::function<void(std::vector<std::uint8_t>&)> sync_flags = [](std::vector<std::uint8_t>&) {};  ///< owner -> copies
  std::function<void(std::vector<std::uint8_t>&)> and_flags = [](std::vector<std::uint8_t>&) {};  ///< AND of all copies
  std::function<bool(bool)> any = [](bool value) { return value; };
  std::function<double(double)> max = [](double value) { return value; };
  std::function<std::size_t(std::size_t)> sum = [](std::size_t value) { return value; };
  bool exchanges = false;  ///< true when the hooks really exchange (more than one process)
};

/// relax_near_separators() on one process's piece; with the same inputs split over
/// processes the result is bit-identical to the whole mesh relaxed at once.
RelaxStats relax_piece(RelaxPiece& piece, const RelaxOptions& options, const RelaxComm& comm);

/// Laplacian relaxation of the vertices within `rings` rings of the separators
/// (§3.3.2): Jacobi sweeps, each vertex to the mean of its edge neighbours; a move
/// that would make an incident quad's scaled Jacobian non-positive (or lower than
/// min(its value, 0.5)) is refused. Bit-identical for any thread count or MPI split.
RelaxStats relax_near_separators(MergedMesh& merged, const RelaxOptions& options = {});

// ---------------------------------------------------------------------------
// The whole pipeline on one machine

struct Quad2dOptions {
  double size = 0;               ///< target edge length (metric units); 0: see below
  std::size_t target_quads = 0;  ///< about this many quads (size derived from the area)
  /// With neither: the mean input boundary segment length (§3.3.1).
  /// parts = 0 (the default here): default_part_count().
  PartitionOptions partition = [] {
    PartitionOptions defaults;
    defaults.parts = 0;
    return defaults;
  }();
  /// Ignore partition.cells and use about one CVT cell per 100 quads, within
  /// [max(24 parts, 256), 4000]: a part needs ~24 cells for balance, and more cells
  /// than that only cost time when the quads are few.
  bool auto_cells = true;
  PavingOptions paving;
  RelaxOptions relax;
  /// Structured blocks where they fit: four-sided parts as one grid (mapped_mesh),
  /// other parts with 3..8 corners as polar blocks (polar_mesh), paving for the
  /// rest. false: the dissertation's paving of every part.
  bool blocks = true;
  /// Before partitioning, water narrower than min_channel element sizes is closed and
  /// islands smaller than min_island element areas are dropped (remove_narrow_water()):
  /// boundary samples an element apart on both banks of a creek leave no room for a
  /// valid quad. Measured on the Gulf of Mexico (bench/quad2d/notes.md): at 0.5, paving
  /// still fails in a few parts of some partitions (1M quads in 1024 parts); at 1 every
  /// Table 3.4 configuration meshes. 0 keeps every feature.
  double min_channel = 1.0;
  double min_island = 0.25;
  bool progress = false;
};

struct Quad2dReport {
  std::size_t quads = 0, points = 0, parts = 0;
  double size = 0;
  double scaled_jacobian_avg = 0, scaled_jacobian_std = 0, scaled_jacobian_min = 0;
  std::size_t inverted = 0, singular_vertices = 0;
  double region_area = 0, mesh_area = 0;
  PavingStats paving;  ///< summed over parts
  RelaxStats relax;
  std::vector<double> part_seconds;  ///< meshing time per part
  std::vector<std::pair<std::string, double>> stage_seconds;
  double peak_rss_mb = 0;
  std::string projection;  ///< "" or the LAEA projection the mesh is written in
  PartitionMetrics partition;
  NarrowWaterReport coastline_filter;  ///< what min_channel / min_island removed
};

struct Quad2dResult {
  MergedMesh merged;
  std::vector<double> scaled_jacobian;  ///< per quad
  Quad2dReport report;
};

/// The stages before paving: the size (from --size, --quads or the mean input
/// boundary segment), the part count (default_part_count with `processes`), the
/// partition and the consistent samples.
struct Quad2dSetup {
  Partition partition;
  SampledPartition sampled;
  double size = 0;
  std::vector<std::pair<std::string, double>> stage_seconds;
};
Quad2dSetup setup_quad2d(const Polygon2& region, const Quad2dOptions& options, std::size_t processes = 1);

/// Predicted meshing work of a part, in units of one paved quad: its expected quad
/// count (area / size²), times kBlockWorkFactor when it is a structured grid candidate
/// (measured: a mapped part costs about a tenth of a paved one of the same area; polar
/// parts, polished as a whole, cost about as much as paved ones). Orders the threads' parts and assigns parts to MPI
/// ranks.
inline constexpr double kBlockWorkFactor = 0.15;
double predicted_part_work(const Quad2dSetup& setup, std::size_t part);

/// Meshes the listed parts in parallel (TBB): each worker takes the part of largest
/// predicted work left (LPT order); the other entries of the result stay empty.
/// part_seconds gets each part's meshing time.
std::vector<PavedPart> pave_parts(const Quad2dSetup& setup, std::span<const std::size_t> parts,
                                  const PavingOptions& options, std::vector<double>& part_seconds, bool progress);

/// Partitions, samples, paves every part in parallel (TBB, largest work first),
/// merges and relaxes. The mesh is identical for any thread count.
Quad2dResult mesh_region_quads(const Polygon2& region, const Quad2dOptions& options = {});

/// Parts for an expected quad count when none are asked for: 1 below 20k quads,
/// else the largest of 8, one per 500k quads and two per process (MPI rank).
/// Independent of the thread count.
std::size_t default_part_count(std::size_t expected_quads, std::size_t processes);

/// Process of each part: longest predicted work first onto the least loaded
/// process (LPT; ties to the lowest process). InputError for zero processes.
std::vector<std::int32_t> assign_parts(std::span<const double> work, std::size_t processes);
/// Speedup of that assignment over one process: sum of work / largest load.
double predicted_speedup(std::span<const double> work, std::size_t processes);

/// Maps mesh points from the metric plane of a lon/lat region back to degrees
/// (the inverse of the projection partition_region() chose). InputError for a
/// planar region.
void points_to_lonlat(const Polygon2& region, std::vector<Vec3>& points);

/// Signed area of a planar quad mesh (positive for counter-clockwise quads).
double quad_mesh_area(const QuadMesh& mesh);

/// Size for a wanted quad count: sqrt(area / quads).
double size_for_quad_count(double area, std::size_t quads);

}  // namespace structmesh
