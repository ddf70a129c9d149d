// Topological cleanup of one part's all-quad mesh: edge rotations, quad diagonal
// collapses and doublet removals chosen greedily to lower the irregularity, each
// followed by local smoothing and undone when no smoothing keeps the quads good.
//
// Canann, Muthukrishnan & Phillips 1998 ("Topological improvement procedures for
// quadrilateral finite element meshes", Engineering with Computers 14) and Kinney
// 1997 ("CleanUp", 6th International Meshing Roundtable) improve paved meshes by such
// local operations; we use three basic ones (edge rotation, diagonal collapse, doublet
// removal) and pick among them by an energy instead of by their templates: every point p with q(p) quads costs (q(p) -
// t(p))², where t = 4 for an interior point and t = max(1, θ / 90°) for a boundary point with interior angle θ. The
// boundary term matters because parts are merged along their separators: a straight separator point with two quads on
// each side becomes a regular interior point of the merged mesh (dissertation §3.3.2).
//
// Connectivity lives in flat per-point slot arrays sized once with slack (no
// per-element allocation); an operation that would overflow a slot is skipped.
// Every change goes through set_quad()/move() which log the old values, so a
// rejected operation is undone exactly (each point's quads may come back in another
// order), and an operation undone once is not tried again until a kept move has changed
// something within three rings of it (known_to_fail()). Points are visited in index order and
// candidates sorted by (energy change, kind, indices): the result is deterministic.
#include "quad2d/quad_cleanup.hpp"

#include "quad2d/paving.hpp"

#include "structmesh/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <utility>

namespace structmesh::paving {

namespace {

/// No operation may push the worst quad around it below min(its worst before, kFloor).
constexpr double kFloor = 0.5;
/// A gather at p evaluates moves on p's quads; each reads a ring of points around them
/// and its smoothing two more, and known_to_fail() looks three rings out: four rings.
constexpr int kDirtyRings = 4;
/// On a regular grid a unit charge's potential is 1.45 at its point and 0.002 this far out.
constexpr int kPotentialRings = 8;
constexpr double kField = 2.0;
constexpr double kFieldDecay = 0.9;
constexpr int kFieldSweeps = 30;
constexpr int kWarmFieldSweeps = 10;

enum class Kind : std::uint8_t { Doublet = 0, Collapse = 1, Swap = 2 };

struct Candidate {
  double delta = 0;   // energy change
  double delta2 = 0;  // secondary energy change (charge_energy), for moves with delta 0
  Kind kind = Kind::Swap;
  Index a = 0, b = 0;  // Doublet: point a; Collapse: quad a, diagonal b; Swap: edge a -> b, direction (dir)
  std::uint8_t dir = 0;
  bool operator<(const Candidate& o) const {
    if (delta != o.delta) return delta < o.delta;
    if (delta2 != o.delta2) return delta2 < o.delta2;
    if (kind != o.kind) return kind < o.kind;
    if (a != o.a) return a < o.a;
    if (b != o.b) return b < o.b;
    return dir < o.dir;
  }
  bool operator==(const Candidate& o) const { return kind == o.kind && a == o.a && b == o.b && dir == o.dir; }
};

class Cleaner {
 public:
  Cleaner(std::vector<Vec2>& points, std::vector<std::array<Index, 4>>& quads, Index fixed, double size)
      : P_(points), Q_(quads), fixed_(fixed), size_(size) {
    const auto n = static_cast<Index>(P_.size());
    cnt_.assign(n, 0);
    for (const auto& q : Q_)
      for (const Index v : q) ++cnt_[v];
    // Slots: the current count plus room for the operations (a point gains at most a
    // few quads per operation; more than 12 extra is never a sensible configuration).
    off_.assign(n + 1, 0);
    for (Index p = 0; p < n; ++p) off_[p + 1] = off_[p] + cnt_[p] + 12;
    inc_.assign(off_[n], kInvalidIndex);
    std::fill(cnt_.begin(), cnt_.end(), 0);
    for (Index id = 0; id < Q_.size(); ++id)
      for (const Index v : Q_[id]) inc_[off_[v] + cnt_[v]++] = id;
    target_.assign(n, 4.0);
    care_.assign(n, 1);
    for (Index p = 0; p < fixed_ && p < n; ++p) boundary_target(p);
    touched_.assign(n, 0);
    modified_at_.assign(n, 0);
    visited_.assign(n, 0);
  }

  std::size_t irregular() const {
    std::size_t count = 0;
    for (Index p = 0; p < P_.size(); ++p)
      if (alive(p) && care_[p] && static_cast<double>(cnt_[p]) != std::round(target_[p])) ++count;
    return count;
  }

  CleanupStats run(int max_passes) {
    CleanupStats stats;
    stats.irregular_before = irregular();
    std::vector<Candidate> cands;
    // Pass 0 gathers at every point; a later pass only where the previous one changed
    // something within kDirtyRings (see mark_dirty()).
    std::vector<std::uint8_t> dirty(P_.size(), 1);
    for (int pass = 0; pass < max_passes; ++pass) {
      bool any = false;
      const std::uint64_t operations_before = operations_;
      update_potential();
      for (Index p = 0; p < P_.size(); ++p) {
        if (!dirty[p] || !alive(p) || cost(p, cnt_[p]) == 0) continue;
        gather(p, cands);
        for (const Candidate& c : cands) {
          if (known_to_fail(c)) {
            ++stats.rejected;
            continue;
          }
          if (attempt(c)) {
            any = true;
            if (c.kind == Kind::Swap) ++stats.swaps;
            if (c.kind == Kind::Collapse) ++stats.collapses;
            if (c.kind == Kind::Doublet) ++stats.doublets;
            break;
          }
          ++stats.rejected;
          rejected_at_[key_of(c)] = operations_;
        }
      }
      stats.passes = pass + 1;
      if (!any) break;
      mark_dirty(operations_before, dirty);
    }
    final_smoothing();
    stats.irregular_after = irregular();
    compact();
    return stats;
  }

 private:
  /// dirty[p] = whether p is within kDirtyRings of a point that a move kept since
  /// `since` moved or gave other quads. Elsewhere a gather would find what it found in
  /// the pass before (the same candidates, each known_to_fail()), except for swaps that
  /// the drift of the potential turns favourable, which is weak beyond a few rings.
  void mark_dirty(std::uint64_t since, std::vector<std::uint8_t>& dirty) {
    std::fill(dirty.begin(), dirty.end(), 0);
    ++visit_stamp_;
    region_.clear();
    for (Index p = 0; p < P_.size(); ++p)
      if (modified_at_[p] > since) visited_[p] = visit_stamp_, region_.push_back(p);
    const std::size_t outer = grow_region(0, kDirtyRings);
    for (const Index v : region_) dirty[v] = 1;
    grow_region(outer, kPotentialRings - kDirtyRings);
    potential_points_.assign(region_.begin(), region_.end());
    std::sort(potential_points_.begin(), potential_points_.end());
  }

  /// Adds `rings` rings of points (those sharing a quad) around region_, whose points
  /// from `from` on are the outermost ring so far; every point in it carries
  /// visit_stamp_. Returns where the last ring added starts.
  std::size_t grow_region(std::size_t from, int rings) {
    for (int ring = 0; ring < rings; ++ring) {
      const std::size_t end = region_.size();
      for (std::size_t i = from; i < end; ++i)
        for (const Index id : quads_of(region_[i]))
          for (const Index v : Q_[id])
            if (visited_[v] != visit_stamp_) visited_[v] = visit_stamp_, region_.push_back(v);
      from = end;
    }
    return from;
  }

  // ---- connectivity
  bool alive(Index p) const { return cnt_[p] > 0; }
  std::span<const Index> quads_of(Index p) const { return {inc_.data() + off_[p], cnt_[p]}; }
  static int find(const std::array<Index, 4>& q, Index v) {
    for (int j = 0; j < 4; ++j)
      if (q[j] == v) return j;
    return -1;
  }
  static std::array<Index, 4> rotated(const std::array<Index, 4>& q, int start) {
    return {q[start], q[(start + 1) % 4], q[(start + 2) % 4], q[(start + 3) % 4]};
  }
  /// The quad holding the directed edge a -> b, or kInvalidIndex.
  Index quad_with_edge(Index a, Index b) const {
    for (const Index id : quads_of(a)) {
      const int j = find(Q_[id], a);
      if (Q_[id][(j + 1) % 4] == b) return id;
    }
    return kInvalidIndex;
  }
  bool adjacent(Index a, Index b) const {
    for (const Index id : quads_of(a)) {
      const int j = find(Q_[id], a);
      if (Q_[id][(j + 1) % 4] == b || Q_[id][(j + 3) % 4] == b) return true;
    }
    return false;
  }
  bool boundary_edge(Index a, Index b) const {
    return (quad_with_edge(a, b) == kInvalidIndex) != (quad_with_edge(b, a) == kInvalidIndex);
  }

  void boundary_target(Index p) {
    // The boundary edges at p (no quad on their other side): exactly one in and one out
    // for a simple boundary; anything else is left as it is (no cost).
    Index next = kInvalidIndex, prev = kInvalidIndex;
    int outs = 0, ins = 0;
    for (const Index id : quads_of(p)) {
      const int j = find(Q_[id], p);
      const Index a = Q_[id][(j + 1) % 4], b = Q_[id][(j + 3) % 4];
      if (quad_with_edge(a, p) == kInvalidIndex) {
        next = a;
        ++outs;
      }
      if (quad_with_edge(p, b) == kInvalidIndex) {
        prev = b;
        ++ins;
      }
    }
    if (outs != 1 || ins != 1) {
      care_[p] = 0;
      return;
    }
    const double theta = ccw_angle(P_[next] - P_[p], P_[prev] - P_[p]);
    target_[p] = std::max(1.0, theta / (0.5 * kPi));
  }

  double cost(Index p, Index count) const {
    if (!care_[p] || count == 0) return 0;
    const double e = static_cast<double>(count) - target_[p];
    return e * e;
  }
  double change(Index p, int by) const {
    return cost(p, static_cast<Index>(static_cast<int>(cnt_[p]) + by)) - cost(p, cnt_[p]);
  }

  bool can_set(Index id, const std::array<Index, 4>& v) const {
    if (v[0] == kInvalidIndex) return true;
    for (const Index w : v)
      if (find(Q_[id], w) < 0 && cnt_[w] >= off_[w + 1] - off_[w]) return false;
    return true;
  }
  void set_quad(Index id, const std::array<Index, 4>& v) {
    const auto old = Q_[id];
    if (old[0] != kInvalidIndex)
      for (const Index w : old) {
        Index* s = inc_.data() + off_[w];
        Index* e = s + cnt_[w];
        *std::find(s, e, id) = e[-1];
        --cnt_[w];
      }
    Q_[id] = v;
    if (v[0] != kInvalidIndex)
      for (const Index w : v) inc_[off_[w] + cnt_[w]++] = id;
    quad_log_.emplace_back(id, old);
  }
  void move(Index p, const Vec2& to) {
    point_log_.emplace_back(p, P_[p]);
    P_[p] = to;
  }
  void undo() {
    for (auto it = point_log_.rbegin(); it != point_log_.rend(); ++it) P_[it->first] = it->second;
    replay_.swap(quad_log_);
    for (auto it = replay_.rbegin(); it != replay_.rend(); ++it) set_quad(it->first, it->second);
    replay_.clear();
    point_log_.clear();
    quad_log_.clear();
  }

  // ---- candidates
  void gather(Index p, std::vector<Candidate>& out) {
    out.clear();
    auto add = [&](Kind kind, Index a, Index b, std::uint8_t dir) {
      Candidate c{0, 0, kind, a, b, dir};
      if (!evaluate(c) || c.delta > 1e-9) return;
      if (c.delta >= -1e-9) {
        // Neutral for the primary energy: only an edge rotation (a collapse would
        // coarsen the mesh for nothing), and only when it brings charges together.
        if (kind != Kind::Swap) return;
        c.delta = 0;
        if (!secondary(c) || c.delta2 > -1e-9) return;
      }
      out.push_back(c);
    };
    if (p >= fixed_ && cnt_[p] == 2) add(Kind::Doublet, p, 0, 0);
    for (const Index id : quads_of(p)) {
      add(Kind::Collapse, id, 0, 0);
      add(Kind::Collapse, id, 1, 0);
      const auto& q = Q_[id];
      for (int j = 0; j < 4; ++j)
        for (std::uint8_t dir = 0; dir < 2; ++dir) add(Kind::Swap, q[j], q[(j + 1) % 4], dir);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  /// A swap of the edge a -> b: the two quads around it form the hexagon
  /// h = (b, x, y, a, z, w); the new diagonal joins h1-h4 (dir 0) or h2-h5 (dir 1).
  struct SwapPlan {
    Index qa, qb;
    std::array<Index, 6> h;
    std::array<Index, 4> n0, n1;
    Index g0, g1;  // gain a quad
  };
  bool plan_swap(Index a, Index b, int dir, SwapPlan& s) const {
    s.qa = quad_with_edge(a, b);
    s.qb = quad_with_edge(b, a);
    if (s.qa == kInvalidIndex || s.qb == kInvalidIndex) return false;
    const auto A = rotated(Q_[s.qa], find(Q_[s.qa], a));  // a, b, x, y
    const auto B = rotated(Q_[s.qb], find(Q_[s.qb], b));  // b, a, z, w
    s.h = {b, A[2], A[3], a, B[2], B[3]};
    for (int i = 0; i < 6; ++i)
      for (int j = i + 1; j < 6; ++j)
        if (s.h[i] == s.h[j]) return false;
    const auto& h = s.h;
    if (dir == 0) {
      s.n0 = {h[1], h[2], h[3], h[4]};
      s.n1 = {h[4], h[5], h[0], h[1]};
      s.g0 = h[1];
      s.g1 = h[4];
    } else {
      s.n0 = {h[2], h[3], h[4], h[5]};
      s.n1 = {h[5], h[0], h[1], h[2]};
      s.g0 = h[2];
      s.g1 = h[5];
    }
    if (adjacent(s.g0, s.g1)) return false;
    // An interior point left with two quads is a doublet: never made on purpose.
    for (const Index v : {a, b})
      if (v >= fixed_ && cnt_[v] <= 3) return false;
    return true;
  }

  /// A collapse of quad id = (a, b, c, d) along the diagonal a-c (diag 0 from
  /// corner 0, 1 from corner 1): c's quads move to a (the kept point), b and d lose one.
  struct CollapsePlan {
    Index id, keep, gone, b, d;
  };
  bool plan_collapse(Index id, int diag, CollapsePlan& s) const {
    const auto q = rotated(Q_[id], diag);
    Index a = q[0], c = q[2];
    s.id = id;
    s.b = q[1];
    s.d = q[3];
    if (a < fixed_ && c < fixed_) return false;
    if (c < fixed_ || (a >= fixed_ && c < a)) std::swap(a, c);  // keep the boundary point, else the lower index
    s.keep = a;
    s.gone = c;
    for (const Index v : {s.b, s.d})
      if ((v >= fixed_ && cnt_[v] <= 3) || cnt_[v] <= 1) return false;
    // A kept boundary point must not lose its boundary edges to the other side.
    if (a < fixed_ && (boundary_edge(a, s.b) || boundary_edge(a, s.d))) return false;
    // Link condition: a and c share no neighbour but b and d, and no other quad.
    for (const Index r : quads_of(c)) {
      if (r == id) continue;
      const auto& o = Q_[r];
      const int j = find(o, c);
      if (find(o, a) >= 0) return false;
      for (const Index n : {o[(j + 1) % 4], o[(j + 3) % 4]})
        if (n != s.b && n != s.d && adjacent(a, n)) return false;
    }
    return true;
  }

  bool plan_doublet(Index p, std::array<Index, 2>& ids, std::array<Index, 4>& merged) const {
    if (p < fixed_ || cnt_[p] != 2) return false;
    ids = {quads_of(p)[0], quads_of(p)[1]};
    const auto q1 = rotated(Q_[ids[0]], find(Q_[ids[0]], p));  // p, a, x, b
    const auto q2 = rotated(Q_[ids[1]], find(Q_[ids[1]], p));  // p, b, y, a
    if (q1[1] != q2[3] || q1[3] != q2[1] || q1[2] == q2[2]) return false;
    merged = {q1[1], q1[2], q1[3], q2[2]};
    return true;
  }

  bool evaluate(Candidate& c) const {
    switch (c.kind) {
      case Kind::Doublet: {
        std::array<Index, 2> ids;
        std::array<Index, 4> m;
        if (!plan_doublet(c.a, ids, m)) return false;
        // Always wanted: a doublet's two quads are nearly flat.
        c.delta = -1e6;
        return true;
      }
      case Kind::Collapse: {
        CollapsePlan s;
        if (!plan_collapse(c.a, c.b, s)) return false;
        const Index merged = cnt_[s.keep] + cnt_[s.gone] - 2;
        c.delta = cost(s.keep, merged) - cost(s.keep, cnt_[s.keep]) - cost(s.gone, cnt_[s.gone]) + change(s.b, -1) +
                  change(s.d, -1);
        return true;
      }
      case Kind::Swap: {
        SwapPlan s;
        if (!plan_swap(c.a, c.b, c.dir, s)) return false;
        c.delta = change(c.a, -1) + change(c.b, -1) + change(s.g0, 1) + change(s.g1, 1);
        return true;
      }
    }
    return false;
  }

  // ---- geometry
  double quality(Index id) const {
    const auto& q = Q_[id];
    return scaled_jacobian(P_[q[0]], P_[q[1]], P_[q[2]], P_[q[3]]);
  }
  double quality_around(Index p, const Vec2& at) {
    const Vec2 keep = P_[p];
    P_[p] = at;
    double worst = 2;
    for (const Index id : quads_of(p)) worst = std::min(worst, quality(id));
    P_[p] = keep;
    return worst;
  }
  Vec2 laplacian_target(Index p) const {
    Vec2 sum(0, 0);
    for (const Index id : quads_of(p)) {
      const auto& q = Q_[id];
      const int j = find(q, p);
      sum += 0.5 * (P_[q[(j + 1) % 4]] + P_[q[(j + 3) % 4]]);
    }
    return sum / static_cast<double>(cnt_[p]);
  }
  /// Pattern search for the position of p maximising the worst quad around it.
  void optimize(Index p) {
    Vec2 at = P_[p];
    double now = quality_around(p, at);
    double len = 0;
    for (const Index id : quads_of(p)) {
      const auto& q = Q_[id];
      len += (P_[q[(find(q, p) + 1) % 4]] - at).norm();
    }
    double step = 0.2 * len / static_cast<double>(cnt_[p]);
    const double smallest = 0.01 * step;
    bool improved_any = false;
    for (int it = 0; it < 24 && step > smallest; ++it) {
      const bool improved = pattern_search_round(at, step, now, [&](const Vec2& to) { return quality_around(p, to); });
      if (!improved) step *= 0.5;
      improved_any |= improved;
    }
    if (improved_any) move(p, at);
  }

  /// Smooths the movable points `pts` (sorted) and returns the worst quad touching
  /// them or the changed quads.
  double settle(const std::vector<Index>& pts, const std::vector<Index>& changed, double floor) {
    for (int sweep = 0; sweep < 8; ++sweep)
      for (const Index p : pts) move(p, laplacian_target(p));
    auto worst = [&] {
      double w = 2;
      for (const Index id : changed)
        if (Q_[id][0] != kInvalidIndex) w = std::min(w, quality(id));
      for (const Index p : pts)
        for (const Index id : quads_of(p)) w = std::min(w, quality(id));
      return w;
    };
    double w = worst();
    // Optimise only when the Laplacian did not already reach what the caller needs: a
    // zone whose worst quad was poor before (at a jagged boundary) used to be
    // optimised at every one of its attempts.
    if (w >= floor) return w;  // floor = min(worst before, kFloor) <= 0.5
    for (int round = 0; round < 3; ++round) {
      for (const Index p : pts) {
        double around = 2;
        for (const Index id : quads_of(p)) around = std::min(around, quality(id));
        if (around < floor) optimize(p);  // only what holds the attempt back
      }
      w = worst();
    }
    return w;
  }

  /// The interior points of the given quads, sorted, unique, plus (ring) their
  /// interior edge neighbours.
  void collect(const std::vector<Index>& quads, bool ring, std::vector<Index>& pts) {
    pts.clear();
    for (const Index id : quads) {
      if (Q_[id][0] == kInvalidIndex) continue;
      for (const Index v : Q_[id])
        if (v >= fixed_) pts.push_back(v);
    }
    if (ring) {
      add_ring(pts);
    } else {
      std::sort(pts.begin(), pts.end());
      pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    }
  }

  /// Adds the free points of the quads around `pts`; sorted, without repeats.
  void add_ring(std::vector<Index>& pts) const {
    const std::size_t n = pts.size();
    for (std::size_t i = 0; i < n; ++i)
      for (const Index id : quads_of(pts[i]))
        for (const Index v : Q_[id])
          if (v >= fixed_) pts.push_back(v);
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  }

  struct Plan {
    SwapPlan sw{};
    CollapsePlan co{};
    std::array<Index, 2> ids{};
    std::array<Index, 4> merged{};
    std::array<Index, 4> moved{};  // the points whose quad count changes
    int moved_count = 0;
  };
  /// Plans c; changed_ gets the quads it will change.
  bool prepare(const Candidate& c, Plan& pl) {
    changed_.clear();
    switch (c.kind) {
      case Kind::Doublet:
        if (!plan_doublet(c.a, pl.ids, pl.merged)) return false;
        changed_ = {pl.ids[0], pl.ids[1]};
        pl.moved = {c.a, pl.merged[0], pl.merged[2], c.a};
        pl.moved_count = 3;
        return true;
      case Kind::Collapse:
        if (!plan_collapse(c.a, c.b, pl.co)) return false;
        changed_.assign(quads_of(pl.co.gone).begin(), quads_of(pl.co.gone).end());
        pl.moved = {pl.co.keep, pl.co.gone, pl.co.b, pl.co.d};
        pl.moved_count = 4;
        return true;
      case Kind::Swap:
        if (!plan_swap(c.a, c.b, c.dir, pl.sw)) return false;
        changed_ = {pl.sw.qa, pl.sw.qb};
        pl.moved = {c.a, c.b, pl.sw.g0, pl.sw.g1};
        pl.moved_count = 4;
        return true;
    }
    return false;
  }
  /// The topological change of a prepared plan (logged); changed_ gets the quads
  /// that are new or modified. False (nothing changed) when a slot would overflow.
  bool apply(const Candidate& c, Plan& pl) {
    switch (c.kind) {
      case Kind::Doublet:
        if (!can_set(pl.ids[0], pl.merged)) return false;
        set_quad(pl.ids[0], pl.merged);
        set_quad(pl.ids[1], {kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex});
        changed_ = {pl.ids[0]};
        return true;
      case Kind::Collapse: {
        const CollapsePlan& co = pl.co;
        for (const Index id : changed_) {
          if (id == co.id) continue;
          auto q = Q_[id];
          q[find(q, co.gone)] = co.keep;
          if (!can_set(id, q)) {
            undo();
            return false;
          }
          set_quad(id, q);
        }
        set_quad(co.id, {kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex});
        if (co.keep >= fixed_) move(co.keep, 0.5 * (P_[co.keep] + P_[co.gone]));
        changed_.assign(quads_of(co.keep).begin(), quads_of(co.keep).end());
        return true;
      }
      case Kind::Swap:
        if (!can_set(pl.sw.qa, pl.sw.n0) || !can_set(pl.sw.qb, pl.sw.n1)) return false;
        set_quad(pl.sw.qa, pl.sw.n0);
        set_quad(pl.sw.qb, pl.sw.n1);
        return true;
    }
    return false;
  }

  /// Secondary energy: the squared "charge" (sum of target minus quad count over the
  /// corners) of the quads around the given points. An isolated valence-3 point costs
  /// 4, a 3-5 pair sharing an edge 5 instead of 9: moves that leave the primary energy
  /// unchanged but lower this one bring singular points of opposite sign together,
  /// where a later move cancels them.
  double charge_energy(const std::array<Index, 4>& pts, int count) {
    e2q_.clear();
    for (int i = 0; i < count; ++i)
      for (const Index id : quads_of(pts[i])) e2q_.push_back(id);
    std::sort(e2q_.begin(), e2q_.end());
    e2q_.erase(std::unique(e2q_.begin(), e2q_.end()), e2q_.end());
    double e = 0;
    for (const Index id : e2q_) {
      double charge = 0;
      for (const Index v : Q_[id])
        if (care_[v]) charge += target_[v] - static_cast<double>(cnt_[v]);
      e += charge * charge;
    }
    return e;
  }
  double charge(Index p) const { return alive(p) && care_[p] ? target_[p] - static_cast<double>(cnt_[p]) : 0.0; }
  /// A screened potential of the charges (a few damped averaging sweeps over the edge
  /// graph): long-range guidance for the neutral moves, which lower the interaction
  /// energy sum(charge * potential) when a charge moves towards charges of the other
  /// sign. Recomputed once per pass, so a pass stays O(n).
  void update_potential() {
    const auto n = static_cast<Index>(P_.size());
    // The charges move little from one pass to the next: later passes start from the
    // previous potential with 10 sweeps instead of 30 from zero (those were 40% of the
    // whole pipeline on the Key at 500k quads; now paving takes 9.0 s instead of 13.5,
    // singular vertices 3,004 vs 3,007, average SJ 0.993 vs 0.995; 6 sweeps lowered
    // the annulus test's average below 0.9).
    const bool warm = potential_.size() == n;
    if (!warm) potential_.assign(n, 0.0);
    const int sweeps = warm ? kWarmFieldSweeps : kFieldSweeps;
    // Warm passes sweep only around the charges that the last pass moved
    // (potential_points_, kPotentialRings): the field is screened (decay kFieldDecay per
    // sweep), so a change reaches a few rings, and elsewhere the sweeps would leave it
    // as it was (nearly: the Key's and the Pipe's meshes of Table 3.4 are unchanged; the
    // Gulf at 20M quads has 1 singular vertex fewer). With the gathers only where
    // something changed (mark_dirty()), the Gulf's paving at 20M quads went from 33 to
    // 29 s on two threads; the sweeps were then still a quarter of the cleanup there
    // (its bands keep ~600 swaps per pass going), hence the flat lists below.
    const std::size_t count = warm ? potential_points_.size() : n;
    // The sweeps read the same edge graph each time: listed once, flat (the pairs of a
    // point's quads in their order, so the sums round as before).
    sweep_points_.clear();
    sweep_offsets_.assign(1, 0);
    sweep_pairs_.clear();
    for (std::size_t i = 0; i < count; ++i) {
      const Index p = warm ? potential_points_[i] : static_cast<Index>(i);
      if (!alive(p)) continue;
      sweep_points_.push_back(p);
      for (const Index id : quads_of(p)) {
        const auto& q = Q_[id];
        const int j = find(q, p);
        sweep_pairs_.push_back({q[(j + 1) % 4], q[(j + 3) % 4]});
      }
      sweep_offsets_.push_back(static_cast<Index>(sweep_pairs_.size()));
    }
    for (int sweep = 0; sweep < sweeps; ++sweep)
      for (std::size_t i = 0; i < sweep_points_.size(); ++i) {
        double sum = 0;
        for (Index k = sweep_offsets_[i]; k < sweep_offsets_[i + 1]; ++k)
          sum += potential_[sweep_pairs_[k][0]] + potential_[sweep_pairs_[k][1]];
        const Index p = sweep_points_[i];
        potential_[p] =
            charge(p) + kFieldDecay * sum / static_cast<int>(2 * (sweep_offsets_[i + 1] - sweep_offsets_[i]));
      }
  }

  /// The secondary energy change of c (topology only, undone at once).
  bool secondary(Candidate& c) {
    Plan pl;
    if (!prepare(c, pl)) return false;
    const double before = charge_energy(pl.moved, pl.moved_count);
    double field = 0;
    for (int i = 0; i < pl.moved_count; ++i) field -= charge(pl.moved[i]) * potential_[pl.moved[i]];
    if (!apply(c, pl)) return false;
    const double after = charge_energy(pl.moved, pl.moved_count);
    for (int i = 0; i < pl.moved_count; ++i) field += charge(pl.moved[i]) * potential_[pl.moved[i]];
    undo();
    c.delta2 = after - before + kField * field;
    return true;
  }

  /// Whether c was attempted and undone before and nothing it reads was changed by a kept
  /// move since. An attempt reads the points of the quads it changes (within a ring of its
  /// anchor points) and two rings around them (the smoothing's Laplacian targets, the quads
  /// whose worst it measures); so when no point within three rings of the anchors was moved,
  /// or had its quads changed, by a move kept since the rejection, the attempt sees what it
  /// saw and is skipped. Not quite bit for bit: an undo re-adds a point's quads at the end of
  /// its list, so moves tried and undone in between can reorder the sums over those lists,
  /// and a repeat then rounds differently (on the Key and the Pipe of Table 3.4 the meshes are
  /// the same; on the Gulf at 5M quads 16,901 singular vertices instead of 16,896, and the
  /// paving stage on 2 threads 8.9 s instead of 10.6). Restoring the lists' order on undo
  /// made it exact, but the meshes worse (Key 560 -> 588 singular vertices, Pipe 588 -> 633):
  /// those reordered repeats are second chances that sometimes pass.
  bool known_to_fail(const Candidate& c) {
    const auto it = rejected_at_.find(key_of(c));
    if (it == rejected_at_.end()) return false;
    const std::uint64_t since = it->second;
    ++visit_stamp_;
    region_.clear();
    const auto visit = [&](Index v) {
      if (visited_[v] != visit_stamp_) visited_[v] = visit_stamp_, region_.push_back(v);
    };
    switch (c.kind) {
      case Kind::Doublet:
        visit(c.a);
        break;
      case Kind::Collapse:
        if (Q_[c.a][0] == kInvalidIndex) return false;
        for (const Index v : Q_[c.a]) visit(v);
        break;
      case Kind::Swap:
        visit(c.a), visit(c.b);
        break;
    }
    grow_region(0, 3);
    for (const Index v : region_)
      if (modified_at_[v] > since) return false;
    return true;
  }

  bool attempt(const Candidate& c) {
    Plan pl;
    if (!prepare(c, pl)) return false;
    // The worst quad within reach of the smoothing before.
    collect(changed_, true, ring_);
    double before = 2;
    for (const Index id : changed_) before = std::min(before, quality(id));
    for (const Index p : ring_)
      for (const Index id : quads_of(p)) before = std::min(before, quality(id));
    const double floor = std::min(before, kFloor);
    if (!apply(c, pl)) return false;

    // Smoothing: first only the points of the changed quads, then one ring more.
    bool ok = false;
    for (const bool ring : {false, true}) {
      collect(changed_, ring, pts_);
      const double after = settle(pts_, changed_, floor);
      if (after > 0 && after >= floor) {
        ok = true;
        break;
      }
    }
    if (!ok) {
      undo();
      return false;
    }
    ++operations_;
    for (const auto& [p, old] : point_log_) touched_[p] = 1, modified_at_[p] = operations_;
    for (const auto& [id, old] : quad_log_)
      for (const auto& q : {old, Q_[id]})
        if (q[0] != kInvalidIndex)
          for (const Index v : q) touched_[v] = 1, modified_at_[v] = operations_;
    point_log_.clear();
    quad_log_.clear();
    return true;
  }

  /// Guarded Laplacian sweeps and a local optimisation of the worst quads over the
  /// touched points and a ring around them: the operations' smoothing only saw their
  /// own neighbourhood.
  void final_smoothing() {
    std::vector<Index> pts;
    for (Index p = fixed_; p < P_.size(); ++p)
      if (touched_[p] && alive(p)) pts.push_back(p);
    add_ring(pts);
    for (int sweep = 0; sweep < 20; ++sweep) {
      double moved = 0;
      for (const Index p : pts) {
        const Vec2 to = laplacian_target(p);
        const double after = quality_around(p, to);
        if (after > 0 && after >= std::min(quality_around(p, P_[p]), 0.5)) {
          moved = std::max(moved, (to - P_[p]).norm());
          P_[p] = to;
        }
      }
      if (moved < 1e-3 * size_) break;
    }
    for (int round = 0; round < 2; ++round)
      for (const Index p : pts) {
        double around = 2;
        for (const Index id : quads_of(p)) around = std::min(around, quality(id));
        if (around < 0.6) optimize(p);
      }
    point_log_.clear();
  }

  /// Drops removed quads and points; interior points keep their relative order.
  void compact() {
    std::vector<Index> remap(P_.size(), kInvalidIndex);
    Index next = 0;
    for (Index p = 0; p < P_.size(); ++p) {
      if (p >= fixed_ && !alive(p)) continue;
      remap[p] = next;
      P_[next++] = P_[p];
    }
    P_.resize(next);
    std::size_t out = 0;
    for (const auto& q : Q_)
      if (q[0] != kInvalidIndex) Q_[out++] = {remap[q[0]], remap[q[1]], remap[q[2]], remap[q[3]]};
    Q_.resize(out);
  }

  std::vector<Vec2>& P_;
  std::vector<std::array<Index, 4>>& Q_;
  const Index fixed_;
  const double size_;
  std::vector<Index> off_, cnt_, inc_;
  std::vector<double> target_, potential_;
  std::vector<std::uint8_t> care_, touched_;
  std::vector<std::pair<Index, std::array<Index, 4>>> quad_log_, replay_;
  std::vector<std::pair<Index, Vec2>> point_log_;
  std::vector<Index> changed_, ring_, pts_, e2q_;
  // Attempts undone, with the count of kept moves at the time; per point, the kept move
  // that last moved it or changed its quads (known_to_fail()).
  struct CandidateKey {
    Index a, b;
    std::uint8_t kind, dir;
    bool operator==(const CandidateKey&) const = default;
  };
  static CandidateKey key_of(const Candidate& c) { return {c.a, c.b, static_cast<std::uint8_t>(c.kind), c.dir}; }
  struct CandidateKeyHash {
    std::size_t operator()(const CandidateKey& k) const {
      return (static_cast<std::size_t>(k.a) * 0x9E3779B97F4A7C15ull) ^
             (static_cast<std::size_t>(k.b) * 0xC2B2AE3D27D4EB4Full) ^ (static_cast<std::size_t>(k.kind) << 1) ^ k.dir;
    }
  };
  std::unordered_map<CandidateKey, std::uint64_t, CandidateKeyHash> rejected_at_;
  std::uint64_t operations_ = 0;
  std::vector<std::uint64_t> modified_at_;
  std::vector<std::uint32_t> visited_;
  std::uint32_t visit_stamp_ = 0;
  std::vector<Index> region_;
  std::vector<Index> potential_points_;
  std::vector<Index> sweep_points_, sweep_offsets_;
  std::vector<std::array<Index, 2>> sweep_pairs_;
};

}  // namespace

CleanupStats clean_up_quads(std::vector<Vec2>& points, std::vector<std::array<Index, 4>>& quads, Index fixed_count,
                            double size, int max_passes) {
  if (max_passes < 1) throw InputError("clean_up_quads: max_passes must be at least 1");
  Cleaner cleaner(points, quads, fixed_count, size);
  return cleaner.run(max_passes);
}

}  // namespace structmesh::paving
