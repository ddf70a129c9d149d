// solve_interval_assignment(): the integer problem of choosing segment counts
// (Mitchell's "interval assignment" of submapping mesh generators) for the part
// boundaries, as an MILP for COIN-OR CBC:
//
//   minimise   sum_e w_e d_e  -  R sum_p z_p
//   subject to d_e >= n_e - t_e,  d_e >= t_e - n_e           (deviation from the ideal t_e)
//              sum_{e in part p} n_e = 2 m_p                  (even boundary, §3.3.1)
//              |sum_{side 0} n - sum_{side 2} n| <= M (1 - z_p) (and sides 1, 3) for four-sided p
//              n_e integer in [lo_e, hi_e] (about 0.75..1.33 t_e), m_p integer, z_p binary,
//
// with w_e = 1 / max(1, t_e) (relative size change) and R = 2: a part becomes a
// structured grid when that costs less than changing about two short edges by a
// whole segment each.
#include "quad2d/interval_assignment.hpp"

#include <CbcModel.hpp>
#include <CbcSolver.hpp>
#include <CoinPackedMatrix.hpp>
#include <OsiClpSolverInterface.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace structmesh::quad2d {

namespace {

constexpr double kMappedReward = 2.0;
// Branch-and-bound nodes: a limit on work, not on time, so the result is the same on
// any machine. The LP relaxation is nearly always integral here.
constexpr int kNodeLimit = 500;

struct Row {
  std::vector<int> index;
  std::vector<double> value;
  double lo, hi;
};

}  // namespace

IntervalSolution solve_interval_assignment(const IntervalProblem& problem) {
  const std::size_t edges = problem.ideal.size();
  const std::size_t parts = problem.part_edges.size();
  const std::size_t mapped = problem.four_sided.size();
  const std::size_t polar = problem.polar.size();
  std::vector<std::size_t> chord_offset(polar + 1, 0);
  for (std::size_t q = 0; q < polar; ++q) chord_offset[q + 1] = chord_offset[q] + problem.polar[q].sides.size();
  const std::size_t chords = chord_offset[polar];
  // Columns: n_e [0, E), d_e [E, 2E), m_p [2E, 2E+P), z_p [.., +F), polar y_q [.., +Q),
  // chord counts r [.., +C), chord deviations [.., +C).
  const int n0 = 0, d0 = static_cast<int>(edges), m0 = static_cast<int>(2 * edges),
            z0 = static_cast<int>(2 * edges + parts), y0 = z0 + static_cast<int>(mapped),
            r0 = y0 + static_cast<int>(polar), dr0 = r0 + static_cast<int>(chords);
  const std::size_t columns = 2 * edges + parts + mapped + polar + 2 * chords;
  std::vector<double> col_lo(columns, 0.0), col_hi(columns, COIN_DBL_MAX), objective(columns, 0.0);
  for (std::size_t e = 0; e < edges; ++e) {
    const double t = problem.ideal[e];
    // Element sizes stay within about [0.75, 1.33] of the wanted size (one segment
    // either way always allowed, so short edges can still match).
    const double rounded = std::max(1.0, std::round(t));
    col_lo[n0 + e] = std::max<double>(problem.minimum[e], std::min(rounded - 1.0, std::floor(0.75 * t)));
    col_hi[n0 + e] = std::max(rounded + 1.0, std::ceil(1.33 * t));
    objective[d0 + e] = 1.0 / std::max(1.0, t);
  }
  for (std::size_t f = 0; f < mapped; ++f) {
    col_hi[z0 + f] = 1.0;
    objective[z0 + f] = -kMappedReward;
  }
  for (std::size_t q = 0; q < polar; ++q) {
    col_hi[y0 + q] = 1.0;
    objective[y0 + q] = -problem.polar[q].reward;
    for (std::size_t i = 0; i < problem.polar[q].sides.size(); ++i) {
      const std::size_t c = chord_offset[q] + i;
      const double t = problem.polar[q].chord_ideal[i];
      col_lo[r0 + c] = 1.0;
      col_hi[r0 + c] = std::max(4.0, std::ceil(3.0 * t) + 2.0);
      objective[dr0 + c] = 0.5 / std::max(1.0, t);
    }
  }

  std::vector<Row> rows;
  for (std::size_t e = 0; e < edges; ++e) {
    const int n = n0 + static_cast<int>(e), d = d0 + static_cast<int>(e);
    rows.push_back({{d, n}, {1.0, -1.0}, -problem.ideal[e], COIN_DBL_MAX});
    rows.push_back({{d, n}, {1.0, 1.0}, problem.ideal[e], COIN_DBL_MAX});
  }
  for (std::size_t p = 0; p < parts; ++p) {
    Row row{{}, {}, 0.0, 0.0};
    for (const Index e : problem.part_edges[p]) {
      // An edge listed twice (both sides of a slit) adds twice.
      const auto it = std::find(row.index.begin(), row.index.end(), n0 + static_cast<int>(e));
      if (it != row.index.end()) {
        row.value[static_cast<std::size_t>(it - row.index.begin())] += 1.0;
      } else {
        row.index.push_back(n0 + static_cast<int>(e));
        row.value.push_back(1.0);
      }
    }
    row.index.push_back(m0 + static_cast<int>(p));
    row.value.push_back(-2.0);
    rows.push_back(std::move(row));
  }
  for (std::size_t f = 0; f < mapped; ++f) {
    const IntervalProblem::FourSided& four = problem.four_sided[f];
    for (int pair = 0; pair < 2; ++pair) {
      const std::vector<Index>& a = four.sides[pair];
      const std::vector<Index>& b = four.sides[pair + 2];
      double big = 4.0;
      for (const Index e : a) big += col_hi[n0 + e];
      for (const Index e : b) big += col_hi[n0 + e];
      for (const double sign : {1.0, -1.0}) {
        // sign * (sum a - sum b) + M z <= M
        Row row{{}, {}, -COIN_DBL_MAX, big};
        const auto add = [&](Index e, double value) {
          const int column = n0 + static_cast<int>(e);
          const auto it = std::find(row.index.begin(), row.index.end(), column);
          if (it != row.index.end()) {
            row.value[static_cast<std::size_t>(it - row.index.begin())] += value;
          } else {
            row.index.push_back(column);
            row.value.push_back(value);
          }
        };
        for (const Index e : a) add(e, sign);
        for (const Index e : b) add(e, -sign);
        row.index.push_back(z0 + static_cast<int>(f));
        row.value.push_back(big);
        rows.push_back(std::move(row));
      }
    }
  }

  for (std::size_t q = 0; q < polar; ++q) {
    const IntervalProblem::Polar& blocks = problem.polar[q];
    const std::size_t k = blocks.sides.size();
    for (std::size_t i = 0; i < k; ++i) {
      const int r = r0 + static_cast<int>(chord_offset[q] + i), dr = dr0 + static_cast<int>(chord_offset[q] + i);
      rows.push_back({{dr, r}, {1.0, -1.0}, -blocks.chord_ideal[i], COIN_DBL_MAX});
      rows.push_back({{dr, r}, {1.0, 1.0}, blocks.chord_ideal[i], COIN_DBL_MAX});
      // sum_{side i} n - r_{i-1} - r_{i+1} = 0 when y_q = 1 (big-M otherwise).
      const int before = r0 + static_cast<int>(chord_offset[q] + (i + k - 1) % k);
      const int after = r0 + static_cast<int>(chord_offset[q] + (i + 1) % k);
      double big = 4.0 + col_hi[before] + col_hi[after];
      for (const Index e : blocks.sides[i]) big += col_hi[n0 + e];
      for (const double sign : {1.0, -1.0}) {
        Row row{{}, {}, -COIN_DBL_MAX, big};
        for (const Index e : blocks.sides[i]) {
          row.index.push_back(n0 + static_cast<int>(e));
          row.value.push_back(sign);
        }
        row.index.push_back(before);
        row.value.push_back(-sign);
        if (after != before) {
          row.index.push_back(after);
          row.value.push_back(-sign);
        } else {
          row.value.back() -= sign;
        }
        row.index.push_back(y0 + static_cast<int>(q));
        row.value.push_back(big);
        rows.push_back(std::move(row));
      }
    }
  }

  for (const auto& [f, q] : problem.exclusive)
    rows.push_back({{z0 + static_cast<int>(f), y0 + static_cast<int>(q)}, {1.0, 1.0}, -COIN_DBL_MAX, 1.0});

  CoinPackedMatrix matrix(false, 0, 0);
  matrix.setDimensions(0, static_cast<int>(columns));
  std::vector<double> row_lo, row_hi;
  for (const Row& r : rows) {
    matrix.appendRow(static_cast<int>(r.index.size()), r.index.data(), r.value.data());
    row_lo.push_back(r.lo);
    row_hi.push_back(r.hi);
  }
  OsiClpSolverInterface solver;
  solver.messageHandler()->setLogLevel(0);
  solver.loadProblem(matrix, col_lo.data(), col_hi.data(), objective.data(), row_lo.data(), row_hi.data());
  for (std::size_t e = 0; e < edges; ++e) solver.setInteger(n0 + static_cast<int>(e));
  for (std::size_t p = 0; p < parts; ++p) solver.setInteger(m0 + static_cast<int>(p));
  for (std::size_t f = 0; f < mapped; ++f) solver.setInteger(z0 + static_cast<int>(f));
  for (std::size_t q = 0; q < polar; ++q) solver.setInteger(y0 + static_cast<int>(q));
  for (std::size_t c = 0; c < chords; ++c) solver.setInteger(r0 + static_cast<int>(c));
  // Plain branch and bound (CbcModel without the stand-alone solver's default cut
  // generators and heuristics): these MILPs are small and their LP relaxations
  // nearly integral, and the defaults cost far more than they find here.
  solver.initialSolve();
  CbcModel model(solver);
  model.messageHandler()->setLogLevel(0);
  model.setMaximumNodes(kNodeLimit);
  model.setLogLevel(0);
  model.branchAndBound();

  IntervalSolution solution;
  const double* best = model.bestSolution();
  if (best == nullptr) return solution;
  solution.counts.resize(edges);
  for (std::size_t e = 0; e < edges; ++e)
    solution.counts[e] = static_cast<Index>(std::lround(std::max(1.0, best[n0 + e])));
  // Trust only what holds in integers.
  for (std::size_t p = 0; p < parts; ++p) {
    std::uint64_t total = 0;
    for (const Index e : problem.part_edges[p]) total += solution.counts[e];
    if (total % 2 != 0) return IntervalSolution{};
  }
  solution.mapped.assign(mapped, 0);
  for (std::size_t f = 0; f < mapped; ++f) {
    const auto side_sum = [&](int s) {
      std::uint64_t total = 0;
      for (const Index e : problem.four_sided[f].sides[s]) total += solution.counts[e];
      return total;
    };
    solution.mapped[f] = side_sum(0) == side_sum(2) && side_sum(1) == side_sum(3) ? 1 : 0;
  }
  solution.polar.assign(polar, 0);
  solution.chord_segments.assign(polar, {});
  for (std::size_t q = 0; q < polar; ++q) {
    const IntervalProblem::Polar& blocks = problem.polar[q];
    const std::size_t k = blocks.sides.size();
    std::vector<Index>& r = solution.chord_segments[q];
    for (std::size_t i = 0; i < k; ++i) r.push_back(static_cast<Index>(std::lround(best[r0 + chord_offset[q] + i])));
    bool holds = true;
    for (std::size_t i = 0; i < k; ++i) {
      std::uint64_t side = 0;
      for (const Index e : blocks.sides[i]) side += solution.counts[e];
      holds = holds && r[i] >= 1 && side == r[(i + k - 1) % k] + r[(i + 1) % k];
    }
    solution.polar[q] = holds ? 1 : 0;
  }
  solution.solved = true;
  return solution;
}

}  // namespace structmesh::quad2d
