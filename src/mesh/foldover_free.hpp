// Internal: the continuation loop of Garanzha et al. 2021 ("Foldover-free maps in 50 lines of
// code") that quad2d/untangle_quads.cpp (quad corners) and hex/untangle_hexes.cpp (hex
// corners) share. Each supplies its barrier energy, which divides by
//   χ(D, ε) = (D + sqrt(ε² + D²)) / 2,
// finite for inverted elements (D <= 0) while ε > 0; minimising it (L-BFGS, LBFGS++) while ε
// shrinks by the paper's rule pulls every determinant positive without a feasible start.
// Header-only: the two modules link no common library that has LBFGS++ on its include path.
#pragma once

#include <LBFGS.h>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <exception>

namespace structmesh::detail {

inline double foldover_chi(double eps, double det) {
  // The second form avoids cancellation for negative det.
  if (det > 0) return 0.5 * (det + std::sqrt(eps * eps + det * det));
  return 0.5 * eps * eps / (std::sqrt(eps * eps + det * det) - det);
}

inline double foldover_chi_derivative(double eps, double det) {
  return 0.5 + det / (2 * std::sqrt(eps * eps + det * det));
}

struct FoldoverFreeSettings {
  int max_steps = 30;        ///< continuation steps (ε updates)
  int max_iterations = 200;  ///< L-BFGS iterations per step
  bool wolfe = true;         ///< Wolfe backtracking line search (else Armijo)
  /// After a failed line search, go back to where the step started if the energy rose
  /// (LBFGS++ throws with x at its last trial point).
  bool restore_on_failure = false;
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
  LBFGSpp::LBFGSParam<double> param;  // must outlive the solver (held by reference)
  param.m = 8;
  param.epsilon = 1e-8;
  param.epsilon_rel = 0;
  param.past = 2;
  param.delta = 1e-7;
  param.max_iterations = settings.max_iterations;
  param.linesearch =
      settings.wolfe ? LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_WOLFE : LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_ARMIJO;
  param.max_linesearch = 40;
  LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchBacktracking> solver(param);
  Eigen::VectorXd gradient(x.size());
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
  }
  x = best;
  result.min_det_after = best_detmin;
  return result;
}

}  // namespace structmesh::detail
