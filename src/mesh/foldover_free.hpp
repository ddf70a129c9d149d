// Internal: the continuation loop of Garanzha et al. 2021 ("Foldover-free maps in 50 lines of
// code") that quad2d/untangle_quads.cpp (quad corners) and hex/untangle_hexes.cpp (hex
// corners) share. Each supplies its barrier energy, which divides by
//   χ(D, ε) = (D + sqrt(ε² + D²)) / 2,
// finite for inverted elements (D <= 0) while ε > 0; minimising it (L-BFGS, LBFGS++) while ε
// shrinks by the paper's rule pulls every determinant positive without a feasible start.
// Header-only: the two modules link no common library that has LBFGS++ on its include path.
#pragma once

#include "mesh/lbfgs_parameters.hpp"

#include <LBFGS.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>

namespace structmesh::detail {

inline double foldover_chi(double eps, double det) {
  // The second form avoids cancellation for negative det.
  if (det > 0) return 0.5 * (det + std::sqrt(eps * eps + det * det));
  return 0.5 * eps * eps / (std::sqrt(eps * eps + det * det) - det);
}

inline double foldover_chi_derivative(double eps, double det) {
  return 0.5 + det / (2 * std::sqrt(eps * eps + det * det));
}

/// The 3D energy of one Jacobian J = [a b d]:
///   (1 - θ) |J|² / χ(det J, ε)^(2/3) + θ (det J² + 1) / χ(det J, ε),  θ = 1/128
/// (the area term small, as in the paper: the shape term does the work), and its gradients
/// with respect to the columns a, b and d.
inline double foldover_energy_3d(double eps, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                 const Eigen::Vector3d& d, Eigen::Vector3d& ga, Eigen::Vector3d& gb,
                                 Eigen::Vector3d& gd) {
  constexpr double kTheta = 1.0 / 128;
  const Eigen::Vector3d bd = b.cross(d), da = d.cross(a), ab = a.cross(b);
  const double det = a.dot(bd);
  const double chi_value = foldover_chi(eps, det), chi_slope = foldover_chi_derivative(eps, det);
  const double frobenius = a.squaredNorm() + b.squaredNorm() + d.squaredNorm();
  const double chi_23 = std::cbrt(chi_value * chi_value);
  const double shape = frobenius / chi_23, area = (det * det + 1) / chi_value;
  // dE/d det, then dE/da = 2 (1 - θ) a / χ^(2/3) + dE/d det * (b x d), and so on.
  const double d_det = (1 - kTheta) * (-2.0 / 3.0) * shape * chi_slope / chi_value +
                       kTheta * (2 * det / chi_value - area * chi_slope / chi_value);
  const double stretch = 2 * (1 - kTheta) / chi_23;
  ga = stretch * a + d_det * bd;
  gb = stretch * b + d_det * da;
  gd = stretch * d + d_det * ab;
  return (1 - kTheta) * shape + kTheta * area;
}

struct FoldoverFreeSettings {
  int max_steps = 30;        ///< continuation steps (ε updates)
  int max_iterations = 200;  ///< L-BFGS iterations per step
  bool wolfe = true;         ///< Wolfe backtracking line search (else Armijo)
  /// After a failed line search, go back to where the step started if the energy rose
  /// (LBFGS++ throws with x at its last trial point).
  bool restore_on_failure = false;
  /// Continuation steps after the first one that ends with every determinant positive (the
  /// steps after it only improve the elements' shapes).
  int max_steps_once_valid = std::numeric_limits<int>::max();
  /// Asked after each step with the number of steps done; true ends the loop (the caller's
  /// judgement that it is getting nowhere).
  std::function<bool(int steps)> give_up;
};

struct FoldoverFreeResult {
  double min_det_before = 0, min_det_after = 0;
  int outer_iterations = 0;
};

/// Minimises energy(x, gradient) (which reads `eps`) while updating eps, from x; x gets the
/// placement with the largest smallest determinant min_det(x) seen, or the latest once it is
/// positive (lower energy: better shaped elements).
template <class Energy, class MinDet>
FoldoverFreeResult minimize_foldover_free(Eigen::VectorXd& x, double& eps, Energy&& energy, MinDet&& min_det,
                                          const FoldoverFreeSettings& settings) {
  FoldoverFreeResult result;
  double detmin = min_det(x);
  result.min_det_before = detmin;
  eps = std::sqrt(1e-12 + 0.04 * std::pow(std::min(detmin, 0.0), 2));
  Eigen::VectorXd best = x;
  double best_detmin = detmin;
  LBFGSpp::LBFGSParam<double> param = lbfgs_parameters(1e-8, settings.max_iterations, settings.wolfe);
  param.past = 2;
  param.delta = 1e-7;
  LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchBacktracking> solver(param);
  Eigen::VectorXd gradient(x.size());
  int valid_steps = 0;  // steps that ended valid
  for (int outer = 0; outer < settings.max_steps; ++outer) {
    result.outer_iterations = outer + 1;
    const double before = energy(x, gradient);
    double after = before;
    const Eigen::VectorXd start = settings.restore_on_failure ? x : Eigen::VectorXd();
    try {
      solver.minimize(energy, x, after);
    } catch (const std::exception&) {
      after = energy(x, gradient);
      if (settings.restore_on_failure && !(after <= before)) x = start, after = before;
    }
    if (!std::isfinite(after)) {
      x = best;
      break;
    }
    detmin = min_det(x);
    if (detmin > 0 || detmin > best_detmin) best = x, best_detmin = detmin;
    const double sigma = std::max(1 - after / before, 0.1);
    const double mu = (1 - sigma) * foldover_chi(eps, detmin);
    eps = detmin < mu ? 2 * std::sqrt(mu * (mu - detmin)) : 1e-10;
    if (detmin > 0 && std::abs(before - after) <= 1e-4 * std::abs(after)) break;
    if (detmin > 0 && ++valid_steps > settings.max_steps_once_valid) break;
    if (settings.give_up && settings.give_up(outer + 1)) break;
  }
  x = best;
  result.min_det_after = best_detmin;
  return result;
}

}  // namespace structmesh::detail
