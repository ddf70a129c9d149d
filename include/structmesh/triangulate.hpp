// Constrained Delaunay triangulation of a planar region (design/partition2d.md §2.1).
//
// The first stage of geometry-aware partitioning: the restricted Voronoi clipping
// (§2.2) integrates over these triangles, and the `--method metis` baseline
// partitions a refined triangulation of about N triangles. Coordinates are
// triangulated as given: lon/lat input is projected by a later stage (§2.0).
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace structmesh {

struct TriangulateOptions {
  /// 0: the constrained Delaunay triangulation of the boundary points only.
  /// > 0: Delaunay refinement (Ruppert/Shewchuk, CGAL's Delaunay_mesher_2) with a
  /// minimum angle of about 20.7° (shape bound B = 0.125) and an edge-length bound
  /// chosen so that the result has about this many triangles (within ±25%). The
  /// angle bound alone grades the mesh from the boundary segments, so the count never
  /// drops below that floor (about 3 triangles per boundary segment on the Key and
  /// the Pipe): a smaller target returns the angle-only refinement.
  std::size_t target_triangles = 0;
  /// With target_triangles > 0 and a boundary floor at or above the target: still
  /// bound the edge length as a uniform mesh of target_triangles would, so no
  /// interior triangle is larger than about A / target (the partitioning baselines
  /// need node areas below a part's; the angle-only grading leaves triangles
  /// spanning a sizeable share of the region).
  bool bound_size_above_floor = false;
  /// > 0: before refinement, insert the points of a square grid of this spacing that
  /// lie inside the region and at least a quarter spacing from the boundary
  /// segments of the triangle they fall in. Without interior points a polygon's
  /// triangulation has long slivers across the region; with them every triangle
  /// is at most about a spacing across (the restricted Voronoi clipping of §2.2
  /// then meets only a few cells per triangle).
  double steiner_spacing = 0;
  /// Points at exactly the same coordinates are one vertex, so rings may touch at a
  /// point or pass a point twice (the loops left by advancing-front paving do: an
  /// island's front touching the outer front). Triangles then use the smallest index
  /// of each such group, and boundary_edges lists every ring segment once (zero-length
  /// ones skipped), oriented with the region on its left. Without it a repeated point
  /// is an InputError.
  bool merge_repeated_points = false;
};

struct RegionTriangulation {
  /// The input points first, unchanged and in input order (point i of the Polygon2
  /// is point i here, bit-identical), then the Steiner points added by refinement
  /// (numbered in order of first use by `triangles`).
  std::vector<Vec2> points;
  /// Triangles inside the region, counter-clockwise, each starting at its smallest
  /// vertex id, in Hilbert order of their centroids (deterministic, spatially local).
  std::vector<std::array<Index, 3>> triangles;
  /// The constrained edges (the input segments, subdivided by refinement), each
  /// oriented with the region on its left. Listed ring by ring, every ring walked
  /// from its first input point, so without refinement edge k of a ring is the
  /// input segment k when the ring follows the orientation convention (outer ring
  /// counter-clockwise, holes clockwise), and segment k of the reversed ring otherwise.
  std::vector<std::array<Index, 2>> boundary_edges;
};

/// Triangulates `region`. InputError when the rings are not a valid region boundary:
/// a ring with fewer than 3 points, non-finite or (unless merged) repeated points, crossing
/// segments, or a vertex lying on another segment (what check_region reports as
/// self-intersections; run it first for a full list of problems).
RegionTriangulation triangulate_region(const Polygon2& region, const TriangulateOptions& options = {});

}  // namespace structmesh
