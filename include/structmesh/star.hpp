// Star decomposition of a tetrahedral solid (dissertation §2.3): split the tets into
// parts that are each star-shaped with respect to their guard, growing the parts from
// the guards of §2.2.
//
// Growth rule (exact). A union R of tets is star-shaped with respect to a point g
// whenever g lies strictly on the inner side of the plane of every boundary face of R:
// along any ray from g each boundary crossing then goes from inside to outside, so a
// ray can leave R but never re-enter it, and R is non-empty only if it contains g. A
// tet t may therefore join the part of guard g when g lies strictly on t's side of
// every face of t that is not shared with a tet already in the part (the faces t adds
// to the part's boundary); the faces it shares stop being boundary faces. The test is
// CGAL's exact orientation predicate, so grown parts are star-shaped exactly, not up
// to a tolerance. This replaces the dissertation's visibility-dependency graph (the
// sets T~(g, t) of §2.3), which is a sufficient condition of the same kind but needs
// segment-face intersections per vertex, and which the dissertation then relaxes.
//
// Growth order. Candidate tets are taken in increasing power distance of the guard to
// their circumsphere, |g - c|^2 - r^2: for a Delaunay tetrahedralization this order is
// a visibility order from g (Edelsbrunner's acyclicity theorem), so a convex Delaunay
// solid grows whole from one guard; all parts grow at once from one queue, a tet going
// to the first part that may take it.
#pragma once

#include "structmesh/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace structmesh {

struct StarOptions {
  /// Every part star-shaped: tets no part could take are re-guarded (a new guard at
  /// the deepest tet of each leftover component, grown by the same exact rule) until
  /// none is left. Without it, leftover components of at most `merge_max_tets` tets
  /// join the part they share most faces with first (the dissertation's relaxation;
  /// fewer, slightly imperfect parts), if the vertex moves (below) leave at most
  /// `merge_max_violations` of their faces breaking the rule; the others are re-guarded.
  bool strict = false;
  std::size_t merge_max_tets = 64;
  /// Without `strict`: the most faces breaking the growth rule a merged component may
  /// keep. Rocker arm (307k tets, the same guards): any number, 101 parts with 99.930% of
  /// part vertices visible; at most 8, 104 / 99.938%; 4, 118 / 99.958%; 2, 149 / 99.974%
  /// (merging components of at most 32 tets instead of 64, with no such bound: 149 /
  /// 99.962%). With no bound one bench run of the 3holes solid fell to 99.86%.
  std::size_t merge_max_violations = 4;
  /// Leftover components of at most this many tets first try to join a neighbouring
  /// part with interior vertices moved so that the rule holds again (exactly
  /// star-shaped; both modes). 0: never.
  std::size_t repair_max_tets = 4096;
  /// Laplacian smoothing sweeps of the inner borders (§2.3): each vertex on an
  /// interface between parts, off the solid's boundary, moves towards the mean of its
  /// interface neighbours, a move being kept only when no tet around it inverts and
  /// every interface face around it still passes the growth rule for the guards on
  /// both of its sides (so star-shaped parts stay star-shaped). 0: no smoothing.
  int smoothing_iterations = 10;
  bool progress = false;
};

struct StarPart {
  Vec3 guard;
  bool added = false;  ///< a guard placed for leftover tets (not one of the input guards)
  std::size_t tets = 0;
  double volume = 0;
  std::size_t vertices = 0;           ///< distinct vertices of the part's tets
  std::size_t visible_vertices = 0;   ///< of those, seen from the guard within the part
  std::size_t kernel_violations = 0;  ///< boundary faces whose plane does not have the guard strictly inside
  bool star_shaped = false;           ///< kernel_violations == 0 (exact: the part is star-shaped w.r.t. its guard)
};

struct StarResult {
  std::vector<Index> tet_part;  ///< per tet: its part
  std::vector<StarPart> parts;
  std::vector<Vec3> points;  ///< the mesh points after smoothing (the input points without it)
  std::size_t input_guards = 0;
  std::size_t dropped_guards = 0;      ///< input guards outside the solid or in a tet another guard took
  std::size_t moved_guards = 0;        ///< input guards on a face, edge or vertex, moved into a tet
  std::size_t absorbed_tets = 0;       ///< leftover components a part took whole by the exact rule
  std::size_t repaired_tets = 0;       ///< leftover tets joined to a part after moving vertices restored the rule
  std::size_t merged_tets = 0;         ///< leftover tets merged into a neighbouring part regardless (not strict)
  std::size_t relocated_vertices = 0;  ///< interior vertices moved to restore the rule
  std::size_t growth_rounds = 0;       ///< 1 + rounds of re-guarding leftovers
  std::size_t smoothed_vertices = 0;   ///< inner-border vertices the smoothing moved
  double interface_area_before = 0, interface_area_after = 0;  ///< area of the faces between parts
  double visible_fraction = 0;                                 ///< sum of visible_vertices / sum of vertices over parts
  std::vector<std::pair<std::string, double>> stage_seconds;
};

/// Star decomposition of `solid` seeded by `guards` (typically guard_surface() of its
/// boundary). Every tet ends in exactly one part and every part is face-connected.
/// InputError for an empty mesh, a tet of non-positive volume (orientation: the
/// points of a tet must be positively oriented) or a face shared by more than two tets.
/// No guards (or none inside) is allowed: the parts then all come from re-guarding.
StarResult star_decomposition(const TetMesh& solid, std::span<const Vec3> guards, const StarOptions& options = {});

/// Exact test of the growth rule on a finished part: the number of boundary faces of
/// the tets with tet_part == part (faces not shared with another tet of the part)
/// whose plane does not have `guard` strictly on the part's side. 0 means the part is
/// star-shaped with respect to `guard` (see the top of this header).
std::size_t kernel_violations(const TetMesh& solid, std::span<const Index> tet_part, Index part, const Vec3& guard);

/// Face neighbours of every tet: neighbors[t][i] is the tet across the face opposite
/// vertex i of t (kInvalidIndex on the boundary). InputError when a face belongs to
/// more than two tets.
std::vector<std::array<Index, 4>> tet_neighbors(const TetMesh& solid);

}  // namespace structmesh
