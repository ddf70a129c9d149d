// untangle_hexes(): joint untangling of a region of a hex mesh, for the folds that moving
// one point at a time cannot undo (smooth_hex_mesh.cpp).
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <span>
#include <vector>

namespace structmesh::hex_detail {

struct HexUntangleResult {
  double min_det_before = 0;  ///< smallest corner determinant over the hexes involved, / size^3
  double min_det_after = 0;
  int outer_iterations = 0;
};

/// Moves the points `free` of the hexes (VTK order) jointly so that every corner
/// determinant of the hexes that use them turns positive, by the continuation method of
/// Garanzha et al. 2021 on the eight corner tets and Verdict's centre sample of each hex;
/// `size` is the edge length the Jacobians are measured against. The other points stay.
/// Returns the smallest corner determinant (over size^3) before and after; `points` gets
/// the placement with the largest smallest determinant seen, or the last one once all are
/// positive.
HexUntangleResult untangle_hexes(std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes,
                                 std::span<const Index> free, double size, int max_steps = 30);

struct HexPolishResult {
  double worst_before = 0, worst_after = 0;  ///< worst Verdict sample of the hexes
};

/// Moves the points `free` jointly to raise the worst Verdict sample (8 corners and the
/// centre) of `hexes`, the hexes that use them: L-BFGS on the samples' soft minimum
/// (polish_hexes.cpp). `points` change only if the worst sample rose.
HexPolishResult polish_hexes(std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes,
                             std::span<const Index> free, int max_iterations = 200);

}  // namespace structmesh::hex_detail
