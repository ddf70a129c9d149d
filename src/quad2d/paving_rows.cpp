// Rows, seams and chord splits of the paving mesher (Blacker & Stephenson 1991).
//
// A row classifies every front node by its interior angle (end ~90°, side ~180°,
// corner ~270°, reversal ~360°), plans the new nodes of the next layer, then glues the
// layer quad by quad with try_quad(), so that a quad that does not fit is skipped and
// the front stays valid. Tucks (a side node treated as an end) and wedges (a side node
// treated as a corner) keep the layer's edge lengths near the target size where the
// front shrinks or grows. Chords split a loop where two parts of the front face each
// other within about two sizes, or join a hole's front to the front around it.
#include "quad2d/paving.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

namespace structmesh::paving {

namespace {

enum class NodeType : std::uint8_t { End, Side, Corner, Reversal, Tuck, Wedge };

constexpr double kEndAngle = 0.75 * kPi;       // 135°
constexpr double kCornerAngle = 1.3 * kPi;     // 234°
constexpr double kReversalAngle = 1.78 * kPi;  // 320°

Vec2 rotate(const Vec2& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

}  // namespace

double Paver::local_size(Index node) const {
  const double l = 0.5 * ((pos(node_next_[node]) - pos(node)).norm() + (pos(node_prev_[node]) - pos(node)).norm());
  return 0.2 * l + 0.8 * size_;
}

double Paver::ray_gap(Index node, const Vec2& dir, double range) {
  const Vec2 p = pos(node);
  const Vec2 end = p + range * dir;
  const Index pp = node_point_[node];
  double best = range;
  grid_.visit(
      p.cwiseMin(end), p.cwiseMax(end), [this](Index n, Index m) { return edge_live(n, m); },
      [&](Index n, Index m) {
        const Index u = node_point_[n], v = node_point_[m];
        if (u == pp || v == pp) return true;
        const Vec2& a = mesh_.points[u];
        const Vec2 e = mesh_.points[v] - a;
        const double den = cross(dir, e);
        if (std::abs(den) < 1e-300) return true;
        const Vec2 w = a - p;
        const double t = cross(w, e) / den, s = cross(w, dir) / den;
        if (t > 0 && s >= 0 && s <= 1) best = std::min(best, t);
        return true;
      });
  return best;
}

bool Paver::row(Index loop) {
  const std::vector<Index> all = loop_nodes(loop);
  const std::size_t n = all.size();
  if (n < 4) return false;
  // Start at an end node so that the layer closes where it turns.
  std::size_t start = 0;
  std::vector<double> angle(n);
  for (std::size_t i = 0; i < n; ++i) angle[i] = interior_angle(all[i]);
  for (std::size_t i = 0; i < n; ++i)
    if (angle[i] < kEndAngle) {
      start = i;
      break;
    }
  std::vector<Index> nodes(n);
  std::vector<double> alpha(n);
  for (std::size_t i = 0; i < n; ++i) {
    nodes[i] = all[(start + i) % n];
    alpha[i] = angle[(start + i) % n];
  }
  auto nx = [n](std::size_t i) { return (i + 1) % n; };
  auto pv = [n](std::size_t i) { return (i + n - 1) % n; };

  std::vector<NodeType> type(n);
  std::vector<double> d(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = alpha[i];
    type[i] = a < kEndAngle        ? NodeType::End
              : a < kCornerAngle   ? NodeType::Side
              : a < kReversalAngle ? NodeType::Corner
                                   : NodeType::Reversal;
    d[i] = local_size(nodes[i]);
  }
  // Two ends in a row would both consume the edge between them: keep the sharper.
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = nx(i);
    if (type[i] == NodeType::End && type[j] == NodeType::End) {
      if (alpha[i] <= alpha[j])
        type[j] = NodeType::Side;
      else
        type[i] = NodeType::Side;
    }
  }
  if (std::all_of(type.begin(), type.end(), [](NodeType t) { return t == NodeType::End; })) return false;

  // Side-node projections: along the bisector, distance d / sin(α/2) so that the layer
  // has thickness d; where the front faces another part of the front within 3.6 d
  // (an odd number of layers fits) the layer is thinned so that the remaining gap is
  // a whole number of layers.
  std::vector<Vec2> side_pos(n);
  bool narrow = false;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 p = pos(nodes[i]);
    const Vec2 dn = (pos(nodes[nx(i)]) - p).normalized();
    const Vec2 dir = rotate(dn, 0.5 * alpha[i]);
    double dist = d[i] / std::max(std::sin(0.5 * alpha[i]), 0.7);
    if (type[i] == NodeType::Side) {
      const double gap = ray_gap(nodes[i], dir, 3.6 * d[i]);
      if (gap >= 2.5 * d[i] && gap < 3.5 * d[i]) dist = std::min(dist, gap / 3);
      narrow |= gap < 3.5 * d[i];
    }
    side_pos[i] = p + dist * dir;
  }
  // Tucks and wedges: where the layer's edges would come out much shorter or longer
  // than the target size, drop or add two front nodes at a free (non-input) side node.
  {
    std::size_t last = n + n;  // index of the last tuck/wedge (spacing >= 3 nodes)
    for (std::size_t i = 0; i < n; ++i) {
      if (type[i] != NodeType::Side || node_point_[nodes[i]] < mesh_.fixed_count) continue;
      if (type[pv(i)] != NodeType::Side || type[nx(i)] != NodeType::Side) continue;
      if (last < n && i - last < 4) continue;
      const double len = 0.5 * ((side_pos[nx(i)] - side_pos[i]).norm() + (side_pos[i] - side_pos[pv(i)]).norm());
      if (len < 0.45 * size_) {
        type[i] = NodeType::Tuck;
        last = i;
      } else if (len > 1.8 * size_) {
        type[i] = NodeType::Wedge;
        last = i;
      }
    }
  }

  // Planned points with union-find (an end node or a tuck makes the last new point of
  // its predecessor and the first of its successor one point).
  planned_pos_.clear();
  planned_node_.clear();
  std::vector<Index> parent;
  std::vector<Vec2> sum;
  std::vector<double> weight;
  auto add_planned = [&](const Vec2& p) {
    parent.push_back(static_cast<Index>(parent.size()));
    sum.push_back(p);
    weight.push_back(1);
    return static_cast<Index>(parent.size() - 1);
  };
  auto find = [&](Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<Index> out_begin(n), out_count(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 p = pos(nodes[i]);
    const Vec2 dn = (pos(nodes[nx(i)]) - p).normalized();
    out_begin[i] = static_cast<Index>(parent.size());
    switch (type[i]) {
      case NodeType::End:
      case NodeType::Tuck:
        break;
      case NodeType::Side:
        add_planned(side_pos[i]);
        out_count[i] = 1;
        break;
      case NodeType::Corner:
      case NodeType::Wedge: {
        const double di = d[i];
        Vec2 n1, n3;
        if (type[i] == NodeType::Corner) {
          n3 = p + di * rotate(dn, 0.5 * kPi);
          n1 = p + di * rotate(dn, alpha[i] - 0.5 * kPi);
        } else {
          n3 = p + di * rotate(dn, 0.5 * alpha[i] - 0.25 * kPi);
          n1 = p + di * rotate(dn, 0.5 * alpha[i] + 0.25 * kPi);
        }
        add_planned(n1);
        add_planned(n1 + n3 - p);
        add_planned(n3);
        out_count[i] = 3;
        break;
      }
      case NodeType::Reversal: {
        const double di = d[i];
        const Vec2 n5 = p + di * rotate(dn, 0.5 * kPi);
        const Vec2 n3 = p + di * rotate(dn, 0.5 * alpha[i]);
        const Vec2 n1 = p + di * rotate(dn, alpha[i] - 0.5 * kPi);
        add_planned(n1);
        add_planned(n1 + n3 - p);
        add_planned(n3);
        add_planned(n3 + n5 - p);
        add_planned(n5);
        out_count[i] = 5;
        break;
      }
    }
  }
  auto first_out = [&](std::size_t i) { return out_begin[i]; };
  auto last_out = [&](std::size_t i) { return out_begin[i] + out_count[i] - 1; };
  for (std::size_t i = 0; i < n; ++i) {
    if (type[i] != NodeType::End && type[i] != NodeType::Tuck) continue;
    const std::size_t a = pv(i), b = nx(i);
    if (out_count[a] == 0 || out_count[b] == 0) return false;
    Index ra = find(last_out(a)), rb = find(first_out(b));
    if (ra != rb) {
      parent[rb] = ra;
      sum[ra] += sum[rb];
      weight[ra] += weight[rb];
    }
    if (type[i] == NodeType::End) {
      sum[ra] += pos(nodes[a]) + pos(nodes[b]) - pos(nodes[i]);
      weight[ra] += 1;
    }
  }
  planned_pos_.resize(parent.size());
  planned_node_.assign(parent.size(), kInvalidIndex);
  for (Index k = 0; k < parent.size(); ++k) {
    const Index r = find(k);
    planned_pos_[k] = sum[r] / weight[r];
  }
  // Paved-boundary smoothing of the new layer: a side node's new point moves towards
  // the mean of its neighbours' new points, which damps any zigzag of the front
  // before the next layer copies it (the paved-boundary smoothing of Blacker & Stephenson).
  {
    std::vector<Vec2> smoothed(n);
    std::vector<std::uint8_t> movable(n, 0);
    for (std::size_t i = 0; i < n; ++i)
      movable[i] = type[i] == NodeType::Side && out_count[pv(i)] != 0 && out_count[nx(i)] != 0;
    for (int sweep = 0; sweep < 2; ++sweep) {
      for (std::size_t i = 0; i < n; ++i) {
        if (!movable[i]) continue;
        const Vec2& left = planned_pos_[find(last_out(pv(i)))];
        const Vec2& right = planned_pos_[find(first_out(nx(i)))];
        smoothed[i] = 0.5 * planned_pos_[find(out_begin[i])] + 0.25 * (left + right);
      }
      for (std::size_t i = 0; i < n; ++i)
        if (movable[i]) planned_pos_[find(out_begin[i])] = smoothed[i];
    }
  }
  auto planned = [&](Index k) { return Slot{true, find(k)}; };
  auto existing = [&](std::size_t i) { return Slot{false, nodes[i]}; };

  // Tucks: nudge the (free) tuck node towards its new point so that the tuck quad
  // has no straight angle; refused when it would spoil the quads already there.
  for (std::size_t i = 0; i < n; ++i) {
    if (type[i] != NodeType::Tuck) continue;
    const Index p = node_point_[nodes[i]];
    const Vec2 target = mesh_.points[p] + 0.3 * (planned_pos_[find(last_out(pv(i)))] - mesh_.points[p]);
    if (point_fronts_[p] == 1 && mesh_.min_quality_around(p, target) > 0.5 &&
        clearance(target, 0.3 * d[i], std::array<Index, 3>{node_point_[nodes[pv(i)]], p, node_point_[nodes[nx(i)]]}) >=
            0.3 * d[i])
      mesh_.points[p] = target;
  }

  // Glue the layer in front order.
  constexpr double kMinRowQuality = 0.35;
  std::size_t added = 0, attempted = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = nx(i);
    const double di = d[i];
    if (out_count[i] >= 3) {
      for (Index t = 0; t + 2 < out_count[i]; t += 2) {
        const Index o = out_begin[i] + t;
        ++attempted;
        added += try_quad({existing(i), planned(o + 2), planned(o + 1), planned(o)}, kMinRowQuality, di);
      }
    }
    if (type[i] == NodeType::End || type[i] == NodeType::Tuck) continue;
    if (type[j] == NodeType::End || type[j] == NodeType::Tuck) {
      const double q = type[j] == NodeType::Tuck ? 0.02 : 0.1;
      ++attempted;
      added += try_quad({existing(i), existing(j), existing(nx(j)), planned(last_out(i))}, q, di);
    } else {
      const Slot a = planned(first_out(j)), b = planned(last_out(i));
      if (a.id == b.id) continue;
      ++attempted;
      added += try_quad({existing(i), existing(j), a, b}, kMinRowQuality, di);
    }
  }
  if (added < attempted) narrow = true;
  if (loops_[loop].alive) loops_[loop].narrow = narrow;
  if (added > 0) ++stats_.rows;
  return added > 0;
}

bool Paver::clip_ear(Index loop) {
  // Cut the best-shaped quad off the loop: four consecutive front nodes, or three and
  // the point completing their parallelogram. For loops where rows do not fit (narrow
  // zigzag channels left where fronts met at an angle).
  struct Ear {
    double score;
    std::size_t i;
    bool closed;
  };
  const std::vector<Index> nodes = loop_nodes(loop);
  const std::size_t n = nodes.size();
  if (n < 6) return false;
  std::vector<Ear> ears;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 &a = pos(nodes[i]), &b = pos(nodes[(i + 1) % n]), &c = pos(nodes[(i + 2) % n]);
    const Vec2& d = pos(nodes[(i + 3) % n]);
    const double closed = scaled_jacobian(a, b, c, d);
    if (closed > 0.05) ears.push_back({closed + 0.1, i, true});
    if (interior_angle(nodes[(i + 1) % n]) < 0.9 * kPi) {
      const double open = scaled_jacobian(a, b, c, a + c - b);
      if (open > 0.05) ears.push_back({open, i, false});
    }
  }
  std::sort(ears.begin(), ears.end(), [](const Ear& x, const Ear& y) {
    return std::tie(y.score, x.i, x.closed) < std::tie(x.score, y.i, y.closed);
  });
  planned_pos_.clear();
  planned_node_.clear();
  for (const Ear& e : ears) {
    const Slot a{false, nodes[e.i]}, b{false, nodes[(e.i + 1) % n]}, c{false, nodes[(e.i + 2) % n]};
    const double d = local_size(b.id);
    if (e.closed) {
      if (try_quad({a, b, c, Slot{false, nodes[(e.i + 3) % n]}}, 0.05, d)) return true;
    } else {
      planned_pos_.assign(1, pos(a.id) + pos(c.id) - pos(b.id));
      planned_node_.assign(1, kInvalidIndex);
      if (try_quad({a, b, c, Slot{true, 0}}, 0.05, d)) return true;
    }
  }
  return false;
}

bool Paver::seams(Index loop) {
  constexpr double kSeamAngle = 60.0 / 180.0 * kPi;
  bool any = false;
  const std::vector<Index> nodes = loop_nodes(loop);
  for (const Index v : nodes) {
    if (!node_alive_[v] || loops_[loop].size <= 6) continue;
    if (interior_angle(v) > kSeamAngle) continue;
    const Index u = node_prev_[v], w = node_next_[v];
    const Index pu = node_point_[u], pw = node_point_[w];
    if (pu == pw || point_fronts_[pu] != 1 || point_fronts_[pw] != 1) continue;
    if (makes_doublet(node_point_[v], 0)) continue;
    const bool fu = pu < mesh_.fixed_count, fw = pw < mesh_.fixed_count;
    if (fu && fw) continue;
    const Index keep = fu ? pu : (fw ? pw : std::min(pu, pw));
    const Index drop = keep == pu ? pw : pu;
    const Vec2 target = fu ? mesh_.points[pu] : (fw ? mesh_.points[pw] : 0.5 * (mesh_.points[pu] + mesh_.points[pw]));
    if ((mesh_.points[pu] - mesh_.points[pw]).norm() > 1.2 * local_size(v)) continue;
    // No quad may hold both points (it would collapse).
    bool shared = false;
    mesh_.for_each_quad(pu, [&](Index q) {
      for (const Index x : mesh_.quads[q])
        if (x == pw) shared = true;
    });
    if (shared) continue;
    if (mesh_.min_quality_around(pu, target) < 0.15 || mesh_.min_quality_around(pw, target) < 0.15) continue;
    const Index before = node_prev_[u], after = node_next_[w];
    if (before == w || after == u) continue;
    const Vec2 old_u = mesh_.points[pu], old_w = mesh_.points[pw];
    const Vec2 pb = pos(before), pa = pos(after), pvv = pos(v);
    if (segment_blocked(pb, target, node_point_[before], pu) || segment_blocked(target, pa, pw, node_point_[after]))
      continue;
    // Commit: one point survives at the target; v leaves the front.
    mesh_.points[keep] = target;
    mesh_.merge_point(drop, keep);
    kill_node(v);
    kill_node(w);
    node_point_[u] = keep;
    point_fronts_[keep] = 1;
    point_fronts_[drop] = 0;
    set_next(before, u);
    set_next(u, after);
    Loop& l = loops_[loop];
    l.size -= 2;
    l.area += 0.5 * (cross(pb, target) + cross(target, pa) - cross(pb, old_u) - cross(old_u, pvv) - cross(pvv, old_w) -
                     cross(old_w, pa));
    l.head = u;
    ++stats_.seams;
    any = true;
  }
  return any;
}

bool Paver::apply_chord(Index a, Index b, int interior, bool join) {
  const Vec2 pa = pos(a), pb = pos(b);
  const Index qa = node_point_[a], qb = node_point_[b];
  if (qa == qb) return false;
  const Vec2 dir = pb - pa;
  // Inside the wedge at both ends, and crossing nothing.
  const double sa = ccw_angle(pos(node_next_[a]) - pa, dir);
  if (!(sa > 0.2 && sa < interior_angle(a) - 0.2)) return false;
  const double sb = ccw_angle(pos(node_next_[b]) - pb, -dir);
  if (!(sb > 0.2 && sb < interior_angle(b) - 0.2)) return false;
  if (segment_blocked(pa, pb, qa, qb)) return false;
  const double spacing = dir.norm() / (interior + 1);
  if (segment_clearance(pa, pb, 0.3 * spacing, std::array<Index, 2>{qa, qb}) < 0.3 * spacing) return false;
  std::vector<Vec2> cp(static_cast<std::size_t>(interior));
  for (int t = 0; t < interior; ++t) {
    cp[t] = pa + dir * (static_cast<double>(t + 1) / (interior + 1));
    if (clearance(cp[t], 0.45 * spacing, std::array<Index, 2>{qa, qb}) < 0.45 * spacing) return false;
  }

  // Never cut off a loop of 4 that is not a decent quad.
  if (!join && interior == 0) {
    for (const auto& [s, t] : {std::pair{a, b}, std::pair{b, a}}) {
      const Index u = node_next_[s], v = node_next_[u];
      if (node_next_[v] == t && scaled_jacobian(pos(s), pos(u), pos(v), pos(t)) < 0.2) return false;
    }
  }
  const Index la = node_loop_[a], lb = node_loop_[b];
  const Index na = node_next_[a], pbn = node_prev_[b];
  std::vector<Index> points(cp.size());
  for (std::size_t t = 0; t < cp.size(); ++t) points[t] = mesh_.add_point(cp[t]);
  // Loop X: a -> chord -> b -> ... ; loop Y: b' -> chord reversed -> a' -> na -> ... -> pbn.
  Index at = a;
  for (const Index p : points) {
    const Index f = new_node(p, la);
    set_next(at, f);
    at = f;
  }
  set_next(at, b);
  const Index b2 = new_node(qb, la);
  const Index a2 = new_node(qa, la);
  set_next(pbn, b2);
  at = b2;
  for (std::size_t t = points.size(); t-- > 0;) {
    const Index g = new_node(points[t], la);
    set_next(at, g);
    at = g;
  }
  set_next(at, a2);
  set_next(a2, na);

  if (join) {
    Loop& keep = loops_[la];
    Loop& gone = loops_[lb];
    keep.size += gone.size + 2 + 2 * static_cast<Index>(interior);
    keep.area += gone.area;
    keep.head = a;
    keep.stuck = 0;
    gone.alive = false;
    gone.size = 0;
    relabel(b, node_prev_[b], la);  // the whole joined loop from b round to a2 -> ... -> a
  } else {
    // Walk both new loops together; the shorter one gets a new id (O(shorter)).
    Index x = node_next_[a], y = node_next_[b2];
    Index nx = 1, ny = 1;
    while (x != a && y != b2) {
      x = node_next_[x];
      y = node_next_[y];
      ++nx;
      ++ny;
    }
    const bool x_short = x == a;
    const Index head = x_short ? a : b2;
    const auto id = static_cast<Index>(loops_.size());
    Loop fresh;
    fresh.alive = true;
    fresh.head = head;
    fresh.size = x_short ? nx : ny;
    double area2 = 0;
    Index m = head;
    do {
      node_loop_[m] = id;
      area2 += cross(pos(m), pos(node_next_[m]));
      m = node_next_[m];
    } while (m != head);
    fresh.area = 0.5 * area2;
    Loop& old = loops_[la];
    old.size = old.size + 2 + 2 * static_cast<Index>(interior) - fresh.size;
    old.area -= fresh.area;
    old.head = x_short ? b2 : a;
    old.stuck = 0;
    if (fresh.area < 0) {
      negative_loops_.push_back(id);
      fresh.listed = true;
    }
    if (old.area < 0 && !old.listed) {
      negative_loops_.push_back(la);
      old.listed = true;
    }
    loops_.push_back(fresh);
  }
  ++stats_.splits;
  return true;
}

bool Paver::splits(Index loop) {
  struct Candidate {
    double score;
    Index a, b;
    int interior;
    bool join;
  };
  if (!loops_[loop].narrow && loops_[loop].size > 24) return false;
  const std::vector<Index> nodes = loop_nodes(loop);
  const std::size_t n = nodes.size();
  if (n < 6) return false;
  std::vector<Candidate> found;
  // Position along the loop of every node (scratch array shared by all loops).
  std::vector<Index>& index_of = index_of_;
  if (index_of.size() < node_next_.size()) index_of.resize(node_next_.size());
  for (std::size_t i = 0; i < n; ++i) index_of[nodes[i]] = static_cast<Index>(i);

  // Parity. A loop closes with quads only when its node count plus the node counts of
  // the open holes inside it is even (every quad changes a loop's count by an even
  // number, and a chord joining a hole adds the hole's count plus an even number). So
  // a chord's interior node count m follows the odd holes each side gets: holes
  // inside the sub-loop X = nodes[i..j] + chord are counted by the crossings of a ray
  // (+x) from a point of the hole with X's edges, from per-hole sorted lists of the
  // loop's crossing edges (O(n log h) per call, O(h log n) per candidate).
  struct OddHole {
    Vec2 at;
    std::vector<Index> crossing_edges;  // loop edges nodes[k] -> nodes[k + 1] the ray crosses
  };
  std::vector<OddHole> odd;
  std::vector<double> twice_area(n + 1, 0);  // prefix sums of the shoelace terms
  for (std::size_t k = 0; k < n; ++k) twice_area[k + 1] = twice_area[k] + cross(pos(nodes[k]), pos(nodes[(k + 1) % n]));
  {
    BoundingBox2 box;
    for (const Index v : nodes) box.extend(pos(v));
    for (const Vec2& q : odd_hole_points(loop))
      if (q.x() >= box.min.x() && q.x() <= box.max.x() && q.y() >= box.min.y() && q.y() <= box.max.y())
        odd.push_back({q, {}});
    std::sort(odd.begin(), odd.end(), [](const OddHole& x, const OddHole& y) {
      return std::tie(x.at.y(), x.at.x()) < std::tie(y.at.y(), y.at.x());
    });
    for (std::size_t k = 0; k < n && !odd.empty(); ++k) {
      const Vec2 &u = pos(nodes[k]), &v = pos(nodes[(k + 1) % n]);
      const double lo = std::min(u.y(), v.y()), hi = std::max(u.y(), v.y());
      auto it = std::lower_bound(odd.begin(), odd.end(), lo, [](const OddHole& h, double y) { return h.at.y() < y; });
      for (; it != odd.end() && it->at.y() < hi; ++it) {
        const Vec2& q = it->at;
        if ((u.y() > q.y()) != (v.y() > q.y()) && q.x() < u.x() + (q.y() - u.y()) / (v.y() - u.y()) * (v.x() - u.x()))
          it->crossing_edges.push_back(static_cast<Index>(k));
      }
    }
  }
  const bool hole_loop = loops_[loop].area < 0;
  // Parity of m that lets both sub-loops of the chord nodes[i] -> nodes[j] close.
  auto chord_parity = [&](std::size_t i, std::size_t j) {
    const std::size_t p = j - i;
    int holes = 0;
    const Vec2 &a = pos(nodes[i]), &b = pos(nodes[j]);
    for (const OddHole& h : odd) {
      const auto& e = h.crossing_edges;
      auto crossings = std::lower_bound(e.begin(), e.end(), static_cast<Index>(j)) -
                       std::lower_bound(e.begin(), e.end(), static_cast<Index>(i));
      const Vec2& q = h.at;
      if ((b.y() > q.y()) != (a.y() > q.y()) && q.x() < b.x() + (q.y() - b.y()) / (a.y() - b.y()) * (a.x() - b.x()))
        ++crossings;
      holes += static_cast<int>(crossings % 2);
    }
    // The sub-loop that bounds a region with those holes: X, or (a hole's loop cut
    // off a pocket, X being what is left of the hole) the other one.
    const bool x_bounds = !hole_loop || twice_area[j] - twice_area[i] + cross(b, a) > 0;
    return static_cast<int>(((x_bounds ? p + 1 : n - p + 1) + static_cast<std::size_t>(holes)) % 2);
  };

  // Chords start only at nodes of angle >= 0.8π: a cheap test (no atan2) first.
  const double cos_turn = std::cos(0.2 * kPi);
  std::vector<double> alpha(n, 0), dloc(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& p = pos(nodes[i]);
    const Vec2 in = p - pos(node_prev_[nodes[i]]), out = pos(node_next_[nodes[i]]) - p;
    if (cross(in, out) > 0 && in.dot(out) < cos_turn * in.norm() * out.norm()) continue;  // turns left > 36°
    alpha[i] = interior_angle(nodes[i]);
    dloc[i] = local_size(nodes[i]);
  }
  auto deviation = [](double s) {
    // distance of a sub-angle from the nearest of 90° and 180°
    return std::min(std::abs(s - 0.5 * kPi), std::abs(s - kPi));
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Index a = nodes[i];
    if (alpha[i] < 0.8 * kPi) continue;
    const Vec2 pa = pos(a);
    const double reach = 2.4 * dloc[i];
    const Vec2 r(reach, reach);
    grid_.visit(
        pa - r, pa + r, [this](Index x, Index y) { return edge_live(x, y); },
        [&](Index b, Index) {
          const Index lb = node_loop_[b];
          const bool join = lb != loop;
          if (join) {
            if (!loops_[lb].alive) return true;
          } else if (index_of[b] <= i) {
            return true;
          }
          const Vec2 pb = pos(b);
          const Vec2 dir = pb - pa;
          const double c = dir.norm();
          if (c > reach || c <= 0) return true;
          const double ab = interior_angle(b);
          if (ab < 0.8 * kPi) return true;
          const double d = 0.5 * (dloc[i] + local_size(b));
          int m = 0;
          if (join) {
            m = std::max(0, static_cast<int>(std::lround(c / d)) - 1);
          } else {
            const std::size_t p = index_of[b] - i;
            if (p < 3 || n - p < 3) return true;
            const int parity = chord_parity(i, index_of[b]);
            const double ideal = c / d - 1;
            m = parity + 2 * std::max(0, static_cast<int>(std::lround((ideal - parity) / 2)));
            if (static_cast<int>(p) + 1 + m < 4 || static_cast<int>(n - p) + 1 + m < 4) return true;
          }
          const double ratio = c / ((m + 1) * d);
          if (ratio < 0.65 || ratio > 1.45 || m > 2) return true;
          const double sa = ccw_angle(pos(node_next_[a]) - pa, dir);
          const double sb = ccw_angle(pos(node_next_[b]) - pb, -dir);
          const double min_sub = 0.3 * kPi;
          if (sa < min_sub || alpha[i] - sa < min_sub || sb < min_sub || ab - sb < min_sub) return true;
          const double score = (deviation(sa) + deviation(alpha[i] - sa) + deviation(sb) + deviation(ab - sb)) / kPi +
                               2 * std::abs(std::log(ratio));
          if (score > 0.9) return true;
          found.push_back({score, a, b, m, join});
          return true;
        });
  }
  if (found.empty()) return false;
  std::sort(found.begin(), found.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.score, x.a, x.b, x.interior) < std::tie(y.score, y.a, y.b, y.interior);
  });
  // A join changes the loops' numbering: apply the best one alone.
  for (const Candidate& c : found) {
    if (!c.join) continue;
    if (apply_chord(c.a, c.b, c.interior, true)) return true;
  }
  std::vector<std::pair<Index, Index>> accepted;
  std::vector<std::uint8_t> used(n, 0);
  bool any = false;
  for (const Candidate& c : found) {
    if (c.join) continue;
    const Index i = index_of[c.a], j = index_of[c.b];
    if (used[i] || used[j]) continue;
    bool crosses = false;
    for (const auto& [s, t] : accepted)
      if ((s < i && i < t && t < j) || (i < s && s < j && j < t)) crosses = true;
    if (crosses) continue;
    if (!apply_chord(c.a, c.b, c.interior, false)) continue;
    used[i] = used[j] = 1;
    accepted.emplace_back(i, j);
    any = true;
  }
  return any;
}

std::vector<Vec2> Paver::odd_hole_points(Index loop) {
  std::vector<Vec2> points;
  std::erase_if(negative_loops_, [this](Index l) { return !loops_[l].alive; });
  for (const Index l : negative_loops_) {
    if (l == loop || loops_[l].area >= 0 || loops_[l].size % 2 == 0) continue;
    Index v = loops_[l].head;
    while (point_fronts_[node_point_[v]] != 1 && node_next_[v] != loops_[l].head) v = node_next_[v];
    if (point_fronts_[node_point_[v]] == 1) points.push_back(pos(v));
  }
  return points;
}

}  // namespace structmesh::paving
