// Exact geometric tests behind check_surface(), kept in one translation unit
// (self_intersections.cpp) because CGAL is slow to compile.
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <span>
#include <vector>

namespace structmesh::detail {

/// Exact test (CGAL filtered predicate): do p, q, r lie on one line (zero-area triangle)?
bool collinear(const Vec3& p, const Vec3& q, const Vec3& r);

/// Face pairs found by find_self_intersections(). Faces are numbered in bundle
/// cell order: all triangles, then all quads. Every pair has a < b; pairs are sorted.
struct SelfIntersections {
  /// Faces that share no vertex index and touch or cross (exact test).
  std::vector<std::array<Index, 2>> disjoint_pairs;
  /// Triangles that share one or two vertex indices (or all three: duplicates) and
  /// whose intersection is more than the shared vertex or edge: folds and overlaps.
  std::vector<std::array<Index, 2>> adjacent_overlaps;
};

/// Every intersecting pair of faces. A quad is tested as its two triangles
/// (0,1,2) and (0,2,3); a zero-area triangle as the segment between its two
/// farthest points (or as a point). Indices must be in range.
/// `adjacent_overlaps` is filled only for triangle-triangle pairs and only when
/// `find_adjacent` is set; quads sharing a vertex with another face are not tested.
SelfIntersections find_self_intersections(std::span<const Vec3> points, std::span<const std::array<Index, 3>> triangles,
                                          std::span<const std::array<Index, 4>> quads, bool find_adjacent);

}  // namespace structmesh::detail
