// partition_cell_graph (design §2.7): recursive bisection with METIS 2-way + refinement
// of J = L_S + lambda D_theta (CVT-GP), the METIS baselines, and the exact engine
// (one MILP per bisection, exact_bisection.cpp). Single-threaded on purpose: the
// refinement reads labels across group borders (corners shared with other groups),
// so sequential recursion keeps results independent of the thread count; a
// 25k-node graph into 1024 parts is a fraction of a second this way.
//
// Where this differs from the design's wording, and why:
// - refinement passes are Fiduccia-Mattheyses style (moves of any gain, rolled back
//   to the best prefix) instead of strictly improving moves only (Refiner);
// - each bisection also refines two axis-parallel starts beside METIS's and keeps
//   the best (gp_bisection);
// - the per-bisection band is (1 + t)^depth = sqrt(1 + imbalance), so a part that
//   stays in every band also meets the k-way band (detail::bisection_tolerance);
// - the exact engine's time limit covers the whole run, shared by group size.
#include "partition2d/graph_partition_detail.hpp"
#include "partition2d/partition_internal.hpp"
#include "structmesh/error.hpp"

#include <metis.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <utility>
#include <vector>

namespace structmesh::partition2d {
namespace {

using Label = std::int32_t;
constexpr double kInf = std::numeric_limits<double>::infinity();

double mean_arc(const CellGraph& graph) {
  if (graph.mean_arc_length > 0) return graph.mean_arc_length;
  double sum = 0;
  for (double w : graph.arc_length) sum += w;
  return graph.arc_length.empty() ? 1.0 : sum / static_cast<double>(graph.arc_length.size());
}

std::size_t ceil_log2(std::size_t k) {
  std::size_t d = 0;
  while ((std::size_t{1} << d) < k) ++d;
  return d;
}

// ---------------------------------------------------------------------------------
// METIS (design §2.6, §2.7 and RECIPES.md): integer weights, never nparts = 1,
// CONTIG only for Kway on a connected graph, both sides counted afterwards.
// ---------------------------------------------------------------------------------

struct MetisGraph {
  std::vector<idx_t> xadj{0}, adjncy, vwgt, adjwgt;
};

/// The subgraph induced by `nodes` (local index = position in `nodes`). `local_of`
/// has one slot per graph node, kInvalidIndex outside; it is left as it was.
MetisGraph metis_graph(const CellGraph& graph, std::span<const Index> nodes, std::vector<Index>& local_of) {
  for (std::size_t i = 0; i < nodes.size(); ++i) local_of[nodes[i]] = static_cast<Index>(i);
  double total = 0;
  for (Index v : nodes) total += graph.node_area[v];
  const double length_unit = mean_arc(graph);
  MetisGraph m;
  m.vwgt.reserve(nodes.size());
  for (Index v : nodes) {
    // Areas scaled so the group sums to about 2^24: fine resolution, no idx_t overflow.
    const double w = total > 0 ? graph.node_area[v] / total * 16777216.0 : 1.0;
    m.vwgt.push_back(static_cast<idx_t>(std::max<long long>(1, std::llround(w))));
    for (Index a = graph.adjacency_offsets[v]; a < graph.adjacency_offsets[v + 1]; ++a) {
      const Index u = graph.adjacency[a];
      if (local_of[u] == kInvalidIndex) continue;
      m.adjncy.push_back(static_cast<idx_t>(local_of[u]));
      // The same double gives the same integer both ways, so the CSR stays symmetric.
      const long long w_arc = std::llround(graph.arc_length[a] / length_unit * 1000.0);
      m.adjwgt.push_back(static_cast<idx_t>(std::clamp<long long>(w_arc, 1, 1 << 20)));
    }
    m.xadj.push_back(static_cast<idx_t>(m.adjncy.size()));
  }
  for (Index v : nodes) local_of[v] = kInvalidIndex;
  return m;
}

enum class MetisKind : std::uint8_t { Kway, Recursive };

std::vector<idx_t> run_metis(MetisGraph& m, MetisKind kind, std::size_t parts, std::span<real_t> target_weights,
                             double tolerance, bool contiguous, std::uint64_t seed) {
  if (parts < 2) throw Error("partition_cell_graph: METIS called with fewer than 2 parts");
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  options[METIS_OPTION_SEED] = static_cast<idx_t>(seed % 2147483647u);
  options[METIS_OPTION_UFACTOR] = static_cast<idx_t>(std::max<long long>(1, std::llround(1000.0 * tolerance)));
  if (contiguous) options[METIS_OPTION_CONTIG] = 1;
  idx_t n = static_cast<idx_t>(m.vwgt.size()), ncon = 1, nparts = static_cast<idx_t>(parts), cut = 0;
  std::vector<idx_t> part(m.vwgt.size(), 0);
  real_t* tp = target_weights.empty() ? nullptr : target_weights.data();
  const int rc = kind == MetisKind::Kway
                     ? METIS_PartGraphKway(&n, &ncon, m.xadj.data(), m.adjncy.data(), m.vwgt.data(), nullptr,
                                           m.adjwgt.data(), &nparts, tp, nullptr, options, &cut, part.data())
                     : METIS_PartGraphRecursive(&n, &ncon, m.xadj.data(), m.adjncy.data(), m.vwgt.data(), nullptr,
                                                m.adjwgt.data(), &nparts, tp, nullptr, options, &cut, part.data());
  if (rc != METIS_OK) {
    throw Error(std::string("partition_cell_graph: ") +
                (kind == MetisKind::Kway ? "METIS_PartGraphKway" : "METIS_PartGraphRecursive") + " failed with code " +
                std::to_string(rc) + " (" + std::to_string(n) + " nodes, " + std::to_string(parts) + " parts)");
  }
  return part;
}

/// A position per node: the mean of its corners (a node without corners, a cell
/// enclosed by one other cell, takes the mean of its neighbours' positions).
std::vector<Vec2> node_positions(const CellGraph& graph) {
  const std::size_t n = graph.node_count();
  std::vector<Vec2> position(n, Vec2::Zero());
  std::vector<char> known(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    const Index begin = graph.node_corner_offsets[v], end = graph.node_corner_offsets[v + 1];
    if (begin == end) continue;
    for (Index i = begin; i < end; ++i) position[v] += graph.corner_position[graph.node_corners[i]];
    position[v] /= static_cast<double>(end - begin);
    known[v] = 1;
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (known[v]) continue;
    std::size_t count = 0;
    for (Index a = graph.adjacency_offsets[v]; a < graph.adjacency_offsets[v + 1]; ++a)
      if (known[graph.adjacency[a]]) {
        position[v] += position[graph.adjacency[a]];
        ++count;
      }
    if (count > 0) position[v] /= static_cast<double>(count);
  }
  return position;
}

// ---------------------------------------------------------------------------------
// Refinement of J = L_S + lambda D_theta (design §2.7), shared by the bisections
// (two active labels) and the k-way pass (all labels active).
// ---------------------------------------------------------------------------------

class Refiner {
 public:
  Refiner(const CellGraph& graph, std::vector<Label>& labels, std::size_t label_count, double lambda,
          bool boundary_corners)
      : graph_(graph),
        labels_(labels),
        lambda_(lambda),
        boundary_corners_(boundary_corners),
        area_(label_count, 0.0),
        lo_(label_count, 0.0),
        hi_(label_count, kInf),
        active_(label_count, 0),
        visit_stamp_(graph.node_count(), 0),
        key_(graph.node_count(), kInf),
        locked_(graph.node_count(), 0),
        eps_(1e-9 * mean_arc(graph)) {
    double total = 0;
    for (double a : graph.node_area) total += a;
    mean_node_area_ = graph.node_count() > 0 ? total / static_cast<double>(graph.node_count()) : 0.0;
  }

  /// Makes `label` movable with area band [lo, hi]; its area is summed over `nodes`.
  void activate(Label label, double lo, double hi) {
    active_[label] = 1;
    lo_[label] = lo;
    hi_[label] = hi;
    area_[label] = 0;
  }
  void deactivate(Label label) { active_[label] = 0; }
  void add_area(Label label, double a) { area_[label] += a; }
  double area(Label label) const { return area_[label]; }
  double band_violation(Label label) const { return violation(label, area_[label]); }

  /// J restricted to what a bisection of `nodes` can change: arcs inside the group
  /// and the corners of its nodes.
  double group_objective(std::span<const Index> nodes) {
    double length = 0, angle = 0;
    ++stamp_;
    for (Index v : nodes) visit_stamp_[v] = stamp_;
    for (Index v : nodes)
      for (Index a = graph_.adjacency_offsets[v]; a < graph_.adjacency_offsets[v + 1]; ++a) {
        const Index u = graph_.adjacency[a];
        if (u > v && visit_stamp_[u] == stamp_ && labels_[u] != labels_[v]) length += graph_.arc_length[a];
      }
    if (lambda_ == 0) return length;
    corner_seen_.resize(graph_.corner_position.size(), 0);
    ++corner_stamp_;
    for (Index v : nodes)
      for (Index i = graph_.node_corner_offsets[v]; i < graph_.node_corner_offsets[v + 1]; ++i) {
        const Index c = graph_.node_corners[i];
        if (corner_seen_[c] == corner_stamp_) continue;
        corner_seen_[c] = corner_stamp_;
        angle += corner_value(c);
      }
    return length + lambda_ * angle;
  }

  bool in_band(Label label) const {
    const double slack = 1e-9 * std::max(1.0, hi_[label]);
    return area_[label] >= lo_[label] - slack && area_[label] <= hi_[label] + slack;
  }

  /// One refinement pass, Fiduccia-Mattheyses style: the best feasible move of any
  /// gain is applied in order of dJ (a priority queue keyed (dJ, node), lazily
  /// updated), each node at most once, and the pass is rolled back to its best
  /// prefix (least band violation, then least J). Zero-gain moves let a staircase
  /// separator on a grid slide row by row into a straight one, which strictly
  /// improving single moves cannot do. Returns the moves kept.
  std::size_t refinement_pass(std::span<const Index> nodes) {
    using Entry = std::pair<double, Index>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap;
    ++round_;
    const auto consider = [&](Index v) {
      if (locked_[v] == round_) return;
      const Move m = best_move(v, kInf);
      key_[v] = m.to >= 0 ? m.gain : kInf;
      if (key_[v] < kInf) heap.emplace(key_[v], v);
    };
    for (Index v : nodes) consider(v);
    log_.clear();
    double cumulative = 0, best_cumulative = 0, violation_now = total_violation();
    double best_violation = violation_now;
    std::size_t best_length = 0;
    // A climb that has not paid off after this many moves is abandoned.
    const std::size_t patience = std::max<std::size_t>(64, nodes.size() / 16);
    const double tiny = 1e-12 * std::max(1.0, best_violation);
    while (!heap.empty() && log_.size() < best_length + patience) {
      const auto [g, v] = heap.top();
      heap.pop();
      if (g != key_[v] || locked_[v] == round_) continue;  // stale entry
      key_[v] = kInf;
      const Move m = best_move(v, kInf);
      if (m.to < 0) continue;
      if (m.gain > g + eps_) {  // the neighbourhood changed; queue at its true gain
        key_[v] = m.gain;
        heap.emplace(m.gain, v);
        continue;
      }
      const Label from = labels_[v];
      const double a = graph_.node_area[v];
      violation_now += violation(from, area_[from] - a) + violation(m.to, area_[m.to] + a) -
                       violation(from, area_[from]) - violation(m.to, area_[m.to]);
      apply(v, m.to);
      locked_[v] = round_;
      log_.emplace_back(v, from);
      cumulative += m.gain;
      if (violation_now < best_violation - tiny ||
          (violation_now <= best_violation + tiny && cumulative < best_cumulative - eps_)) {
        best_violation = std::min(best_violation, violation_now);
        best_cumulative = cumulative;
        best_length = log_.size();
      }
      for_each_affected(v, consider);
    }
    while (log_.size() > best_length) {
      apply(log_.back().first, log_.back().second);
      log_.pop_back();
    }
    for (Index v : nodes) key_[v] = kInf;
    return best_length;
  }

  /// Balancing pass (design §2.7): while an active part is outside its band, move
  /// one node along a shortest chain of parts from a part with surplus to a part
  /// with room (cheapest feasible dJ per hop), kept only when the total band
  /// violation drops. Returns the number of moves kept.
  std::size_t balance(std::span<const Index> nodes) {
    std::vector<char> stuck(area_.size(), 0);
    std::size_t kept = 0;
    // Part membership is rebuilt (O(n)) only when a chain fails on a stale one:
    // departed nodes are skipped by the transfer, and a part that received nodes
    // rarely needs them as candidates, so long one-way transfers stay near-linear.
    bool members_dirty = true, members_fresh = false;
    const std::size_t cap = 2 * nodes.size() + 64;
    for (std::size_t iteration = 0; iteration < cap; ++iteration) {
      Label worst = -1;
      double worst_violation = 0;
      for (Label l = 0; l < static_cast<Label>(area_.size()); ++l) {
        if (!active_[l] || stuck[l] || in_band(l)) continue;
        const double viol = violation(l, area_[l]);
        if (viol > worst_violation) {
          worst_violation = viol;
          worst = l;
        }
      }
      if (worst < 0) break;
      if (members_dirty) {
        build_members(nodes);
        members_dirty = false;
        members_fresh = true;
      }
      const bool surplus = area_[worst] > hi_[worst];
      // First a chain to a part with room for a mean cell, else one past its middle.
      std::vector<Label> chain = part_chain(worst, surplus, mean_node_area_);
      if (chain.size() < 2) chain = part_chain(worst, surplus, -1);
      if (chain.size() < 2) {
        if (members_fresh) stuck[worst] = 1;
        members_dirty = true;
        blocked_.clear();
        continue;
      }
      const double before = total_violation();
      std::vector<std::pair<Index, Label>> undo;
      bool ok = true;
      std::pair<Label, Label> failed_hop{-1, -1};
      // Fill the receiving end first so every intermediate part only passes area on.
      for (std::size_t hop = chain.size() - 1; hop-- > 0;) {
        const Index v = cheapest_transfer(chain[hop], chain[hop + 1]);
        if (v == kInvalidIndex) {
          failed_hop = {chain[hop], chain[hop + 1]};
          ok = false;
          break;
        }
        undo.emplace_back(v, chain[hop]);
        apply(v, chain[hop + 1]);
      }
      if (ok && total_violation() < before - 1e-12 * std::max(1.0, before)) {
        kept += undo.size();
        members_fresh = false;
        blocked_.clear();
        continue;
      }
      for (auto it = undo.rbegin(); it != undo.rend(); ++it) apply(it->first, it->second);
      // A hop with no movable cell (every candidate would disconnect or pinch its
      // part) is blocked and another chain tried, a few times, before giving up.
      if (!ok && blocked_.size() < kMaxBlockedHops) {
        blocked_.push_back(failed_hop);
        continue;
      }
      blocked_.clear();
      if (members_fresh) stuck[worst] = 1;
      members_dirty = true;  // retry once on the current membership
    }
    return kept;
  }

 private:
  struct Move {
    double gain = kInf;
    Label to = -1;
  };

  double violation(Label l, double a) const { return std::max(0.0, a - hi_[l]) + std::max(0.0, lo_[l] - a); }
  double total_violation() const {
    double sum = 0;
    for (std::size_t l = 0; l < area_.size(); ++l)
      if (active_[l]) sum += violation(static_cast<Label>(l), area_[l]);
    return sum;
  }

  void apply(Index v, Label to) {
    const Label from = labels_[v];
    area_[from] -= graph_.node_area[v];
    area_[to] += graph_.node_area[v];
    labels_[v] = to;
  }

  template <class F>
  void for_each_affected(Index v, F&& f) {
    for (Index a = graph_.adjacency_offsets[v]; a < graph_.adjacency_offsets[v + 1]; ++a) f(graph_.adjacency[a]);
    // Nodes sharing only a corner with v (a 4-valent grid vertex) see their dD_theta change too.
    for (Index i = graph_.node_corner_offsets[v]; i < graph_.node_corner_offsets[v + 1]; ++i) {
      const Index c = graph_.node_corners[i];
      for (Index s = graph_.corner_offsets[c]; s < graph_.corner_offsets[c + 1]; ++s) {
        const Index u = graph_.spokes[s].left_node;
        if (u != kInvalidIndex && u != v) f(u);
      }
    }
  }

  double corner_value(Index c) const {
    const CornerCost cost = corner_cost_at(graph_, c, labels_);
    return cost.separator_sum + (boundary_corners_ ? cost.boundary_sum : 0.0);
  }

  /// dJ of moving v to `to`: dL_S from v's arcs, dD_theta by recomputing the corners
  /// of v (eq. (3.7) restricted to what the move can change).
  double gain(Index v, Label to) {
    const Label from = labels_[v];
    double d_length = 0;
    for (Index a = graph_.adjacency_offsets[v]; a < graph_.adjacency_offsets[v + 1]; ++a) {
      const Label l = labels_[graph_.adjacency[a]];
      if (l == from) d_length += graph_.arc_length[a];
      if (l == to) d_length -= graph_.arc_length[a];
    }
    if (lambda_ == 0) return d_length;
    double d_angle = 0;
    for (Index i = graph_.node_corner_offsets[v]; i < graph_.node_corner_offsets[v + 1]; ++i) {
      const Index c = graph_.node_corners[i];
      d_angle -= corner_value(c);
      labels_[v] = to;
      d_angle += corner_value(c);
      labels_[v] = from;
    }
    return d_length + lambda_ * d_angle;
  }

  /// Whether the part of v stays connected without v: its neighbours in that part
  /// must meet again in a BFS of the part that avoids v. The BFS is capped (a move
  /// that cannot be proved safe cheaply is rejected), which keeps a pass near-linear:
  /// in a planar dual the neighbours usually form one run and meet at once.
  bool source_stays_connected(Index v) {
    const Label from = labels_[v];
    std::size_t targets = 0;
    Index start = kInvalidIndex;
    ++stamp_;
    for (Index a = graph_.adjacency_offsets[v]; a < graph_.adjacency_offsets[v + 1]; ++a) {
      const Index u = graph_.adjacency[a];
      if (labels_[u] != from || visit_stamp_[u] == stamp_ + 1) continue;
      visit_stamp_[u] = stamp_ + 1;  // "a neighbour still to reach"
      ++targets;
      if (start == kInvalidIndex) start = u;
    }
    if (targets == 0) {
      ++stamp_;
      return false;  // v is the whole part
    }
    if (targets == 1) {
      ++stamp_;
      return true;  // a leaf of its part
    }
    const std::uint32_t reached = stamp_ + 2;
    const std::uint32_t pending = stamp_ + 1;
    stamp_ += 2;
    std::size_t found = 1;
    bfs_.clear();
    bfs_.push_back(start);
    visit_stamp_[start] = reached;
    visit_stamp_[v] = reached;
    constexpr std::size_t kBudget = 512;
    for (std::size_t head = 0; head < bfs_.size() && found < targets && bfs_.size() < kBudget; ++head) {
      const Index w = bfs_[head];
      for (Index a = graph_.adjacency_offsets[w]; a < graph_.adjacency_offsets[w + 1]; ++a) {
        const Index u = graph_.adjacency[a];
        if (labels_[u] != from || visit_stamp_[u] == reached) continue;
        if (visit_stamp_[u] == pending) ++found;
        visit_stamp_[u] = reached;
        bfs_.push_back(u);
      }
    }
    return found == targets;
  }

  /// Runs of `label` in the cyclic sector sequence of corner c (outside = -1).
  int runs(Index c, Label label) const {
    const Index begin = graph_.corner_offsets[c], end = graph_.corner_offsets[c + 1];
    const auto sector = [&](Index s) {
      const Index node = graph_.spokes[s].left_node;
      return node == kInvalidIndex ? Label{-1} : labels_[node];
    };
    int count = 0;
    bool all = true;
    for (Index s = begin; s < end; ++s) {
      const Label here = sector(s), before = sector(s == begin ? end - 1 : s - 1);
      if (here != label) all = false;
      if (here == label && before != label) ++count;
    }
    return all && end > begin ? 1 : count;
  }

  /// No pinch (design §2.7): after the move, neither part involved may occupy two
  /// separate sectors of one of v's corners unless it already did (a vertex-only
  /// self-contact makes a self-touching ring that check_region rejects).
  bool creates_pinch(Index v, Label to) {
    const Label from = labels_[v];
    for (Index i = graph_.node_corner_offsets[v]; i < graph_.node_corner_offsets[v + 1]; ++i) {
      const Index c = graph_.node_corners[i];
      const int from_before = runs(c, from), to_before = runs(c, to);
      labels_[v] = to;
      const int from_after = runs(c, from), to_after = runs(c, to);
      labels_[v] = from;
      if ((from_after > 1 && from_after > from_before) || (to_after > 1 && to_after > to_before)) return true;
    }
    return false;
  }

  /// The feasible move of v with the smallest dJ below `threshold` (to = -1 when none).
  Move best_move(Index v, double threshold) {
    const Label from = labels_[v];
    if (!active_[from]) return {};
    Label targets[16];
    std::size_t count = 0;
    for (Index a = graph_.adjacency_offsets[v]; a < graph_.adjacency_offsets[v + 1] && count < 16; ++a) {
      const Label l = labels_[graph_.adjacency[a]];
      if (l == from || !active_[l] || std::find(targets, targets + count, l) != targets + count) continue;
      targets[count++] = l;
    }
    if (count == 0) return {};
    const double a = graph_.node_area[v];
    std::pair<double, Label> candidates[16];
    std::size_t improving = 0;
    for (std::size_t t = 0; t < count; ++t) {
      const Label to = targets[t];
      // Balance may not get worse (eq. (3.1) band, or the k-way band).
      const double before = violation(from, area_[from]) + violation(to, area_[to]);
      const double after = violation(from, area_[from] - a) + violation(to, area_[to] + a);
      if (after > before + 1e-12 * std::max(1.0, area_[from])) continue;
      const double g = gain(v, to);
      if (g < threshold) candidates[improving++] = {g, to};
    }
    if (improving == 0) return {};
    std::sort(candidates, candidates + improving);
    if (!source_stays_connected(v)) return {};
    for (std::size_t t = 0; t < improving; ++t)
      if (!creates_pinch(v, candidates[t].second)) return {candidates[t].first, candidates[t].second};
    return {};
  }

  /// Part membership of `nodes` as CSR by label (for the balancing pass).
  void build_members(std::span<const Index> nodes) {
    member_offsets_.assign(area_.size() + 1, 0);
    for (Index v : nodes) ++member_offsets_[labels_[v] + 1];
    for (std::size_t l = 0; l < area_.size(); ++l) member_offsets_[l + 1] += member_offsets_[l];
    members_.resize(nodes.size());
    std::vector<Index> fill(member_offsets_.begin(), member_offsets_.end() - 1);
    for (Index v : nodes) members_[fill[labels_[v]]++] = v;
  }

  bool is_blocked(Label p, Label q) const {
    for (const auto& [a, b] : blocked_)
      if ((a == p && b == q) || (a == q && b == p)) return true;
    return false;
  }

  /// Shortest chain of adjacent active parts from a part with surplus to one with
  /// room (below / above the middle of its band), found by BFS from `part`.
  /// Returned from the giving end to the receiving end.
  std::vector<Label> part_chain(Label part, bool surplus, double need) {
    std::vector<Label> parent(area_.size(), -2);
    std::vector<Label> queue{part};
    parent[part] = -1;
    Label found = -1;
    for (std::size_t head = 0; head < queue.size() && found < 0; ++head) {
      const Label p = queue[head];
      for (Index i = member_offsets_[p]; i < member_offsets_[p + 1] && found < 0; ++i) {
        const Index v = members_[i];
        for (Index a = graph_.adjacency_offsets[v]; a < graph_.adjacency_offsets[v + 1]; ++a) {
          const Label q = labels_[graph_.adjacency[a]];
          if (!active_[q] || parent[q] != -2) continue;
          if (is_blocked(p, q)) continue;
          parent[q] = p;
          queue.push_back(q);
          // The far end must have room for about one cell: with cells wider than
          // half the band, a part merely past the middle of its band would just
          // fall out of it on the other side.
          const double room = surplus ? hi_[q] - area_[q] : area_[q] - lo_[q];
          if (room >= (need > 0 ? need : 0.5 * (hi_[q] - lo_[q]))) {
            found = q;
            break;
          }
        }
      }
    }
    if (found < 0) return {};
    std::vector<Label> chain;
    for (Label q = found; q >= 0; q = parent[q]) chain.push_back(q);
    // chain runs found .. part; surplus flows from `part` to `found`.
    if (surplus) std::reverse(chain.begin(), chain.end());
    return chain;
  }

  /// The feasible node of `from` adjacent to `to` with the smallest dJ among those
  /// whose move does not add band violation to the two parts; when there is none,
  /// the one adding the least. With about 30 cells per part a typical cell is wider
  /// than half the band, so the cheapest cell by dJ alone would often overshoot the
  /// giving part and the chain be rejected, while a smaller (e.g. boundary-clipped)
  /// cell fits.
  Index cheapest_transfer(Label from, Label to) {
    Index best = kInvalidIndex;
    bool best_fits = false;
    double best_change = kInf, best_gain = kInf;
    const double before = violation(from, area_[from]) + violation(to, area_[to]);
    const double tolerance = 1e-12 * std::max(1.0, area_[from]);
    for (Index i = member_offsets_[from]; i < member_offsets_[from + 1]; ++i) {
      const Index v = members_[i];
      if (labels_[v] != from) continue;  // moved earlier in this chain
      bool adjacent = false;
      for (Index a = graph_.adjacency_offsets[v]; a < graph_.adjacency_offsets[v + 1] && !adjacent; ++a)
        adjacent = labels_[graph_.adjacency[a]] == to;
      if (!adjacent) continue;
      const double a = graph_.node_area[v];
      const double change = violation(from, area_[from] - a) + violation(to, area_[to] + a) - before;
      const bool fits = change <= tolerance;
      if (best_fits && !fits) continue;
      if (!fits && change > best_change + tolerance) continue;
      const double g = gain(v, to);
      if (fits == best_fits && (fits || change >= best_change - tolerance) && g >= best_gain) continue;
      if (!source_stays_connected(v) || creates_pinch(v, to)) continue;
      best_fits = fits;
      best_change = change;
      best_gain = g;
      best = v;
    }
    return best;
  }

  const CellGraph& graph_;
  std::vector<Label>& labels_;
  double lambda_;
  bool boundary_corners_;
  std::vector<double> area_, lo_, hi_;
  std::vector<char> active_;
  std::vector<std::uint32_t> visit_stamp_;
  std::uint32_t stamp_ = 0;
  std::vector<Index> bfs_;
  std::vector<double> key_;
  std::vector<std::uint32_t> locked_;
  std::vector<std::uint32_t> corner_seen_;
  std::uint32_t corner_stamp_ = 0;
  std::uint32_t round_ = 0;
  std::vector<std::pair<Index, Label>> log_;
  std::vector<Index> member_offsets_, members_;
  double eps_;
  double mean_node_area_ = 0;
  static constexpr std::size_t kMaxBlockedHops = 16;
  std::vector<std::pair<Label, Label>> blocked_;  // hops of the balancing pass found impossible
};

// ---------------------------------------------------------------------------------
// The recursive driver.
// ---------------------------------------------------------------------------------

bool is_baseline(GraphPartitionOptions::Engine engine) {
  return engine == GraphPartitionOptions::Engine::MetisKway || engine == GraphPartitionOptions::Engine::MetisRecursive;
}

class Partitioner {
 public:
  Partitioner(const CellGraph& graph, const GraphPartitionOptions& options, GraphPartitionReport& report)
      : graph_(graph),
        options_(options),
        report_(report),
        lambda_(is_baseline(options.engine) ? 0.0 : options.angle_weight * mean_arc(graph)),
        tolerance_(detail::bisection_tolerance(options.parts, options.imbalance)),
        labels_(graph.node_count(), 0),
        local_of_(graph.node_count(), kInvalidIndex),
        refiner_(graph, labels_, options.parts, lambda_, options.boundary_corners),
        position_(node_positions(graph)) {}

  std::vector<Label> run() {
    std::vector<Index> all(graph_.node_count());
    for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<Index>(v);
    const std::size_t k = options_.parts;
    switch (options_.engine) {
      case GraphPartitionOptions::Engine::RecursiveGp:
        bisect(std::move(all), 0, k);
        kway_refinement();
        break;
      case GraphPartitionOptions::Engine::Exact:
        start_ = std::chrono::steady_clock::now();
        pending_volume_ = static_cast<double>(all.size() * ceil_log2(k));
        report_.exact_gap = 0;
        report_.exact_proven = true;
        bisect(std::move(all), 0, k);
        break;
      case GraphPartitionOptions::Engine::MetisKway:
      case GraphPartitionOptions::Engine::MetisRecursive:
        metis_baseline(all);
        break;
    }
    finish();
    return std::move(labels_);
  }

  /// RecursiveGp's first bisection alone (for detail::gp_first_bisection).
  std::vector<Label> first_bisection() {
    detail::BisectionProblem problem = detail::first_bisection_problem(graph_, options_);
    gp_bisection(problem);
    for (Label& l : labels_) l = l == problem.label1 ? 1 : 0;
    return std::move(labels_);
  }

 private:
  void bisect(std::vector<Index> nodes, Label first, std::size_t k) {
    if (k < 2) return;
    std::size_t k0 = k / 2, k1 = k - k0;
    Label second = first + static_cast<Label>(k0);
    detail::BisectionProblem problem = detail::make_bisection(graph_, std::move(nodes), first, second, k0, k1,
                                                              tolerance_, lambda_, options_.boundary_corners);
    if (options_.engine == GraphPartitionOptions::Engine::Exact) {
      exact_step(problem, k);
    } else {
      gp_bisection(problem);
    }
    std::vector<Index> side0, side1;
    for (Index v : problem.nodes) (labels_[v] == first ? side0 : side1).push_back(v);
    // Beyond the dissertation: when the geometry keeps a bisection more than half a
    // part's area from its target (a sound reachable only through a narrow channel,
    // whose cells cannot all move without cutting it off), the part counts follow
    // the areas instead, k0 = round(k A0 / A), so the deeper bisections can balance.
    if (options_.engine == GraphPartitionOptions::Engine::RecursiveGp) {
      double area0 = 0, area1 = 0;
      for (Index v : side0) area0 += graph_.node_area[v];
      for (Index v : side1) area1 += graph_.node_area[v];
      const double part = (area0 + area1) / static_cast<double>(k);
      if (std::abs(area0 - part * static_cast<double>(k0)) > 0.5 * part) {
        const auto adapted = static_cast<std::size_t>(
            std::clamp<long long>(std::llround(area0 / part), 1, static_cast<long long>(k) - 1));
        if (adapted <= side0.size() && k - adapted <= side1.size()) {
          k0 = adapted;
          k1 = k - k0;
          second = first + static_cast<Label>(k0);
          for (Index v : side1) labels_[v] = second;
        }
      }
    }
    if (side0.size() < k0 || side1.size() < k1) {
      throw InputError("partition_cell_graph: a bisection left fewer cells than parts on one side (" +
                       std::to_string(side0.size()) + " cells for " + std::to_string(k0) + " parts, " +
                       std::to_string(side1.size()) + " for " + std::to_string(k1) + "); raise --cells");
    }
    problem.nodes.clear();
    problem.nodes.shrink_to_fit();
    bisect(std::move(side0), first, k0);
    bisect(std::move(side1), second, k1);
  }

  /// CVT-GP bisection (design §2.7): METIS 2-way with targets k0/k, k1/k, repair,
  /// then passes of refinement and balancing on J until nothing moves.
  ///
  /// Beyond the dissertation: two more starts, straight cuts across x and across y
  /// at the target area (node positions = mean of their corners), are refined the
  /// same way and the best result by (band violation, J) is kept. The L_p-CVT cells
  /// line up with the axes (§1.6), so an axis-parallel cut is often the separator
  /// J wants, and on near-regular cells a graph refinement of single-node moves
  /// cannot turn METIS's staircase into it (every step move has dJ = 0).
  void gp_bisection(const detail::BisectionProblem& problem) {
    std::vector<Label> best;
    double best_violation = kInf, best_value = kInf;
    std::size_t best_moved = 0;
    for (int start = 0; start < 3; ++start) {
      if (start == 0)
        metis_split(problem);
      else
        coordinate_split(problem, start - 1);
      const SideRepair initial = count_and_repair_sides(problem);
      if (start > 0 && far_from_band(problem)) continue;
      // The report describes METIS's output (a straight cut across a non-convex
      // region is often in pieces, and repaired like METIS's).
      if (start == 0) report_.components_before_repair = std::max(report_.components_before_repair, initial.components);
      refiner_.activate(problem.label0, problem.lo0, problem.hi0);
      refiner_.activate(problem.label1, problem.lo1, problem.hi1);
      for (Index v : problem.nodes) refiner_.add_area(labels_[v], graph_.node_area[v]);
      refiner_.balance(problem.nodes);
      for (int pass = 0; pass < options_.refinement_passes; ++pass) {
        const std::size_t moved = refiner_.refinement_pass(problem.nodes) + refiner_.balance(problem.nodes);
        if (moved == 0) break;
      }
      // Every move kept both sides connected; this only guards the invariant.
      const std::size_t moved = initial.moved + count_and_repair_sides(problem).moved;
      const double violation = refiner_.band_violation(problem.label0) + refiner_.band_violation(problem.label1);
      const double value = refiner_.group_objective(problem.nodes);
      refiner_.deactivate(problem.label0);
      refiner_.deactivate(problem.label1);
      const double tiny = 1e-9 * std::max(1.0, value);
      if (violation < best_violation - 1e-12 || (violation <= best_violation + 1e-12 && value < best_value - tiny)) {
        best_violation = violation;
        best_value = value;
        best_moved = moved;
        best.resize(problem.nodes.size());
        for (std::size_t i = 0; i < best.size(); ++i) best[i] = labels_[problem.nodes[i]];
      }
    }
    for (std::size_t i = 0; i < best.size(); ++i) labels_[problem.nodes[i]] = best[i];
    report_.moved_by_repair += best_moved;
  }

  /// Whether side 0 misses its band by more than a tenth of the group's area: a
  /// straight cut across a non-convex group whose repair moved whole pieces. Such a
  /// start is dropped rather than rebalanced node by node.
  bool far_from_band(const detail::BisectionProblem& problem) const {
    double side0 = 0, total = 0;
    for (Index v : problem.nodes) {
      total += graph_.node_area[v];
      if (labels_[v] == problem.label0) side0 += graph_.node_area[v];
    }
    return side0 < problem.lo0 - 0.1 * total || side0 > problem.hi0 + 0.1 * total;
  }

  /// A straight cut across `axis` (0 = x, 1 = y): side 0 takes the nodes of lowest
  /// coordinate (ties by the other coordinate, then id) up to its target area.
  void coordinate_split(const detail::BisectionProblem& problem, int axis) {
    std::vector<Index> order(problem.nodes);
    std::sort(order.begin(), order.end(), [&](Index a, Index b) {
      const Vec2 &p = position_[a], &q = position_[b];
      if (p[axis] != q[axis]) return p[axis] < q[axis];
      if (p[1 - axis] != q[1 - axis]) return p[1 - axis] < q[1 - axis];
      return a < b;
    });
    const double target = 0.5 * (problem.lo0 + problem.hi0);
    double grown = 0;
    for (std::size_t i = 0; i < order.size(); ++i) {
      const bool low = i == 0 || (i + 1 < order.size() && grown + 0.5 * graph_.node_area[order[i]] <= target);
      labels_[order[i]] = low ? problem.label0 : problem.label1;
      if (low) grown += graph_.node_area[order[i]];
    }
  }

  /// METIS_PartGraphRecursive 2-way on the group; an empty side (KarypisLab/METIS#91)
  /// falls back to growing side 0 by BFS from a far node up to its target area.
  void metis_split(const detail::BisectionProblem& problem) {
    const std::span<const Index> nodes(problem.nodes);
    MetisGraph m = metis_graph(graph_, nodes, local_of_);
    // The bands are centred on the targets W k0 / k and W k1 / k.
    const double k_fraction = (problem.lo0 + problem.hi0) / (problem.lo0 + problem.hi0 + problem.lo1 + problem.hi1);
    real_t targets[2] = {static_cast<real_t>(k_fraction), static_cast<real_t>(1.0 - k_fraction)};
    const std::vector<idx_t> part = run_metis(m, MetisKind::Recursive, 2, targets, tolerance_, false, options_.seed);
    std::size_t count0 = 0;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      labels_[nodes[i]] = part[i] == 0 ? problem.label0 : problem.label1;
      count0 += part[i] == 0;
    }
    if (count0 > 0 && count0 < nodes.size()) return;
    grow_split(problem, k_fraction);
  }

  void grow_split(const detail::BisectionProblem& problem, double fraction) {
    const std::span<const Index> nodes(problem.nodes);
    double total = 0;
    for (Index v : nodes) {
      total += graph_.node_area[v];
      labels_[v] = problem.label1;
      local_of_[v] = 0;
    }
    // A pseudo-peripheral start: the last node of a BFS from the first node.
    const auto bfs_order = [&](Index start) {
      std::vector<Index> order{start};
      local_of_[start] = 1;
      for (std::size_t head = 0; head < order.size(); ++head) {
        const Index w = order[head];
        for (Index a = graph_.adjacency_offsets[w]; a < graph_.adjacency_offsets[w + 1]; ++a) {
          const Index u = graph_.adjacency[a];
          if (local_of_[u] != 0) continue;
          local_of_[u] = 1;
          order.push_back(u);
        }
      }
      for (Index v : nodes) local_of_[v] = 0;
      return order;
    };
    const Index start = bfs_order(nodes.front()).back();
    std::vector<Index> order = bfs_order(start);
    double grown = 0;
    for (std::size_t i = 0; i + 1 < order.size() && grown < fraction * total; ++i) {
      labels_[order[i]] = problem.label0;
      grown += graph_.node_area[order[i]];
    }
    for (Index v : nodes) local_of_[v] = kInvalidIndex;
  }

  /// Region growing per side (design §2.7, "moves disconnected pieces to the other
  /// side"): the largest component of a side stays, every other component that
  /// touches the other side flips to it.
  struct SideRepair {
    std::size_t components = 0;  ///< most components of a side before the repair
    std::size_t moved = 0;
  };
  SideRepair count_and_repair_sides(const detail::BisectionProblem& problem) {
    const std::span<const Index> nodes(problem.nodes);
    for (std::size_t i = 0; i < nodes.size(); ++i) local_of_[nodes[i]] = static_cast<Index>(i);
    std::vector<Index> component(nodes.size(), kInvalidIndex);
    std::vector<double> component_area;
    std::vector<Label> component_label;
    std::vector<Index> stack;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (component[i] != kInvalidIndex) continue;
      const Index id = static_cast<Index>(component_area.size());
      const Label l = labels_[nodes[i]];
      double area = 0;
      component[i] = id;
      stack.assign(1, static_cast<Index>(i));
      while (!stack.empty()) {
        const Index w = stack.back();
        stack.pop_back();
        area += graph_.node_area[nodes[w]];
        for (Index a = graph_.adjacency_offsets[nodes[w]]; a < graph_.adjacency_offsets[nodes[w] + 1]; ++a) {
          const Index u = local_of_[graph_.adjacency[a]];
          if (u == kInvalidIndex || component[u] != kInvalidIndex || labels_[nodes[u]] != l) continue;
          component[u] = id;
          stack.push_back(u);
        }
      }
      component_area.push_back(area);
      component_label.push_back(l);
    }
    Index largest[2] = {kInvalidIndex, kInvalidIndex};
    std::size_t count[2] = {0, 0};
    for (Index c = 0; c < component_area.size(); ++c) {
      const int side = component_label[c] == problem.label0 ? 0 : 1;
      ++count[side];
      if (largest[side] == kInvalidIndex || component_area[c] > component_area[largest[side]]) largest[side] = c;
    }
    SideRepair repair;
    repair.components = std::max(count[0], count[1]);
    if (count[0] <= 1 && count[1] <= 1) {
      for (Index v : nodes) local_of_[v] = kInvalidIndex;
      return repair;
    }
    std::vector<char> touches_other(component_area.size(), 0);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      for (Index a = graph_.adjacency_offsets[nodes[i]]; a < graph_.adjacency_offsets[nodes[i] + 1]; ++a) {
        const Index u = local_of_[graph_.adjacency[a]];
        if (u != kInvalidIndex && labels_[nodes[u]] != labels_[nodes[i]]) touches_other[component[i]] = 1;
      }
    }
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const Index c = component[i];
      if (c == largest[0] || c == largest[1] || !touches_other[c]) continue;
      labels_[nodes[i]] = component_label[c] == problem.label0 ? problem.label1 : problem.label0;
      ++repair.moved;
    }
    for (Index v : nodes) local_of_[v] = kInvalidIndex;
    return repair;
  }

  /// Exact engine: the CVT-GP bisection first (a fallback incumbent), then the MILP
  /// with the share of the remaining time proportional to this group's work.
  void exact_step(const detail::BisectionProblem& problem, std::size_t k) {
    gp_bisection(problem);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double remaining = std::max(0.0, options_.exact_time_limit - elapsed);
    const double volume = static_cast<double>(problem.nodes.size() * ceil_log2(k));
    const double seconds = pending_volume_ > volume ? remaining * volume / pending_volume_ : remaining;
    pending_volume_ -= volume;
    const std::size_t k0 = k / 2;
    const std::size_t half = problem.nodes.size() / 2;
    pending_volume_ += static_cast<double>(half * ceil_log2(k0) + (problem.nodes.size() - half) * ceil_log2(k - k0));
    const detail::ExactBisectionResult r = detail::exact_bisection(graph_, labels_, problem, seconds);
    const double gap = r.objective > 0 ? (r.objective - r.bound) / r.objective : 0.0;
    report_.exact_gap = std::max(report_.exact_gap, std::max(0.0, gap));
    report_.exact_proven = report_.exact_proven && r.proven;
    report_.moved_by_repair += count_and_repair_sides(problem).moved;
  }

  /// k-way refinement over the finished partition (design §1.8 step 6): band
  /// L <= A_p <= U with U / L = 1 + imbalance, passes of greedy + balancing, and a
  /// connectivity check after each pass.
  void kway_refinement() {
    const std::size_t k = options_.parts;
    activate_kway_band();
    std::vector<Index> all(graph_.node_count());
    for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<Index>(v);
    refiner_.balance(all);
    for (int pass = 0; pass < options_.refinement_passes; ++pass) {
      const std::size_t moved = refiner_.refinement_pass(all) + refiner_.balance(all);
      if (max_components_per_part(graph_, labels_, k) > 1) {
        report_.moved_by_repair += repair_connectivity(graph_, labels_, k);
        activate_kway_band();
        refiner_.balance(all);
      }
      if (moved == 0) break;
    }
  }

  /// The baselines: METIS k-way (CONTIG when the graph is connected) or recursive,
  /// empty parts refilled, then the components counted and repaired. Kway gets
  /// UFACTOR = 1000 imbalance (largest part <= (1 + e) A): a tighter bound, e.g. our
  /// band's A sqrt(1 + e), made its cuts 50% longer at 24 cells per part.
  void metis_baseline(std::span<const Index> all) {
    const std::size_t k = options_.parts;
    MetisGraph m = metis_graph(graph_, all, local_of_);
    const bool kway = options_.engine == GraphPartitionOptions::Engine::MetisKway;
    // METIS_OPTION_CONTIG returns METIS_ERROR on a disconnected graph (RECIPES.md).
    const bool contiguous = kway && max_components_per_part(graph_, std::vector<Label>(graph_.node_count(), 0), 1) == 1;
    const std::vector<idx_t> part =
        kway ? run_metis(m, MetisKind::Kway, k, {}, options_.imbalance, contiguous, options_.seed)
             : run_metis(m, MetisKind::Recursive, k, {}, tolerance_, false, options_.seed);
    for (std::size_t v = 0; v < part.size(); ++v) labels_[v] = static_cast<Label>(part[v]);
    fill_empty_parts();
    report_.components_before_repair = max_components_per_part(graph_, labels_, k);
    if (report_.components_before_repair > 1) report_.moved_by_repair += repair_connectivity(graph_, labels_, k);
    // METIS can return an empty part (filled above with one node) and the repair can
    // hand a large piece to a neighbour; a baseline with R_W in the thousands would
    // be a straw man. So the baselines get the same balancing pass as CVT-GP, on
    // separator length alone (lambda = 0 for them), and no refinement: METIS's cuts
    // are kept wherever the band allows.
    activate_kway_band();
    refiner_.balance(all);
  }

  /// Every part active with the k-way band L <= A_p <= U, U / L = 1 + imbalance,
  /// around the mean part area, and its area summed from the current labels.
  void activate_kway_band() {
    const std::size_t k = options_.parts;
    double total = 0;
    for (double a : graph_.node_area) total += a;
    const double mean = total / static_cast<double>(k), root = std::sqrt(1 + options_.imbalance);
    for (std::size_t p = 0; p < k; ++p) refiner_.activate(static_cast<Label>(p), mean / root, mean * root);
    for (std::size_t v = 0; v < labels_.size(); ++v) refiner_.add_area(labels_[v], graph_.node_area[v]);
  }

  /// METIS can return empty parts with METIS_OK (KarypisLab/METIS#91): an empty part
  /// takes the last node of a BFS of the part with most nodes (a BFS leaf, so that
  /// part stays connected if it was).
  void fill_empty_parts() {
    const std::size_t k = options_.parts;
    for (;;) {
      std::vector<std::size_t> count(k, 0);
      for (Label l : labels_) ++count[l];
      const auto empty = std::find(count.begin(), count.end(), 0);
      if (empty == count.end()) return;
      const Label donor = static_cast<Label>(std::max_element(count.begin(), count.end()) - count.begin());
      if (count[donor] < 2) throw Error("partition_cell_graph: not enough nodes to fill every part");
      Index start = 0;
      while (labels_[start] != donor) ++start;
      std::vector<Index> order{start};
      local_of_[start] = 0;
      for (std::size_t head = 0; head < order.size(); ++head)
        for (Index a = graph_.adjacency_offsets[order[head]]; a < graph_.adjacency_offsets[order[head] + 1]; ++a) {
          const Index u = graph_.adjacency[a];
          if (labels_[u] != donor || local_of_[u] == 0) continue;
          local_of_[u] = 0;
          order.push_back(u);
        }
      for (Index v : order) local_of_[v] = kInvalidIndex;
      labels_[order.back()] = static_cast<Label>(empty - count.begin());
    }
  }

  /// Final check (design §2.7): every part non-empty and connected, one repair if
  /// not, and an Error when that does not help.
  void finish() {
    const std::size_t k = options_.parts;
    if (max_components_per_part(graph_, labels_, k) > 1) {
      report_.moved_by_repair += repair_connectivity(graph_, labels_, k);
    }
    std::vector<std::size_t> count(k, 0);
    for (Label l : labels_) ++count[l];
    for (std::size_t p = 0; p < k; ++p)
      if (count[p] == 0) throw Error("partition_cell_graph: part " + std::to_string(p) + " is empty");
    // R_W (3.2) against the requested 1 + imbalance (the k-way band itself can be
    // out of reach: 24.06 equal cells per part means parts of 24 and 25).
    std::vector<double> area(k, 0.0);
    for (std::size_t v = 0; v < labels_.size(); ++v) area[labels_[v]] += graph_.node_area[v];
    const auto [smallest, largest] = std::minmax_element(area.begin(), area.end());
    report_.balanced = *largest <= *smallest * (1 + options_.imbalance) * (1 + 1e-9);
    const std::size_t components = max_components_per_part(graph_, labels_, k);
    if (components > 1) {
      throw Error("partition_cell_graph: a part has " + std::to_string(components) +
                  " components after repair (is the graph connected?)");
    }
  }

  const CellGraph& graph_;
  const GraphPartitionOptions& options_;
  GraphPartitionReport& report_;
  double lambda_;
  double tolerance_;
  std::vector<Label> labels_;
  std::vector<Index> local_of_;
  Refiner refiner_;
  std::vector<Vec2> position_;
  std::chrono::steady_clock::time_point start_;
  double pending_volume_ = 0;
};

void check_input(const CellGraph& graph, const GraphPartitionOptions& options) {
  if (options.parts < 1) throw InputError("partition_cell_graph: the number of parts must be at least 1");
  if (options.parts > static_cast<std::size_t>(std::numeric_limits<Label>::max()))
    throw InputError("partition_cell_graph: too many parts");
  if (graph.node_count() < 2 * options.parts) {
    throw InputError("partition_cell_graph: too few cells for " + std::to_string(options.parts) + " parts (" +
                     std::to_string(graph.node_count()) + " graph nodes, need at least 2 per part); raise --cells");
  }
  if (!(options.imbalance >= 0)) throw InputError("partition_cell_graph: imbalance must be >= 0");
}

}  // namespace

namespace detail {

double bisection_tolerance(std::size_t parts, double imbalance) {
  const std::size_t depth = std::max<std::size_t>(1, ceil_log2(parts));
  return std::pow(1 + imbalance, 0.5 / static_cast<double>(depth)) - 1;
}

BisectionProblem make_bisection(const CellGraph& graph, std::vector<Index> nodes, std::int32_t label0,
                                std::int32_t label1, std::size_t k0, std::size_t k1, double tolerance, double lambda,
                                bool boundary_corners) {
  BisectionProblem p;
  double total = 0, largest = 0;
  for (Index v : nodes) {
    total += graph.node_area[v];
    largest = std::max(largest, graph.node_area[v]);
  }
  const double k = static_cast<double>(k0 + k1);
  const double t0 = total * static_cast<double>(k0) / k, t1 = total * static_cast<double>(k1) / k;
  const double w0 = std::max(tolerance * t0, 0.5 * largest), w1 = std::max(tolerance * t1, 0.5 * largest);
  p.nodes = std::move(nodes);
  p.label0 = label0;
  p.label1 = label1;
  p.lo0 = t0 - w0;
  p.hi0 = t0 + w0;
  p.lo1 = t1 - w1;
  p.hi1 = t1 + w1;
  p.lambda = lambda;
  p.boundary_corners = boundary_corners;
  return p;
}

double separator_length(const CellGraph& graph, std::span<const std::int32_t> labels) {
  double sum = 0;
  for (std::size_t v = 0; v < graph.node_count(); ++v)
    for (Index a = graph.adjacency_offsets[v]; a < graph.adjacency_offsets[v + 1]; ++a)
      if (graph.adjacency[a] > v && labels[graph.adjacency[a]] != labels[v]) sum += graph.arc_length[a];
  return sum;
}

double angle_cost(const CellGraph& graph, std::span<const std::int32_t> labels, bool boundary_corners) {
  const CornerCost cost = corner_cost(graph, labels);
  return cost.separator_sum + (boundary_corners ? cost.boundary_sum : 0.0);
}

double objective(const CellGraph& graph, std::span<const std::int32_t> labels, double lambda, bool boundary_corners) {
  return separator_length(graph, labels) + lambda * angle_cost(graph, labels, boundary_corners);
}

BisectionProblem first_bisection_problem(const CellGraph& graph, const GraphPartitionOptions& options) {
  std::vector<Index> all(graph.node_count());
  for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<Index>(v);
  const std::size_t k = std::max<std::size_t>(2, options.parts), k0 = k / 2;
  return make_bisection(graph, std::move(all), 0, static_cast<std::int32_t>(k0), k0, k - k0,
                        bisection_tolerance(k, options.imbalance), options.angle_weight * mean_arc(graph),
                        options.boundary_corners);
}

std::vector<std::int32_t> gp_first_bisection(const CellGraph& graph, const GraphPartitionOptions& options) {
  GraphPartitionOptions o = options;
  o.parts = std::max<std::size_t>(2, options.parts);
  check_input(graph, o);
  GraphPartitionReport report;
  return Partitioner(graph, o, report).first_bisection();
}

}  // namespace detail

std::vector<std::int32_t> partition_cell_graph(const CellGraph& graph, const GraphPartitionOptions& options,
                                               GraphPartitionReport* report) {
  check_input(graph, options);
  GraphPartitionReport local;
  GraphPartitionReport& r = report ? *report : local;
  r = GraphPartitionReport{};
  if (options.parts == 1) {
    // Never call METIS with one part (KarypisLab/METIS#86).
    std::vector<std::int32_t> labels(graph.node_count(), 0);
    r.components_before_repair = max_components_per_part(graph, labels, 1);
    if (r.components_before_repair > 1)
      throw Error("partition_cell_graph: one part asked for, but the graph has " +
                  std::to_string(r.components_before_repair) + " components");
    r.balanced = true;
    return labels;
  }
  return Partitioner(graph, options, r).run();
}

}  // namespace structmesh::partition2d
