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
};

struct PavingStats {
  std::size_t rows = 0;            // rows (layers) generated
  std::size_t seams = 0;           // seam closures of small front angles
  std::size_t splits = 0;          // front loops split or joined by a chord
  std::size_t templates = 0;       // small loops closed by a template
  std::size_t fallback_loops = 0;  // loops closed by the fallback (not by paving)
  /// 1 when the first run failed (a quad it could not untangle, a loop nothing closed)
  /// and a run with a slightly different target size gave this mesh.
  std::size_t retries = 0;
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
// Boundary sampling shared by neighbouring parts

struct SampledPartition {
  /// All boundary sample points of all parts (metric plane); each is stored once,
  /// so neighbouring parts refer to the same index.
  std::vector<Vec2> points;
  std::vector<std::uint8_t> on_region_boundary;  ///< 1 on the region's boundary
  std::vector<std::uint8_t> fixed;               ///< 1 where relaxation may not move it
  /// part -> its loops as a region (outer first) in point indices.
  std::vector<std::vector<std::vector<Index>>> part_loops;
  double size = 0;  ///< the target edge length used
};

/// Samples every curve of the partition with segments of about `size`; separator
/// curves are sampled once and used by both parts; the segment counts are chosen so
/// that every part boundary has an even number of points (§3.3.1). Region boundary
/// curves keep their corners (turning angle above 25°) as samples.
SampledPartition sample_partition(const Partition& partition, double size);

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
  std::size_t rejected_moves = 0;  ///< moves refused because a quad would invert
  int iterations = 0;
};
/// Laplacian relaxation of the vertices within `rings` rings of the separators
/// (§3.3.2): each moves to the mean of its neighbours, in a fixed colour order
/// (deterministic for any thread count); a move that would make an incident quad's
/// scaled Jacobian non-positive (or lower than it was, if it was already low) is refused.
RelaxStats relax_near_separators(MergedMesh& merged, const RelaxOptions& options = {});

// ---------------------------------------------------------------------------
// The whole pipeline on one machine

struct Quad2dOptions {
  double size = 0;               ///< target edge length (metric units); 0: see below
  std::size_t target_quads = 0;  ///< about this many quads (size derived from the area)
  /// With neither: the mean input boundary segment length (§3.3.1).
  PartitionOptions partition;  ///< parts = 0 picks a count for the threads available
  PavingOptions paving;
  RelaxOptions relax;
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
};

struct Quad2dResult {
  MergedMesh merged;
  std::vector<double> scaled_jacobian;  ///< per quad
  Quad2dReport report;
};

/// Partitions, samples, paves every part in parallel (TBB, largest part first),
/// merges and relaxes. The mesh is identical for any thread count.
Quad2dResult mesh_region_quads(const Polygon2& region, const Quad2dOptions& options = {});

/// Size for a wanted quad count: sqrt(area / quads).
double size_for_quad_count(double area, std::size_t quads);

}  // namespace structmesh
