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

#include "structmesh/error.hpp"

#include <CbcModel.hpp>
#include <CbcSolver.hpp>
#include <CoinPackedMatrix.hpp>
#include <OsiClpSolverInterface.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace structmesh::quad2d {

namespace {

constexpr double kMappedReward = 2.0;
// Branch-and-bound nodes: a limit on work, not on time, so the result is the same on
// any machine. The LP relaxation is nearly always integral here.
constexpr int kNodeLimit = 500;
// Parts per cluster of the clustered solve (solve_interval_assignment()).
constexpr std::size_t kClusterParts = 24;
// Above this many parts the whole MILP is not tried: measured on the Key at 2M quads,
// it found a solution for 119 parts (2.4 s) but none for 253 (6.5 s spent) or 1008
// (22.6 s spent), all before the clustered solve.
constexpr std::size_t kWholeSolveMaxParts = 160;

struct Row {
  std::vector<int> index;
  std::vector<double> value;
  double lo, hi;
};

}  // namespace

namespace {

IntervalSolution solve_whole(const IntervalProblem& problem) {
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
    if (!problem.fixed.empty() && problem.fixed[e] != kInvalidIndex) col_lo[n0 + e] = col_hi[n0 + e] = problem.fixed[e];
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

}  // namespace

IntervalSolution solve_interval_assignment(const IntervalProblem& problem) {
  std::size_t parts = problem.part_ids.size();
  if (problem.part_ids.empty()) {
    parts = problem.part_edges.size();
  } else {
    std::vector<std::size_t> ids = problem.part_ids;
    std::sort(ids.begin(), ids.end());
    parts = static_cast<std::size_t>(std::unique(ids.begin(), ids.end()) - ids.begin());
  }
  if (parts <= kWholeSolveMaxParts) {
    IntervalSolution whole = solve_whole(problem);
    if (whole.solved || parts <= kClusterParts) return whole;
  }
  return solve_interval_assignment_in_clusters(problem, kClusterParts);
}

IntervalSolution solve_interval_assignment_in_clusters(const IntervalProblem& problem, std::size_t cluster_parts) {
  if (cluster_parts == 0) throw InputError("solve_interval_assignment_in_clusters: clusters need at least one part");
  const std::size_t rows = problem.part_edges.size();
  const auto id_of = [&](std::size_t row) { return problem.part_ids.empty() ? row : problem.part_ids[row]; };
  std::vector<std::size_t> ids;
  for (std::size_t row = 0; row < rows; ++row) ids.push_back(id_of(row));
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());

  const std::size_t edges = problem.ideal.size();
  const auto local_id = [&](std::size_t id) {
    return static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin());
  };
  // Parts sharing an edge are neighbours.
  std::vector<std::vector<std::size_t>> edge_parts(edges), neighbours(ids.size()), part_rows(ids.size());
  for (std::size_t row = 0; row < rows; ++row) {
    const std::size_t part = local_id(id_of(row));
    part_rows[part].push_back(row);
    for (const Index e : problem.part_edges[row]) edge_parts[e].push_back(part);
  }
  for (auto& parts : edge_parts) {
    std::sort(parts.begin(), parts.end());
    parts.erase(std::unique(parts.begin(), parts.end()), parts.end());
    for (const std::size_t a : parts)
      for (const std::size_t b : parts)
        if (a != b) neighbours[a].push_back(b);
  }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  // Clusters: breadth-first from the lowest unclustered part, up to cluster_parts each.
  std::vector<std::size_t> cluster_of(ids.size(), SIZE_MAX);
  std::vector<std::vector<std::size_t>> clusters;
  for (std::size_t start = 0; start < ids.size(); ++start) {
    if (cluster_of[start] != SIZE_MAX) continue;
    std::vector<std::size_t> members{start};
    cluster_of[start] = clusters.size();
    for (std::size_t k = 0; k < members.size() && members.size() < cluster_parts; ++k)
      for (const std::size_t b : neighbours[members[k]]) {
        if (cluster_of[b] != SIZE_MAX || members.size() >= cluster_parts) continue;
        cluster_of[b] = clusters.size();
        members.push_back(b);
      }
    clusters.push_back(std::move(members));
  }
  // Entries of each cluster.
  std::vector<std::vector<std::size_t>> cluster_four(clusters.size()), cluster_polar(clusters.size());
  for (std::size_t f = 0; f < problem.four_sided.size(); ++f)
    cluster_four[cluster_of[local_id(problem.four_sided[f].part)]].push_back(f);
  for (std::size_t q = 0; q < problem.polar.size(); ++q)
    cluster_polar[cluster_of[local_id(problem.polar[q].part)]].push_back(q);

  IntervalSolution solution;
  solution.solved = true;
  solution.counts.assign(edges, kInvalidIndex);
  solution.mapped.assign(problem.four_sided.size(), 0);
  solution.polar.assign(problem.polar.size(), 0);
  solution.chord_segments.resize(problem.polar.size());
  for (std::size_t q = 0; q < problem.polar.size(); ++q)
    solution.chord_segments[q].assign(problem.polar[q].sides.size(), 1);
  // Clusters that share no edge are solved at the same time: greedy colouring in
  // cluster order, then one colour after the other, each cluster with the edges of
  // earlier colours fixed. The result depends on the colouring alone, not on the
  // number of threads. (Plain sequential solving spent 17.6 s of the Key's 2M quads
  // in 1008 parts on one core: 43 clusters, each at the 500-node limit.)
  std::vector<std::vector<std::size_t>> cluster_neighbours(clusters.size());
  for (const auto& parts : edge_parts)
    for (const std::size_t a : parts)
      for (const std::size_t b : parts)
        if (cluster_of[a] != cluster_of[b]) cluster_neighbours[cluster_of[a]].push_back(cluster_of[b]);
  std::vector<std::size_t> colour(clusters.size(), SIZE_MAX);
  std::size_t colours = 0;
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    std::vector<std::uint8_t> taken(colours + 1, 0);
    for (const std::size_t b : cluster_neighbours[c])
      if (colour[b] != SIZE_MAX) taken[colour[b]] = 1;
    colour[c] = static_cast<std::size_t>(std::find(taken.begin(), taken.end(), 0) - taken.begin());
    colours = std::max(colours, colour[c] + 1);
  }

  struct ClusterSolve {
    IntervalProblem sub;
    std::vector<Index> global;  // sub edge -> problem edge
    std::vector<std::size_t> four_index, polar_index;
    IntervalSolution solution;
  };
  // Reads solution.counts of the cluster's own edges; keep() writes them back only
  // after every cluster of the colour is solved, and clusters of one colour share no
  // edge, so solving them together gives what solving them in turn would.
  const auto solve_cluster = [&](std::size_t c) {
    ClusterSolve out;
    IntervalProblem& sub = out.sub;
    std::vector<Index> local(edges, kInvalidIndex);
    const auto use = [&](Index e) {
      if (local[e] == kInvalidIndex) {
        local[e] = static_cast<Index>(out.global.size());
        out.global.push_back(e);
        sub.ideal.push_back(problem.ideal[e]);
        sub.minimum.push_back(problem.minimum[e]);
        const Index fixed = problem.fixed.empty() ? kInvalidIndex : problem.fixed[e];
        sub.fixed.push_back(solution.counts[e] != kInvalidIndex ? solution.counts[e] : fixed);
      }
      return local[e];
    };
    const auto remap = [&](const std::vector<Index>& list) {
      std::vector<Index> mapped;
      for (const Index e : list) mapped.push_back(use(e));
      return mapped;
    };
    for (const std::size_t part : clusters[c])
      for (const std::size_t row : part_rows[part]) {
        sub.part_edges.push_back(remap(problem.part_edges[row]));
        sub.part_ids.push_back(part);
      }
    out.four_index.assign(problem.four_sided.size(), SIZE_MAX);
    for (const std::size_t f : cluster_four[c]) {
      out.four_index[f] = sub.four_sided.size();
      IntervalProblem::FourSided four{problem.four_sided[f].part, {}};
      for (int side = 0; side < 4; ++side) four.sides[side] = remap(problem.four_sided[f].sides[side]);
      sub.four_sided.push_back(std::move(four));
    }
    out.polar_index.assign(problem.polar.size(), SIZE_MAX);
    for (const std::size_t q : cluster_polar[c]) {
      out.polar_index[q] = sub.polar.size();
      IntervalProblem::Polar blocks = problem.polar[q];
      for (auto& side : blocks.sides) side = remap(side);
      sub.polar.push_back(std::move(blocks));
    }
    for (const auto& [f, q] : problem.exclusive)
      if (out.four_index[f] != SIZE_MAX && out.polar_index[q] != SIZE_MAX)
        sub.exclusive.emplace_back(out.four_index[f], out.polar_index[q]);
    out.solution = solve_whole(sub);
    return out;
  };
  const auto keep = [&](std::size_t c, const ClusterSolve& solved) {
    const IntervalSolution& part = solved.solution;
    for (std::size_t k = 0; k < solved.global.size(); ++k) {
      const Index e = solved.global[k];
      if (solution.counts[e] != kInvalidIndex) continue;
      if (part.solved) {
        solution.counts[e] = part.counts[k];
      } else {
        const Index fixed = solved.sub.fixed[k];
        solution.counts[e] =
            fixed != kInvalidIndex
                ? fixed
                : std::max(problem.minimum[e], static_cast<Index>(std::max(1.0, std::round(problem.ideal[e]))));
      }
    }
    if (!part.solved) return;
    for (const std::size_t f : cluster_four[c]) solution.mapped[f] = part.mapped[solved.four_index[f]];
    for (const std::size_t q : cluster_polar[c]) {
      solution.polar[q] = part.polar[solved.polar_index[q]];
      solution.chord_segments[q] = part.chord_segments[solved.polar_index[q]];
    }
  };
  for (std::size_t k = 0; k < colours; ++k) {
    std::vector<std::size_t> batch;
    for (std::size_t c = 0; c < clusters.size(); ++c)
      if (colour[c] == k) batch.push_back(c);
    std::vector<ClusterSolve> solved(batch.size());
    tbb::parallel_for(std::size_t{0}, batch.size(), [&](std::size_t i) { solved[i] = solve_cluster(batch[i]); });
    for (std::size_t i = 0; i < batch.size(); ++i) keep(batch[i], solved[i]);
  }
  return solution;
}

}  // namespace structmesh::quad2d
