// Closing small loops with templates, and the fallback for a loop paving cannot close.
//
// Templates (dissertation §3.3.1: "the wave front propagates until the front has 6 or
// fewer vertices, by when a template is used"): every tiling of a loop of 4, 6 or 8
// nodes built from chords (with 0 or 1 interior node) and fans around one interior
// point is tried; its interior points are optimised and the valid tiling with the
// best minimum scaled Jacobian wins.
//
// Fallback: a constrained Delaunay triangulation of the loop (and the holes still open
// inside it) with interior points on a grid of the target size, whose triangles are
// paired into quads by a maximum-cardinality matching on the dual graph.
#include "quad2d/paving.hpp"

#include "structmesh/error.hpp"
#include "structmesh/triangulate.hpp"

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/max_cardinality_matching.hpp>

#include <algorithm>
#include <map>
#include <string>
#include <unordered_map>

namespace structmesh::paving {

namespace {

/// The fallback's quads avoid corners at three input points flatter than asin of this
/// short of a straight angle (177 degrees) when its matching can.
constexpr double kFixedCornerSine = 0.05;

struct Tiling {
  std::vector<std::array<int, 4>> quads;  // refs: < n boundary node, else n + extra index
  std::vector<Vec2> extra;
};

class TemplateSearch {
 public:
  explicit TemplateSearch(std::vector<Vec2> boundary) : boundary_(std::move(boundary)), n_(boundary_.size()) {}

  void enumerate(std::vector<std::vector<int>> pending, Tiling base, bool allow_chord_point) {
    if (pending.empty()) {
      tilings_.push_back(std::move(base));
      return;
    }
    const std::vector<int> poly = std::move(pending.back());
    pending.pop_back();
    const int m = static_cast<int>(poly.size());
    if (m == 4) {
      const bool poor =
          scaled_jacobian(at(base, poly[0]), at(base, poly[1]), at(base, poly[2]), at(base, poly[3])) < 0.3;
      if (poor && allow_chord_point) {
        // A badly shaped 4-loop: a ring of 4 quads around an inner quad.
        Tiling t = base;
        Vec2 c(0, 0);
        for (const int v : poly) c += 0.25 * at(base, v);
        const int id = static_cast<int>(n_ + t.extra.size());
        for (const int v : poly) t.extra.push_back(0.5 * (at(base, v) + c));
        for (int k = 0; k < 4; ++k) t.quads.push_back({poly[k], poly[(k + 1) % 4], id + (k + 1) % 4, id + k});
        t.quads.push_back({id, id + 1, id + 2, id + 3});
        enumerate(pending, std::move(t), allow_chord_point);
      }
      base.quads.push_back({poly[0], poly[1], poly[2], poly[3]});
      enumerate(std::move(pending), std::move(base), allow_chord_point);
      return;
    }
    // Chords without interior nodes: both sides even, each at least 4 nodes.
    for (int i = 0; i < m; ++i) {
      for (int j = i + 3; j <= i + m - 3 && j < m; j += 2) {
        std::vector<int> a(poly.begin() + i, poly.begin() + j + 1);
        std::vector<int> b(poly.begin() + j, poly.end());
        b.insert(b.end(), poly.begin(), poly.begin() + i + 1);
        auto next = pending;
        next.push_back(std::move(a));
        next.push_back(std::move(b));
        enumerate(std::move(next), base, allow_chord_point);
      }
    }
    // Fans: one interior point joined to every other node.
    if (m == 6 || m == 8) {
      Vec2 c(0, 0);
      for (const int v : poly) c += at(base, v);
      c /= m;
      for (int parity = 0; parity < 2; ++parity) {
        Tiling t = base;
        const int id = static_cast<int>(n_ + t.extra.size());
        t.extra.push_back(c);
        for (int k = parity; k < m; k += 2) t.quads.push_back({poly[(k + m - 1) % m], poly[k], poly[(k + 1) % m], id});
        enumerate(pending, std::move(t), allow_chord_point);
      }
    }
    // Hexagon with two interior points of valence 3 (an edge between them, each joined
    // to two boundary nodes): the tiling for hexagons with a reflex node.
    if (m == 6 && allow_chord_point) {
      Vec2 c(0, 0);
      for (const int v : poly) c += at(base, v) / 6.0;
      for (int s = 0; s < 3; ++s) {
        Tiling t = base;
        const int c1 = static_cast<int>(n_ + t.extra.size()), c2 = c1 + 1;
        auto p = [&](int k) { return poly[(s + k) % 6]; };
        t.extra.push_back(0.6 * c + 0.4 * at(base, p(1)));
        t.extra.push_back(0.6 * c + 0.4 * at(base, p(4)));
        t.quads.push_back({p(0), p(1), p(2), c1});
        t.quads.push_back({p(2), p(3), c2, c1});
        t.quads.push_back({p(3), p(4), p(5), c2});
        t.quads.push_back({p(5), p(0), c1, c2});
        enumerate(pending, std::move(t), allow_chord_point);
      }
    }
    // Chords with one interior node splitting 8 into 6 + 6.
    if (m == 8 && allow_chord_point) {
      for (int i = 0; i < 4; ++i) {
        const int j = i + 4;
        Tiling t = base;
        const int id = static_cast<int>(n_ + t.extra.size());
        t.extra.push_back(0.5 * (at(base, poly[i]) + at(base, poly[j])));
        std::vector<int> a(poly.begin() + i, poly.begin() + j + 1);
        a.push_back(id);
        std::vector<int> b(poly.begin() + j, poly.end());
        b.insert(b.end(), poly.begin(), poly.begin() + i + 1);
        b.push_back(id);
        auto next = pending;
        next.push_back(a);
        next.push_back(b);
        enumerate(std::move(next), std::move(t), false);
      }
    }
  }

  /// Scores every tiling after a quick placement of its interior points, optimises
  /// the most promising ones fully, and returns the best valid one.
  const Tiling* best(double polygon_area, double& best_min) {
    // A good tiling without interior points (no new singular vertex) ends the search.
    {
      const Tiling* plain = nullptr;
      double plain_score = -1e300, plain_min = -1;
      for (const Tiling& t : tilings_) {
        if (!t.extra.empty()) continue;
        double worst = 0;
        const double sc = score(t, polygon_area, worst);
        if (sc > plain_score) {
          plain_score = sc;
          plain_min = worst;
          plain = &t;
        }
      }
      if (plain != nullptr && plain_min >= 0.7) {
        best_min = plain_min;
        return plain;
      }
    }
    std::vector<std::pair<double, std::size_t>> quick;
    for (std::size_t k = 0; k < tilings_.size(); ++k) {
      Tiling& t = tilings_[k];
      for (int sweep = 0; sweep < 2 && !t.extra.empty(); ++sweep)
        for (std::size_t e = 0; e < t.extra.size(); ++e) optimize(t, static_cast<int>(n_ + e), 0);
      double worst = 0;
      quick.emplace_back(score(t, polygon_area, worst), k);
    }
    std::sort(quick.begin(), quick.end(), [](const auto& x, const auto& y) {
      return x.first > y.first || (x.first == y.first && x.second < y.second);
    });
    const Tiling* winner = nullptr;
    double best_score = -1e300;
    best_min = -1;
    for (std::size_t r = 0; r < quick.size() && r < 2; ++r) {
      Tiling& t = tilings_[quick[r].second];
      for (int sweep = 0; sweep < 4 && !t.extra.empty(); ++sweep)
        for (std::size_t e = 0; e < t.extra.size(); ++e) optimize(t, static_cast<int>(n_ + e), 12);
      double worst = 0;
      const double s = score(t, polygon_area, worst);
      if (s > best_score && worst > 0.02) {
        best_score = s;
        best_min = worst;
        winner = &t;
      }
    }
    return winner;
  }

  const Vec2& at(const Tiling& t, int ref) const {
    return ref < static_cast<int>(n_) ? boundary_[ref] : t.extra[ref - n_];
  }

 private:
  /// The worst scaled Jacobian of the quads `incident` (indices into t.quads, each with
  /// `ref` at one of its corners) with `ref` at p.
  double quality_around(const Tiling& t, const std::vector<std::pair<int, int>>& incident, const Vec2& p) const {
    double worst = 1;
    for (const auto& [quad, corner] : incident) {
      const auto& q = t.quads[static_cast<std::size_t>(quad)];
      std::array<Vec2, 4> c;
      for (int j = 0; j < 4; ++j) c[j] = j == corner ? p : at(t, q[j]);
      worst = std::min(worst, scaled_jacobian(c[0], c[1], c[2], c[3]));
    }
    return worst;
  }
  /// min + half the mean scaled Jacobian, less a little per interior point (fewer
  /// singular vertices at equal quality); -1e300 when the tiling is not valid.
  double score(const Tiling& t, double polygon_area, double& worst) const {
    double area = 0, total = 0;
    worst = 1;
    for (const auto& q : t.quads) {
      const double sj = scaled_jacobian(at(t, q[0]), at(t, q[1]), at(t, q[2]), at(t, q[3]));
      worst = std::min(worst, sj);
      total += sj;
      area += quad_area(at(t, q[0]), at(t, q[1]), at(t, q[2]), at(t, q[3]));
    }
    if (worst <= 0.02 || std::abs(area - polygon_area) > 1e-9 * std::abs(polygon_area) + 1e-300) return -1e300;
    return worst + 0.5 * total / static_cast<double>(t.quads.size()) - 0.2 * static_cast<double>(t.extra.size());
  }
  void optimize(Tiling& t, int ref, int iterations) {
    Vec2& p = t.extra[ref - n_];
    // The quads around ref, in tiling order (a point is at most one corner of a quad),
    // so every trial position below evaluates only those.
    std::vector<std::pair<int, int>>& incident = incident_;
    incident.clear();
    // Start from the mean of the ideal parallelogram points of the quads around it.
    Vec2 ideal(0, 0);
    int count = 0;
    double len = 0;
    for (std::size_t k = 0; k < t.quads.size(); ++k) {
      const auto& q = t.quads[k];
      for (int j = 0; j < 4; ++j) {
        if (q[j] != ref) continue;
        const Vec2 a = at(t, q[(j + 1) % 4]), b = at(t, q[(j + 2) % 4]), c = at(t, q[(j + 3) % 4]);
        ideal += a + c - b;
        len += (a - c).norm();
        ++count;
        incident.emplace_back(static_cast<int>(k), j);
      }
    }
    if (count == 0) return;
    ideal /= count;
    double now = quality_around(t, incident, p);
    const double cand = quality_around(t, incident, ideal);
    if (cand > now) {
      p = ideal;
      now = cand;
    }
    double step = 0.1 * len / count;
    for (int it = 0; it < iterations; ++it) {
      bool improved = false;
      for (const Vec2& d : {Vec2(1, 0), Vec2(-1, 0), Vec2(0, 1), Vec2(0, -1)}) {
        const double q = quality_around(t, incident, p + step * d);
        if (q > now) {
          now = q;
          p += step * d;
          improved = true;
        }
      }
      if (!improved) step *= 0.5;
    }
  }

  std::vector<Vec2> boundary_;
  std::size_t n_;
  std::vector<Tiling> tilings_;
  std::vector<std::pair<int, int>> incident_;  // optimize()'s scratch: (quad, corner) around the point
};

bool inside_ring(const std::vector<Vec2>& ring, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Vec2 &a = ring[i], &b = ring[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

}  // namespace

bool Paver::hole_inside(Index hole, Index loop, const std::vector<Vec2>& ring) const {
  // Test a point of the hole's loop that is not on `loop` (they may touch at a point).
  const Index head = loops_[hole].head;
  Index v = head;
  do {
    const Index p = node_point_[v];
    bool on_loop = false;
    for (Index u = loops_[loop].head;;) {
      on_loop |= node_point_[u] == p;
      u = node_next_[u];
      if (u == loops_[loop].head || on_loop) break;
    }
    if (!on_loop) return inside_ring(ring, pos(v));
    v = node_next_[v];
  } while (v != head);
  return false;
}

bool Paver::contains_open_hole(Index loop) const {
  std::vector<Vec2> ring;
  for (const Index l : negative_loops_) {
    if (l == loop || !loops_[l].alive || loops_[l].area >= 0) continue;
    if (ring.empty())
      for (const Index v : loop_nodes(loop)) ring.push_back(pos(v));
    if (hole_inside(l, loop, ring)) return true;
  }
  return false;
}

bool Paver::close_with_template(Index loop) {
  const std::vector<Index> nodes = loop_nodes(loop);
  const std::size_t n = nodes.size();
  if (n != 4 && n != 6 && n != 8) return false;
  std::vector<Vec2> boundary(n);
  std::vector<Index> pts(n);
  for (std::size_t i = 0; i < n; ++i) {
    boundary[i] = pos(nodes[i]);
    pts[i] = node_point_[nodes[i]];
  }
  {
    std::vector<Index> sorted = pts;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
  }
  TemplateSearch search(boundary);
  std::vector<int> poly(n);
  for (std::size_t i = 0; i < n; ++i) poly[i] = static_cast<int>(i);
  // Chords and fans first; chords through an interior point only when those are poor.
  search.enumerate({poly}, {}, false);
  double worst = 0;
  const Tiling* t = search.best(loops_[loop].area, worst);
  if (n >= 4 && (t == nullptr || worst < 0.75)) {
    TemplateSearch wider(boundary);
    wider.enumerate({poly}, {}, true);
    double wider_worst = 0;
    const Tiling* w = wider.best(loops_[loop].area, wider_worst);
    if (w != nullptr && (t == nullptr || wider_worst > worst)) {
      search = std::move(wider);
      t = search.best(loops_[loop].area, worst);
    }
  }
  if (t == nullptr) return false;
  {
    // No interior point of valence below 3 (a doublet).
    std::vector<int> valence(n + t->extra.size(), 0);
    for (const auto& q : t->quads)
      for (const int v : q) ++valence[v];
    for (std::size_t i = 0; i < n; ++i)
      if (makes_doublet(pts[i], valence[i])) return false;
    for (std::size_t e = 0; e < t->extra.size(); ++e)
      if (valence[n + e] < 3) return false;
  }
  std::vector<Index> extra(t->extra.size());
  for (std::size_t e = 0; e < extra.size(); ++e) extra[e] = mesh_.add_point(t->extra[e]);
  for (const auto& q : t->quads) {
    std::array<Index, 4> mq{};
    for (int j = 0; j < 4; ++j) mq[j] = q[j] < static_cast<int>(n) ? pts[q[j]] : extra[q[j] - n];
    emit_quad(mq);
  }
  for (const Index v : nodes) kill_node(v);
  for (const Index e : extra) released_.push_back(e);
  loops_[loop].alive = false;
  loops_[loop].size = 0;
  ++stats_.templates;
  return true;
}

bool Paver::close_with_ring(Index loop) {
  if (contains_open_hole(loop)) return false;
  const std::vector<Index> nodes = loop_nodes(loop);
  const std::size_t n = nodes.size();
  Vec2 c(0, 0);
  for (const Index v : nodes) c += pos(v) / static_cast<double>(n);
  double r_min = 1e300;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = pos(nodes[i]) - c, b = pos(nodes[(i + 1) % n]) - c;
    if (!(cross(a, b) > 1e-9 * a.norm() * b.norm())) return false;  // not star-shaped from c
    r_min = std::min(r_min, a.norm());
  }
  std::vector<Vec2> inner(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = pos(nodes[i]) - c;
    inner[i] = n <= 8 ? c + 0.5 * r_min * a.normalized() : c + 0.6 * a;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    if (scaled_jacobian(pos(nodes[i]), pos(nodes[j]), inner[j], inner[i]) < 0.05) return false;
  }
  std::vector<Index> pts(n);
  for (std::size_t i = 0; i < n; ++i) pts[i] = mesh_.add_point(inner[i]);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    emit_quad({node_point_[nodes[i]], node_point_[nodes[j]], pts[j], pts[i]});
  }
  for (const Index v : nodes) kill_node(v);
  loops_[loop].alive = false;
  loops_[loop].size = 0;
  add_loop(pts, signed_area(inner));
  ++stats_.templates;
  return true;
}

void Paver::fallback(Index loop) {
  const std::string where = "paving: a front loop of " + std::to_string(loops_[loop].size) + " nodes near (" +
                            std::to_string(pos(loops_[loop].head).x()) + ", " +
                            std::to_string(pos(loops_[loop].head).y()) + ")";
  // The loop may pass a point more than once: both sides of a chord that joined a
  // hole's front (a slit), or a pinch where the front touched itself. Cut it at every
  // repeated point into simple cycles (a stack walk, O(n)): a cycle of two nodes is
  // a slit edge with unmeshed space on both sides (dropped: it need not be an edge of
  // the closure), a negative one a joined hole, a positive one a region to close.
  const std::vector<Index> nodes = loop_nodes(loop);
  std::vector<std::vector<Index>> cycles;
  {
    std::vector<Index> stack;
    std::unordered_map<Index, std::size_t> at;  // point -> position in stack
    for (const Index v : nodes) {
      const auto [it, fresh] = at.emplace(node_point_[v], stack.size());
      if (fresh) {
        stack.push_back(v);
        continue;
      }
      const std::size_t k = it->second;
      cycles.emplace_back(stack.begin() + static_cast<std::ptrdiff_t>(k), stack.end());
      for (std::size_t t = k + 1; t < stack.size(); ++t) at.erase(node_point_[stack[t]]);
      stack.resize(k + 1);
    }
    cycles.push_back(std::move(stack));
  }
  std::vector<std::vector<Vec2>> outers;
  std::vector<std::vector<Index>> outer_points;
  std::vector<std::pair<std::vector<Vec2>, std::vector<Index>>> holes;
  for (const auto& cycle : cycles) {
    if (cycle.size() < 3) continue;
    std::vector<Vec2> ring;
    std::vector<Index> pts;
    for (const Index v : cycle) {
      ring.push_back(pos(v));
      pts.push_back(node_point_[v]);
    }
    if (signed_area(ring) > 0) {
      outers.push_back(std::move(ring));
      outer_points.push_back(std::move(pts));
    } else {
      holes.emplace_back(std::move(ring), std::move(pts));
    }
  }
  if (outers.empty()) throw Error(where + " could not be closed: it bounds no region");
  // The open holes inside the loop.
  std::vector<Index> loop_ids{loop};
  {
    std::vector<Vec2> ring;
    for (const Index v : nodes) ring.push_back(pos(v));
    for (const Index l : negative_loops_) {
      if (l == loop || !loops_[l].alive || loops_[l].area >= 0 || !hole_inside(l, loop, ring)) continue;
      loop_ids.push_back(l);
      std::vector<Vec2> hole;
      std::vector<Index> pts;
      for (const Index v : loop_nodes(l)) {
        hole.push_back(pos(v));
        pts.push_back(node_point_[v]);
      }
      holes.emplace_back(std::move(hole), std::move(pts));
    }
  }
  // Every hole goes to the smallest region around it (tested at its middle-most
  // point that is not on the region's loop).
  std::vector<Polygon2> regions(outers.size());
  std::vector<std::vector<Index>> point_of(outers.size());
  for (std::size_t c = 0; c < outers.size(); ++c) {
    regions[c].add_ring(outers[c]);
    point_of[c] = outer_points[c];
  }
  for (auto& [ring, pts] : holes) {
    std::size_t best = outers.size();
    for (std::size_t c = 0; c < outers.size(); ++c) {
      bool inside = false;
      for (std::size_t i = 0; i < ring.size(); ++i) {
        if (std::find(outer_points[c].begin(), outer_points[c].end(), pts[i]) != outer_points[c].end()) continue;
        inside = inside_ring(outers[c], ring[i]);
        break;
      }
      if (inside && (best == outers.size() || signed_area(outers[c]) < signed_area(outers[best]))) best = c;
    }
    if (best == outers.size()) throw Error(where + " could not be closed: a hole inside it lies in none of its parts");
    regions[best].add_ring(ring);
    point_of[best].insert(point_of[best].end(), pts.begin(), pts.end());
  }
  for (std::size_t c = 0; c < regions.size(); ++c) close_region(regions[c], point_of[c], where);
  for (const Index l : loop_ids) {
    for (const Index v : loop_nodes(l)) kill_node(v);
    loops_[l].alive = false;
    loops_[l].size = 0;
  }
  ++stats_.fallback_loops;
}

void Paver::close_region(const Polygon2& region, const std::vector<Index>& point_of, const std::string& where) {
  const auto boundary_count = static_cast<Index>(point_of.size());
  // Pairs the triangles into quads by a maximum-cardinality matching on the dual graph
  // (triangles sharing an edge that is not on the loop), removes the doublets it
  // leaves, and checks the quads: none folded, none with a reflex corner that
  // smoothing cannot repair (the corner and both its neighbours input points).
  std::vector<std::array<Index, 4>> quads;  // in triangulation numbering
  auto fixed = [&](Index v) { return v < boundary_count && point_of[v] < mesh_.fixed_count; };
  // A corner at three input points keeps its angle whatever smoothing does: it must be
  // convex, and (min_sine > 0) not within asin(min_sine) of a straight angle. At 0 a
  // corner on a straight run of three samples passed by rounding: the Gulf's worst quads
  // at 20M quads (scaled Jacobian 1e-13) were such fallback quads of four boundary
  // samples. A sharp corner there is the loop's own (a tip no quad can do better at).
  const auto corner_ok = [](const Vec2& a, const Vec2& b, double min_sine) {
    return cross(a, b) > (a.dot(b) < 0 ? min_sine * a.norm() * b.norm() : 0.0);
  };
  auto repairable = [&](const std::vector<Vec2>& P, const std::array<Index, 4>& q, double min_sine) {
    for (int j = 0; j < 4; ++j) {
      const Index u = q[(j + 3) % 4], v = q[j], w = q[(j + 1) % 4];
      if (fixed(u) && fixed(v) && fixed(w) && !corner_ok(P[w] - P[v], P[u] - P[v], min_sine)) return false;
    }
    return true;
  };
  auto pair_up = [&](RegionTriangulation& tri, double min_sine) {
    const std::size_t t = tri.triangles.size();
    std::map<std::pair<Index, Index>, Index> edge_owner;
    boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS> graph(t);
    for (Index f = 0; f < t; ++f) {
      for (int j = 0; j < 3; ++j) {
        Index a = tri.triangles[f][j], b = tri.triangles[f][(j + 1) % 3];
        if (a > b) std::swap(a, b);
        const auto [it, fresh] = edge_owner.emplace(std::make_pair(a, b), f);
        if (fresh) continue;
        // Pairs that would make a dart of input points (a reflex corner at three
        // points nothing moves) are left out, so the matching routes around them.
        const auto& t1 = tri.triangles[it->second];
        const auto& t2 = tri.triangles[f];
        const auto third = [&](const std::array<Index, 3>& t) {
          for (const Index v : t)
            if (v != a && v != b) return v;
          return a;
        };
        std::array<Index, 4> q{};
        for (int k = 0; k < 3; ++k)
          if (t1[k] != a && t1[k] != b) q = {t1[k], t1[(k + 1) % 3], third(t2), t1[(k + 2) % 3]};
        if (!repairable(tri.points, q, min_sine)) continue;
        boost::add_edge(it->second, f, graph);
      }
    }
    std::vector<boost::graph_traits<decltype(graph)>::vertex_descriptor> match(t);
    boost::edmonds_maximum_cardinality_matching(graph, &match[0]);
    const auto null = boost::graph_traits<decltype(graph)>::null_vertex();
    if (std::any_of(match.begin(), match.end(), [null](auto v) { return v == null; })) return false;
    quads.clear();
    for (Index f = 0; f < t; ++f) {
      const auto g = static_cast<Index>(match[f]);
      if (g < f) continue;
      const auto& t1 = tri.triangles[f];
      const auto& t2 = tri.triangles[g];
      // t1 = (x, y, z) with the shared edge x -> y; t2 holds y -> x and its third node w.
      for (int j = 0; j < 3; ++j) {
        const Index x = t1[j], y = t1[(j + 1) % 3], z = t1[(j + 2) % 3];
        for (int k = 0; k < 3; ++k)
          if (t2[k] == y && t2[(k + 1) % 3] == x) quads.push_back({x, t2[(k + 2) % 3], y, z});
      }
    }
    // Doublets: an interior point of two quads (p, a, x, b) and (p, b, y, a) goes, and
    // the two quads become (a, x, b, y).
    for (bool again = true; again;) {
      again = false;
      std::vector<std::vector<std::size_t>> around(tri.points.size());
      for (std::size_t q = 0; q < quads.size(); ++q)
        for (const Index v : quads[q]) around[v].push_back(q);
      for (Index p = boundary_count; p < tri.points.size() && !again; ++p) {
        if (around[p].size() != 2) continue;
        auto rotate_to = [&](std::array<Index, 4> q) {
          while (q[0] != p) std::rotate(q.begin(), q.begin() + 1, q.end());
          return q;
        };
        const auto q1 = rotate_to(quads[around[p][0]]), q2 = rotate_to(quads[around[p][1]]);
        if (q1[1] != q2[3] || q1[3] != q2[1]) continue;
        const std::array<Index, 4> merged{q1[1], q1[2], q1[3], q2[2]};
        quads[around[p][0]] = merged;
        quads.erase(quads.begin() + static_cast<std::ptrdiff_t>(around[p][1]));
        again = true;
        if (repairable(tri.points, merged, min_sine)) continue;
        // A dart of input points (a reflex corner nothing can move), or a corner of them
        // too flat: a ring of four quads around an inner quad instead, the inner points
        // halfway to the middle of its inner diagonal (from that corner).
        int reflex = 0;
        for (int j = 0; j < 4; ++j) {
          const Vec2 &u = tri.points[merged[(j + 3) % 4]], &v = tri.points[merged[j]],
                     &w = tri.points[merged[(j + 1) % 4]];
          if (!corner_ok(w - v, u - v, min_sine)) reflex = j;
        }
        const Vec2 mid = 0.5 * (tri.points[merged[reflex]] + tri.points[merged[(reflex + 2) % 4]]);
        const auto first = static_cast<Index>(tri.points.size());
        for (int j = 0; j < 4; ++j) tri.points.push_back(0.5 * (tri.points[merged[j]] + mid));
        quads.erase(std::find(quads.begin(), quads.end(), merged));
        for (Index j = 0; j < 4; ++j) quads.push_back({merged[j], merged[(j + 1) % 4], first + (j + 1) % 4, first + j});
        quads.push_back({first, first + 1, first + 2, first + 3});
      }
    }
    const auto& P = tri.points;
    for (const auto& q : quads) {
      if (!(quad_area(P[q[0]], P[q[1]], P[q[2]], P[q[3]]) > 0)) return false;
      if (!repairable(P, q, min_sine)) return false;
    }
    return true;
  };

  std::vector<std::array<Index, 4>> best;
  std::vector<Vec2> best_points;
  bool done = false;
  // Corners at input points of at least kFixedCornerSine with any of the
  // triangulations, else any convex ones.
  for (const double min_sine : {kFixedCornerSine, 0.0}) {
    if (done) break;
    for (const double factor : {1.0, 0.75, 0.55, 0.4, 0.3, 1.5, 0.0}) {
      RegionTriangulation tri;
      try {
        // A loop may touch a hole's loop (or itself) at a point: one vertex there.
        tri = triangulate_region(region, {.steiner_spacing = factor * size_, .merge_repeated_points = true});
      } catch (const Error& e) {
        throw Error(where + " could not be closed: its fallback triangulation failed (" + e.what() + ")");
      }
      if (tri.boundary_edges.size() != region.points.size()) continue;
      if (tri.triangles.size() % 2 != 0) continue;
      if (!pair_up(tri, min_sine)) {
        // No perfect matching (narrow regions where no grid point fits: the dual is a
        // tree with branches of odd size), or quads no smoothing repairs: every triangle
        // is split into three at its centroid. Then a perfect matching always exists:
        // the dual is connected with an even number t of nodes, so it has a subgraph in
        // which every node has odd degree (a T-join, T = all nodes); a triangle of
        // degree 1 or 3 there matches that many of its thirds across its edges and
        // pairs the others inside it (a doublet at the centroid, removed). Every quad
        // then has a centroid to smooth.
        std::vector<std::array<Index, 3>> thirds;
        thirds.reserve(3 * tri.triangles.size());
        for (const auto& f : tri.triangles) {
          const auto g = static_cast<Index>(tri.points.size());
          tri.points.push_back((tri.points[f[0]] + tri.points[f[1]] + tri.points[f[2]]) / 3.0);
          for (int j = 0; j < 3; ++j) thirds.push_back({f[j], f[(j + 1) % 3], g});
        }
        tri.triangles = std::move(thirds);
        if (!pair_up(tri, min_sine)) continue;
      }
      // A free loop point must not end as a doublet (counted per mesh point: a point
      // the region passes twice is one triangulation vertex).
      std::map<Index, int> added;
      for (Index i = 0; i < boundary_count; ++i) added.emplace(point_of[i], 0);
      for (const auto& q : quads)
        for (const Index v : q)
          if (v < boundary_count) ++added[point_of[v]];
      bool doublet = false;
      for (const auto& [point, count] : added) doublet |= makes_doublet(point, count);
      if (!done || !doublet) {
        best = quads;
        best_points = tri.points;
        done = true;
      }
      if (!doublet) break;  // else keep looking; the doublets are collapsed at the end
    }
  }
  if (!done) throw Error(where + " could not be closed: no perfect matching of its triangulation");
  quads = std::move(best);
  std::vector<Index> mesh_id(best_points.size(), kInvalidIndex);
  for (Index i = 0; i < boundary_count; ++i) mesh_id[i] = point_of[i];
  for (const auto& q : quads) {
    std::array<Index, 4> mq{};
    for (int j = 0; j < 4; ++j) {
      if (mesh_id[q[j]] == kInvalidIndex) {
        mesh_id[q[j]] = mesh_.add_point(best_points[q[j]]);
        released_.push_back(mesh_id[q[j]]);
      }
      mq[j] = mesh_id[q[j]];
    }
    emit_quad(mq);
  }
}

}  // namespace structmesh::paving
