// Internal: the LBFGS++ settings every minimisation of the project starts from (the L_p-CVT,
// the foldover-free untanglers, the polish and the ascent of the mean of the hexes).
// Header-only, like foldover_free.hpp: the modules that use it link no common library that
// has LBFGS++ on its include path.
#pragma once

#include <LBFGS.h>

namespace structmesh::detail {

/// 8 corrections; the absolute gradient test only (the relative one scales with |x|, which
/// depends on where the unknowns' origin is); at most 40 backtracking steps of the line
/// search, Wolfe's or Armijo's. The solver holds the returned object by reference: keep it
/// alive as long as the solver.
inline LBFGSpp::LBFGSParam<double> lbfgs_parameters(double epsilon, int max_iterations, bool wolfe) {
  LBFGSpp::LBFGSParam<double> param;
  param.m = 8;
  param.epsilon = epsilon;
  param.epsilon_rel = 0;
  param.max_iterations = max_iterations;
  param.linesearch =
      wolfe ? LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_WOLFE : LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_ARMIJO;
  param.max_linesearch = 40;
  return param;
}

}  // namespace structmesh::detail
