// untangle_hexes(): joint untangling of a region of a hex mesh, for the folds that moving
// one point at a time cannot undo (smooth_hex_mesh.cpp).
#pragma once

#include "structmesh/mesh.hpp"
#include "structmesh/quality.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

namespace structmesh::hex_detail {

/// A Verdict sample s = det(a, b, d) / (|a| |b| |d|) and its gradients with respect to a, b
/// and d; false when an edge is degenerate.
inline bool sample_with_gradient(const Vec3& a, const Vec3& b, const Vec3& d, double& s, Vec3& ga, Vec3& gb, Vec3& gd) {
  const double la2 = a.squaredNorm(), lb2 = b.squaredNorm(), ld2 = d.squaredNorm();
  constexpr double kTiny = hex_jacobian_sample::kDegenerateSquaredLength;
  if (la2 <= kTiny || lb2 <= kTiny || ld2 <= kTiny) return false;
  const double lengths = std::sqrt(la2 * lb2 * ld2);
  const Vec3 bd = b.cross(d), da = d.cross(a), ab = a.cross(b);
  s = a.dot(bd) / lengths;
  ga = bd / lengths - s * a / la2;
  gb = da / lengths - s * b / lb2;
  gd = ab / lengths - s * d / ld2;
  return true;
}

/// The 9 Verdict samples of a hex (VTK order: the 8 corners, then the centre's principal
/// axes) and their gradients by node; returns the worst, or -infinity (values and gradients
/// then unset) if a sample is degenerate.
inline double hex_samples_with_gradients(const std::array<Vec3, 8>& p, std::array<double, 9>& value,
                                         std::array<std::array<Vec3, 8>, 9>& gradient) {
  double worst = std::numeric_limits<double>::infinity();
  Vec3 ga, gb, gd;
  std::size_t s = 0;
  for (const auto& [o, i, j, l] : hex_jacobian_sample::kCorners) {
    if (!sample_with_gradient(p[i] - p[o], p[j] - p[o], p[l] - p[o], value[s], ga, gb, gd))
      return -std::numeric_limits<double>::infinity();
    auto& g = gradient[s];
    g.fill(Vec3::Zero());
    g[i] = ga, g[j] = gb, g[l] = gd, g[o] = -(ga + gb + gd);
    worst = std::min(worst, value[s++]);
  }
  std::array<Vec3, 3> axis{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  for (std::size_t i = 0; i < 8; ++i)
    for (std::size_t a = 0; a < 3; ++a) axis[a] += hex_jacobian_sample::kAxisSigns[i][a] * p[i];
  if (!sample_with_gradient(axis[0], axis[1], axis[2], value[8], ga, gb, gd))
    return -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < 8; ++i)
    gradient[8][i] = hex_jacobian_sample::kAxisSigns[i][0] * ga + hex_jacobian_sample::kAxisSigns[i][1] * gb +
                     hex_jacobian_sample::kAxisSigns[i][2] * gd;
  return std::min(worst, value[8]);
}

/// The mean length of the hexes' 12 edges (each edge counted once per hex).
inline double mean_hex_edge_length(const std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes) {
  double edge_sum = 0;
  for (const auto& h : hexes)
    for (std::size_t i = 0; i < 4; ++i)
      edge_sum += (points[h[i]] - points[h[(i + 1) % 4]]).norm() +
                  (points[h[i + 4]] - points[h[(i + 1) % 4 + 4]]).norm() + (points[h[i]] - points[h[i + 4]]).norm();
  return hexes.empty() ? 0.0 : edge_sum / (12.0 * static_cast<double>(hexes.size()));
}

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

struct HexMeanAscentResult {
  double score_sum_before = 0, score_sum_after = 0;  ///< sum of the hexes' scaled Jacobians
  int evaluations = 0;                               ///< of the energy and its gradient
};

/// Moves the points `free` jointly to raise the sum of the scaled Jacobians of `hexes` (the
/// hexes that use them), every hex h kept above floor[h] (which it must be above at the
/// start): L-BFGS on the sum of per-hex soft minima of the 9 Verdict samples, with a log
/// barrier at the floors (raise_mean_scaled_jacobian.cpp), for up to max_iterations L-BFGS
/// iterations (restarted after a failed line search). `points` change only if the sum rose.
/// If `normal` is given (one per free point; zero for none), a free point pays
/// normal_stiffness (d . n)^2 for its offset d from its start along n, in mean hex edges.
HexMeanAscentResult raise_mean_scaled_jacobian(std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes,
                                               std::span<const Index> free, std::span<const double> floor,
                                               int max_iterations, std::span<const Vec3> normal = {},
                                               double normal_stiffness = 0);

}  // namespace structmesh::hex_detail
