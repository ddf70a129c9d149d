// Topological cleanup of one part's all-quad mesh (private to the quad2d module):
// local connectivity changes that lower the number of irregular vertices, after
// Canann, Muthukrishnan & Phillips 1998 ("Topological improvement procedures for
// quadrilateral finite element meshes") and Kinney 1997 ("CleanUp: improving
// quadrilateral finite element meshes").
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace structmesh::paving {

struct CleanupStats {
  std::size_t swaps = 0;      // edge rotations
  std::size_t collapses = 0;  // quad diagonal collapses
  std::size_t doublets = 0;   // interior valence-2 points removed
  std::size_t rejected = 0;   // operations undone because no smoothing kept the quads good
  /// Points whose quad count differs from their ideal (interior: 4; boundary:
  /// round(interior angle / 90°), at least 1), before and after.
  std::size_t irregular_before = 0, irregular_after = 0;
  int passes = 0;
};

/// Improves the connectivity of a valid counter-clockwise all-quad mesh of one part.
/// The first `fixed_count` points are its boundary points: they keep their bits and
/// their indices, none is removed and none is added, and every boundary edge stays an
/// edge of exactly one quad. Interior points may move, disappear or be renumbered
/// (they stay in their relative order after the fixed points). `size` is the target
/// edge length (scale of the tolerances). Every quad stays valid (scaled Jacobian >
/// 0) and no operation pushes the worst quad around it below min(its worst before,
/// 0.5). Deterministic: the same input gives the same bits. At most `max_passes` passes
/// (each gathers moves at the irregular points the pass before left or changed).
inline constexpr int kCleanupPasses = 30;
CleanupStats clean_up_quads(std::vector<Vec2>& points, std::vector<std::array<Index, 4>>& quads, Index fixed_count,
                            double size, int max_passes = kCleanupPasses);

}  // namespace structmesh::paving
