// Untangling of a quad mesh zone (private to the quad2d module): moves the free points
// so that every corner of every quad around them turns positive, by the continuation
// method of Garanzha, Kaporin, Kudryavtseva, Protais, Ray & Sokolov 2021 ("Foldover-free
// maps in 50 lines of code", ACM TOG 40(4)).
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace structmesh::paving {

/// The shape term of each corner's energy (divided by χ(det J, ε) ≈ det J):
/// `conformal` is |J|² (the paper's: right angles and equal legs), `angle` is
/// 2 |J e1| |J e2| (right angles only, whatever the legs' ratio: 1 / sin of the
/// corner angle at ε = 0, what the scaled Jacobian measures).
enum class CornerEnergy : std::uint8_t { conformal, angle };

struct UntangleResult {
  bool valid = false;                            ///< every corner of every quad touching a free point is positive
  int outer_iterations = 0;                      ///< continuation steps (each one L-BFGS minimisation)
  double min_det_before = 0, min_det_after = 0;  ///< smallest corner cross product / size²
};

/// Moves the points listed in `free` (and no other) to make the quads that touch them
/// valid. Quads whose first index is kInvalidIndex are skipped. `size` is the target
/// edge length: each quad corner is compared with a right angle of legs `size`.
/// At most `max_steps` continuation steps of up to 300 L-BFGS iterations each.
/// Deterministic. When no valid placement is found the points are left where the best
/// attempt put them (the caller checks `valid` and falls back to remeshing).
UntangleResult untangle_quads(std::vector<Vec2>& points, std::span<const std::array<Index, 4>> quads,
                              std::span<const Index> free, double size, int max_steps = 80,
                              CornerEnergy kind = CornerEnergy::conformal);

/// The smallest scaled Jacobian of the quads (Verdict's quad measure, +z reference);
/// quads whose first index is kInvalidIndex are skipped; +inf for none.
double min_scaled_jacobian(std::span<const Vec2> points, std::span<const std::array<Index, 4>> quads);

/// Shape optimisation of a quad mesh whose points from `fixed_count` on may move:
/// untangle_quads() with the angle energy (at its small final ε, the sum of 1 / sin
/// of the corner angles) over all movable points; a mesh of more than 20k of them is
/// left as it is. Keeps the result
/// when the smallest scaled Jacobian rises, or the mean rises while the smallest stays
/// at least min(before, threshold); returns the smallest scaled Jacobian kept.
double polish_quads(std::vector<Vec2>& points, std::span<const std::array<Index, 4>> quads, Index fixed_count,
                    double size, double threshold);

}  // namespace structmesh::paving
