// Exact bisection (design §2.8): the bisection as a MILP solved by CBC.
//
//   min  sum_e w_e s_e + lambda sum_{pairs} delta_ef t_ef        (3.4) + lambda (3.7)
//   s_e >= x_a - x_b,  s_e >= x_b - x_a                           (y = Ux, |y_e| <= s_e)
//   t_ef >= s_e + s_f - 1                                         (|y_e||y_f| <= t_ef)
//   lo <= sum_v w_v x_v <= hi                                     (3.1)
//   + connectivity cuts (3.9) / (3.10), added lazily.
//
// All objective coefficients are >= 0, so at an integer x the continuous s and t
// settle at |x_a - x_b| and s_e s_f: only x needs to be integer. The angle term uses
// the pairs of spokes at each corner, as (3.7) does; corner_cost counts consecutive
// sectors instead, which agrees at every corner with at most three active spokes.
#include "partition2d/graph_partition_detail.hpp"
#include "structmesh/error.hpp"

#include <CbcModel.hpp>
#include <CbcSolver.hpp>
#include <CoinPackedMatrix.hpp>
#include <OsiClpSolverInterface.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

namespace structmesh::partition2d::detail {
namespace {

struct Row {
  std::vector<int> index;
  std::vector<double> value;
  double lo = -COIN_DBL_MAX, hi = COIN_DBL_MAX;
};

struct Milp {
  std::size_t n = 0;                           ///< x columns [0, n)
  std::vector<std::pair<Index, Index>> arcs;   ///< local endpoints; s column n + e
  std::vector<std::pair<Index, Index>> pairs;  ///< arc pairs; t column n + m + p
  std::vector<double> objective;
  std::vector<Row> rows;
  std::vector<double> col_ub;

  std::size_t columns() const { return objective.size(); }

  /// The objective at an integer x (s = |y|, t = s_e s_f).
  double value(const std::vector<char>& x) const {
    double sum = 0;
    const std::size_t m = arcs.size();
    std::vector<char> s(m);
    for (std::size_t e = 0; e < m; ++e) {
      s[e] = x[arcs[e].first] != x[arcs[e].second];
      if (s[e]) sum += objective[n + e];
    }
    for (std::size_t p = 0; p < pairs.size(); ++p)
      if (s[pairs[p].first] && s[pairs[p].second]) sum += objective[n + m + p];
    return sum;
  }
};

/// What a spoke's activity (its two sectors carry different labels) depends on.
struct SpokeTerm {
  enum Kind : std::uint8_t { Never, Variable, Separator, Boundary } kind = Never;
  Index arc = kInvalidIndex;  ///< MILP arc when Variable
};

struct Solution {
  bool found = false;
  std::vector<char> x;
  double objective = 0, bound = 0;
  bool optimal = false;
  bool nothing_below_cutoff = false;  ///< proven: no solution better than the cutoff
};

/// Solves the MILP with CBC within `seconds`, pruning at `cutoff` (the incumbent's
/// value plus a hair, so CBC only looks for something at least as good).
Solution solve(const Milp& milp, double seconds, double cutoff) {
  const std::size_t columns = milp.columns();
  CoinPackedMatrix matrix(false, 0, 0);
  matrix.setDimensions(0, static_cast<int>(columns));
  std::vector<double> row_lo, row_hi;
  for (const Row& r : milp.rows) {
    matrix.appendRow(static_cast<int>(r.index.size()), r.index.data(), r.value.data());
    row_lo.push_back(r.lo);
    row_hi.push_back(r.hi);
  }
  std::vector<double> col_lo(columns, 0.0);
  OsiClpSolverInterface solver;
  solver.messageHandler()->setLogLevel(0);
  solver.loadProblem(matrix, col_lo.data(), milp.col_ub.data(), milp.objective.data(), row_lo.data(), row_hi.data());
  for (std::size_t j = 0; j < milp.n; ++j) solver.setInteger(static_cast<int>(j));
  CbcModel model(solver);
  model.messageHandler()->setLogLevel(0);
  CbcSolverUsefulData data;
  data.noPrinting_ = true;
  CbcMain0(model, data);
  const std::string limit = std::to_string(std::max(0.01, seconds));
  const std::string cut = std::to_string(cutoff);
  const char* argv[] = {"cbc", "-log", "0", "-sec", limit.c_str(), "-cutoff", cut.c_str(), "-solve", "-quit"};
  CbcMain1(9, argv, model, nullptr, data);
  Solution s;
  const double* best = model.bestSolution();
  s.bound = model.getBestPossibleObjValue();
  if (best == nullptr) {
    s.nothing_below_cutoff = model.isProvenInfeasible();
    return s;
  }
  s.found = true;
  s.x.resize(milp.n);
  for (std::size_t j = 0; j < milp.n; ++j) s.x[j] = best[j] > 0.5;
  s.objective = milp.value(s.x);
  s.optimal = model.isProvenOptimal();
  return s;
}

struct SideComponents {
  std::vector<Index> of_node;  ///< local node -> component
  std::vector<double> area;
  std::vector<char> side;
  std::vector<Index> heaviest;  ///< the component's node of largest area (lowest index on ties)
};

/// Connected components of the two sides of x inside the group.
SideComponents side_components(const CellGraph& graph, const std::vector<Index>& nodes, const std::vector<Index>& local,
                               const std::vector<char>& x) {
  const std::size_t n = nodes.size();
  SideComponents c;
  c.of_node.assign(n, kInvalidIndex);
  std::vector<Index> stack;
  for (std::size_t i = 0; i < n; ++i) {
    if (c.of_node[i] != kInvalidIndex) continue;
    const Index id = static_cast<Index>(c.area.size());
    c.area.push_back(0);
    c.side.push_back(x[i]);
    c.heaviest.push_back(static_cast<Index>(i));
    c.of_node[i] = id;
    stack.assign(1, static_cast<Index>(i));
    while (!stack.empty()) {
      const Index w = stack.back();
      stack.pop_back();
      const double a = graph.node_area[nodes[w]], h = graph.node_area[nodes[c.heaviest[id]]];
      c.area[id] += a;
      if (a > h || (a == h && w < c.heaviest[id])) c.heaviest[id] = w;
      for (Index e = graph.adjacency_offsets[nodes[w]]; e < graph.adjacency_offsets[nodes[w] + 1]; ++e) {
        const Index u = local[graph.adjacency[e]];
        if (u == kInvalidIndex || c.of_node[u] != kInvalidIndex || x[u] != x[w]) continue;
        c.of_node[u] = id;
        stack.push_back(u);
      }
    }
  }
  return c;
}

double elapsed_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Eq. (3.6): deviation from the nearest multiple of pi/2.
double delta_between(double a, double b) { return angle_deviation(b - a); }

}  // namespace

ExactBisectionResult exact_bisection(const CellGraph& graph, std::span<std::int32_t> labels,
                                     const BisectionProblem& problem, double seconds) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Index>& nodes = problem.nodes;
  const std::size_t n = nodes.size();
  std::vector<Index> local(graph.node_count(), kInvalidIndex);
  for (std::size_t i = 0; i < n; ++i) local[nodes[i]] = static_cast<Index>(i);

  Milp milp;
  milp.n = n;
  // Arcs inside the group (each once) and, per adjacency slot, its MILP arc.
  std::vector<Index> slot_arc(graph.adjacency.size(), kInvalidIndex);
  std::vector<double> arc_weight;
  for (std::size_t i = 0; i < n; ++i) {
    const Index v = nodes[i];
    for (Index a = graph.adjacency_offsets[v]; a < graph.adjacency_offsets[v + 1]; ++a) {
      const Index u = graph.adjacency[a];
      if (local[u] == kInvalidIndex || u < v) continue;
      slot_arc[a] = static_cast<Index>(milp.arcs.size());
      milp.arcs.emplace_back(static_cast<Index>(i), local[u]);
      arc_weight.push_back(graph.arc_length[a]);
    }
  }
  const auto arc_between = [&](Index p, Index q) {
    const Index lo = std::min(p, q), hi = std::max(p, q);
    for (Index a = graph.adjacency_offsets[lo]; a < graph.adjacency_offsets[lo + 1]; ++a)
      if (graph.adjacency[a] == hi) return slot_arc[a];
    return kInvalidIndex;
  };
  const std::size_t m = milp.arcs.size();
  std::vector<double> arc_angle_cost(m, 0.0), pair_cost;

  // Corners touching the group: every pair of spokes with a nonzero deviation whose
  // activity depends on x becomes an s coefficient (the other spoke always active)
  // or a t column (both depend on x).
  std::vector<char> corner_seen(graph.corner_offsets.size(), 0);
  std::vector<SpokeTerm> terms;
  for (Index v : nodes) {
    for (Index i = graph.node_corner_offsets[v]; i < graph.node_corner_offsets[v + 1]; ++i) {
      const Index c = graph.node_corners[i];
      if (corner_seen[c]) continue;
      corner_seen[c] = 1;
      const Index begin = graph.corner_offsets[c], end = graph.corner_offsets[c + 1];
      terms.assign(end - begin, SpokeTerm{});
      for (Index s = begin; s < end; ++s) {
        // Spoke s separates sector s - 1 from sector s (sector s = left of spoke s).
        const Index p = graph.spokes[s == begin ? end - 1 : s - 1].left_node, q = graph.spokes[s].left_node;
        SpokeTerm& t = terms[s - begin];
        if (p == q) continue;
        if (p == kInvalidIndex || q == kInvalidIndex) {
          t.kind = SpokeTerm::Boundary;
        } else if (local[p] != kInvalidIndex && local[q] != kInvalidIndex) {
          t.arc = arc_between(p, q);
          t.kind = t.arc == kInvalidIndex ? SpokeTerm::Never : SpokeTerm::Variable;
        } else if (local[p] != kInvalidIndex || local[q] != kInvalidIndex || labels[p] != labels[q]) {
          // A spoke to another group is active whatever x is; so is one between
          // two other nodes with different labels.
          t.kind = SpokeTerm::Separator;
        }
      }
      for (Index s = begin; s < end; ++s) {
        for (Index r = s + 1; r < end; ++r) {
          const SpokeTerm &a = terms[s - begin], &b = terms[r - begin];
          if (a.kind != SpokeTerm::Variable && b.kind != SpokeTerm::Variable) continue;
          if (a.kind == SpokeTerm::Never || b.kind == SpokeTerm::Never) continue;
          const bool boundary_pair = a.kind == SpokeTerm::Boundary || b.kind == SpokeTerm::Boundary;
          if (boundary_pair && !problem.boundary_corners) continue;
          const double delta = delta_between(graph.spokes[s].angle, graph.spokes[r].angle);
          if (delta < 1e-12) continue;
          const double cost = problem.lambda * delta;
          if (a.kind == SpokeTerm::Variable && b.kind == SpokeTerm::Variable) {
            milp.pairs.emplace_back(a.arc, b.arc);
            pair_cost.push_back(cost);
          } else {
            arc_angle_cost[a.kind == SpokeTerm::Variable ? a.arc : b.arc] += cost;
          }
        }
      }
    }
  }

  const std::size_t pairs = milp.pairs.size();
  milp.objective.assign(n + m + pairs, 0.0);
  milp.col_ub.assign(n + m + pairs, 1.0);
  for (std::size_t e = 0; e < m; ++e) milp.objective[n + e] = arc_weight[e] + arc_angle_cost[e];
  for (std::size_t p = 0; p < pairs; ++p) milp.objective[n + m + p] = pair_cost[p];
  for (std::size_t e = 0; e < m; ++e) {
    const int s = static_cast<int>(n + e), a = static_cast<int>(milp.arcs[e].first),
              b = static_cast<int>(milp.arcs[e].second);
    milp.rows.push_back({{s, a, b}, {1.0, -1.0, 1.0}, 0.0, COIN_DBL_MAX});
    milp.rows.push_back({{s, a, b}, {1.0, 1.0, -1.0}, 0.0, COIN_DBL_MAX});
  }
  for (std::size_t p = 0; p < pairs; ++p) {
    const int t = static_cast<int>(n + m + p), e = static_cast<int>(n + milp.pairs[p].first),
              f = static_cast<int>(n + milp.pairs[p].second);
    if (e == f)
      milp.rows.push_back({{t, e}, {1.0, -2.0}, -1.0, COIN_DBL_MAX});
    else
      milp.rows.push_back({{t, e, f}, {1.0, -1.0, -1.0}, -1.0, COIN_DBL_MAX});
  }
  // Eq. (3.1) for side 1 (x = 1), with side 0's band folded in; areas scaled to the
  // group so the row is well conditioned.
  double total = 0;
  for (Index v : nodes) total += graph.node_area[v];
  {
    Row balance;
    for (std::size_t i = 0; i < n; ++i) {
      balance.index.push_back(static_cast<int>(i));
      balance.value.push_back(graph.node_area[nodes[i]] / total);
    }
    balance.lo = std::max(problem.lo1, total - problem.hi0) / total;
    balance.hi = std::min(problem.hi1, total - problem.lo0) / total;
    milp.rows.push_back(std::move(balance));
  }
  // Symmetry: with equal bands the two labelings of one cut are the same bisection.
  if (std::abs(problem.lo0 - problem.lo1) < 1e-12 * total && std::abs(problem.hi0 - problem.hi1) < 1e-12 * total)
    milp.col_ub[0] = 0.0;

  // The incumbent from the caller (the CVT-GP bisection), used when CBC finds
  // nothing connected in time.
  std::vector<char> incumbent(n);
  for (std::size_t i = 0; i < n; ++i) incumbent[i] = labels[nodes[i]] == problem.label1;
  if (milp.col_ub[0] == 0.0 && incumbent[0])
    for (char& x : incumbent) x = !x;

  ExactBisectionResult result;
  result.objective = milp.value(incumbent);
  double incumbent_area = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (incumbent[i]) incumbent_area += graph.node_area[nodes[i]];
  const double band_lo = milp.rows.back().lo, band_hi = milp.rows.back().hi;  // the balance row
  // Feasible for the true problem: in the band, and each side one piece (at most
  // two components in all).
  const bool incumbent_feasible = incumbent_area / total >= band_lo - 1e-9 &&
                                  incumbent_area / total <= band_hi + 1e-9 &&
                                  side_components(graph, nodes, local, incumbent).area.size() <= 2;
  double bound = 0;
  bool improved = false;
  for (;;) {
    const double remaining = seconds - elapsed_since(start);
    if (remaining <= 0) break;
    // An infeasible incumbent is no bound on the optimum.
    const double cutoff = incumbent_feasible ? result.objective + 1e-6 * std::max(1.0, result.objective) : 1e30;
    const Solution s = solve(milp, remaining, cutoff);
    ++result.solves;
    bound = std::max(bound, s.bound);
    if (!s.found) {
      // Nothing beats the incumbent: it is optimal when it is itself feasible.
      if (s.nothing_below_cutoff && incumbent_feasible) {
        result.proven = true;
        bound = std::max(bound, result.objective);
      }
      break;
    }
    // Components of each side inside the group.
    const SideComponents comps = side_components(graph, nodes, local, s.x);
    const std::vector<Index>& component = comps.of_node;
    const std::vector<double>& comp_area = comps.area;
    const std::vector<char>& comp_side = comps.side;
    const std::vector<Index>& comp_heaviest = comps.heaviest;
    std::size_t added = 0;
    for (int side = 0; side < 2; ++side) {
      Index largest = kInvalidIndex;
      for (Index c = 0; c < comp_area.size(); ++c)
        if (comp_side[c] == side && (largest == kInvalidIndex || comp_area[c] > comp_area[largest])) largest = c;
      for (Index c = 0; c < comp_area.size(); ++c) {
        if (comp_side[c] != side || c == largest) continue;
        // S = N(C): every path from C to the largest component C* crosses it, so
        // u in C and v in C* on this side need some w in S on this side too.
        std::vector<char> in_cut(n, 0);
        Row cut;
        for (std::size_t i = 0; i < n; ++i) {
          if (component[i] != c) continue;
          for (Index a = graph.adjacency_offsets[nodes[i]]; a < graph.adjacency_offsets[nodes[i] + 1]; ++a) {
            const Index u = local[graph.adjacency[a]];
            if (u == kInvalidIndex || component[u] == c || in_cut[u]) continue;
            in_cut[u] = 1;
            cut.index.push_back(static_cast<int>(u));
            cut.value.push_back(1.0);
          }
        }
        const double size = static_cast<double>(cut.index.size());
        cut.index.push_back(static_cast<int>(comp_heaviest[c]));
        cut.value.push_back(-1.0);
        cut.index.push_back(static_cast<int>(comp_heaviest[largest]));
        cut.value.push_back(-1.0);
        if (side == 1)
          cut.lo = -1.0;  // (3.9): sum_S x_w >= x_u + x_v - 1
        else
          cut.hi = size - 1.0;  // (3.10): sum_S x_w <= x_u + x_v + |S| - 1
        milp.rows.push_back(std::move(cut));
        ++added;
      }
    }
    if (added == 0) {
      // A time-limited answer replaces the incumbent only when it is no worse.
      if (s.optimal || s.objective <= result.objective) {
        incumbent = s.x;
        result.objective = s.objective;
        result.proven = s.optimal;
        improved = true;
      }
      if (s.optimal) bound = std::max(bound, s.objective);
      break;
    }
    result.connectivity_cuts += added;
  }
  result.bound = std::min(bound, result.objective);
  if (improved) {
    for (std::size_t i = 0; i < n; ++i) labels[nodes[i]] = incumbent[i] ? problem.label1 : problem.label0;
  }
  return result;
}

}  // namespace structmesh::partition2d::detail
