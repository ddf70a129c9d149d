// ilp_set_cover(): optimal guarding, ILP (2.2)-(2.3) of §2.2.2, on the instance left
// by the reductions of §2.2.3, solved by COIN-OR CBC (the dissertation used TomLab).
#include "guard/set_cover_input.hpp"
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"

#include <CbcModel.hpp>
#include <CbcSolver.hpp>
#include <CoinPackedMatrix.hpp>
#include <OsiClpSolverInterface.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

namespace structmesh {

namespace {

struct CbcOutcome {
  std::vector<Index> chosen;  // positions in the reduced instance; empty if CBC found none
  bool optimal = false;
  double bound = 0;
};

CbcOutcome solve_with_cbc(const CompressedRows& sets, std::size_t row_count, const std::vector<Index>& start,
                          double time_limit_seconds) {
  const int columns = static_cast<int>(sets.row_count());
  CoinPackedMatrix matrix(true, 0, 0);
  matrix.setDimensions(static_cast<int>(row_count), 0);
  for (std::size_t c = 0; c < sets.row_count(); ++c) {
    const auto rows = sets.row(c);
    const std::vector<int> index(rows.begin(), rows.end());
    const std::vector<double> value(rows.size(), 1.0);
    matrix.appendCol(static_cast<int>(index.size()), index.data(), value.data());
  }
  // (2.2): minimise the number of chosen sets; (2.3): each element covered at least once.
  const std::vector<double> column_lo(columns, 0.0), column_hi(columns, 1.0), objective(columns, 1.0);
  const std::vector<double> row_lo(row_count, 1.0), row_hi(row_count, COIN_DBL_MAX);
  OsiClpSolverInterface solver;
  solver.messageHandler()->setLogLevel(0);
  solver.loadProblem(matrix, column_lo.data(), column_hi.data(), objective.data(), row_lo.data(), row_hi.data());
  for (int c = 0; c < columns; ++c) solver.setInteger(c);

  CbcModel model(solver);
  CbcSolverUsefulData data;
  CbcMain0(model, data);
  model.messageHandler()->setLogLevel(0);
  model.solver()->messageHandler()->setLogLevel(0);
  // The greedy cover as the incumbent: CBC prunes against it from the start, and a
  // time-out still leaves a solution at least this good.
  std::vector<double> incumbent(columns, 0.0);
  for (const Index c : start) incumbent[c] = 1.0;
  model.setBestSolution(incumbent.data(), columns, static_cast<double>(start.size()), true);
  const std::string seconds = std::to_string(time_limit_seconds);
  // The stand-alone solver's defaults (preprocessing, cuts, heuristics) pay off on
  // set cover; wall-clock time so the limit means what the caller waits.
  const char* arguments[] = {"cbc",  "-log",          "0",      "-slog", "0", "-timeMode", "elapsed",
                             "-sec", seconds.c_str(), "-solve", "-quit"};
  CbcMain1(static_cast<int>(std::size(arguments)), arguments, model, nullptr, data);

  CbcOutcome outcome;
  outcome.optimal = model.isProvenOptimal();
  outcome.bound = model.getBestPossibleObjValue();
  const double* best = model.bestSolution();
  if (best != nullptr && model.getNumCols() == columns)
    for (int c = 0; c < columns; ++c)
      if (best[c] > 0.5) outcome.chosen.push_back(static_cast<Index>(c));
  return outcome;
}

}  // namespace

IlpSetCoverResult ilp_set_cover(const CompressedRows& sets, std::size_t element_count, double time_limit_seconds) {
  const auto started = std::chrono::steady_clock::now();
  const SetCoverReduction reduction = reduce_set_cover(sets, element_count);
  IlpSetCoverResult result;
  result.rows_before = reduction.rows_before;
  result.rows_after = reduction.rows_after;
  result.columns_before = reduction.columns_before;
  result.columns_after = reduction.columns_after;

  std::vector<Index> picked;  // positions in the reduced instance
  result.optimal = true;      // the reductions keep an optimum; nothing left to solve is optimal
  if (reduction.rows_after > 0) {
    const std::vector<Index> greedy = greedy_set_cover(reduction.reduced_sets, reduction.rows_after);
    picked = greedy;
    result.optimal = false;
    if (time_limit_seconds > 0) {
      CbcOutcome cbc = solve_with_cbc(reduction.reduced_sets, reduction.rows_after, greedy, time_limit_seconds);
      if (!cbc.chosen.empty() && cbc.chosen.size() <= greedy.size() &&
          covers_all(reduction.reduced_sets, reduction.rows_after, cbc.chosen)) {
        picked = std::move(cbc.chosen);
        result.optimal = cbc.optimal;
      }
      // A bound a hair above an integer is that integer (LP tolerances).
      if (std::isfinite(cbc.bound))
        result.lower_bound = std::max(1.0, std::min<double>(std::ceil(cbc.bound - 1e-6), picked.size()));
    }
    result.greedy_size = reduction.forced.size() + greedy.size();
  } else {
    result.greedy_size = reduction.forced.size();
  }
  result.chosen = reduction.forced;
  for (const Index k : picked) result.chosen.push_back(reduction.kept_columns[k]);
  std::sort(result.chosen.begin(), result.chosen.end());
  result.lower_bound = result.optimal ? static_cast<double>(result.chosen.size())
                                      : result.lower_bound + static_cast<double>(reduction.forced.size());
  if (!covers_all(sets, element_count, result.chosen))
    throw Error("ilp_set_cover: the " + std::to_string(result.chosen.size()) +
                " sets chosen do not cover every element (a bug in the reductions or the solver interface)");
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace structmesh
