// The advancing front of the paving mesher: growing mesh, edge grid, and the one
// primitive that changes the front, try_quad(): a quad glued onto a chain of front
// edges is accepted only when it lies in the unmeshed region (wedge test at both
// chain ends, no front edge crossed, no front point inside, clearance from the front),
// so the unmeshed region stays a set of valid polygons after every step.
#include "quad2d/paving.hpp"

#include <algorithm>
#include <cmath>

namespace structmesh::paving {

namespace {

double orient(const Vec2& a, const Vec2& b, const Vec2& c) { return cross(b - a, c - a); }

bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}

}  // namespace

bool segments_intersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  if (std::max(a.x(), b.x()) < std::min(c.x(), d.x()) || std::max(c.x(), d.x()) < std::min(a.x(), b.x()) ||
      std::max(a.y(), b.y()) < std::min(c.y(), d.y()) || std::max(c.y(), d.y()) < std::min(a.y(), b.y()))
    return false;
  // Orientations below a relative 1e-12 count as zero: a near-touch is a touch.
  const double lab = (b - a).norm(), lcd = (d - c).norm();
  const double tol = 1e-12 * lab * lcd;
  auto sign = [tol](double v) { return v > tol ? 1 : (v < -tol ? -1 : 0); };
  const int d1 = sign(orient(c, d, a)), d2 = sign(orient(c, d, b));
  const int d3 = sign(orient(a, b, c)), d4 = sign(orient(a, b, d));
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && on_segment(c, d, a)) || (d2 == 0 && on_segment(c, d, b)) || (d3 == 0 && on_segment(a, b, c)) ||
         (d4 == 0 && on_segment(a, b, d));
}

// ---------------------------------------------------------------------------

Index GrowingMesh::add_point(const Vec2& p) {
  points.push_back(p);
  first_record.push_back(kInvalidIndex);
  return static_cast<Index>(points.size() - 1);
}

Index GrowingMesh::add_quad(const std::array<Index, 4>& q) {
  const auto id = static_cast<Index>(quads.size());
  quads.push_back(q);
  for (const Index p : q) {
    record_quad.push_back(id);
    record_next.push_back(first_record[p]);
    first_record[p] = static_cast<Index>(record_quad.size() - 1);
  }
  return id;
}

double GrowingMesh::min_quality_around(Index p, const Vec2& at) const {
  double worst = 1;
  for (Index r = first_record[p]; r != kInvalidIndex; r = record_next[r]) {
    const auto& q = quads[record_quad[r]];
    std::array<Vec2, 4> c;
    for (int j = 0; j < 4; ++j) c[j] = q[j] == p ? at : points[q[j]];
    worst = std::min(worst, scaled_jacobian(c[0], c[1], c[2], c[3]));
  }
  return worst;
}

void GrowingMesh::merge_point(Index from, Index to) {
  Index last = kInvalidIndex;
  for (Index r = first_record[from]; r != kInvalidIndex; r = record_next[r]) {
    for (Index& v : quads[record_quad[r]])
      if (v == from) v = to;
    last = r;
  }
  if (last == kInvalidIndex) return;
  record_next[last] = first_record[to];
  first_record[to] = first_record[from];
  first_record[from] = kInvalidIndex;
}

void GrowingMesh::rebuild_records() {
  std::fill(first_record.begin(), first_record.end(), kInvalidIndex);
  record_quad.clear();
  record_next.clear();
  for (Index id = 0; id < quads.size(); ++id) {
    if (quads[id][0] == kInvalidIndex) continue;
    for (const Index p : quads[id]) {
      record_quad.push_back(id);
      record_next.push_back(first_record[p]);
      first_record[p] = static_cast<Index>(record_quad.size() - 1);
    }
  }
}

// ---------------------------------------------------------------------------

void EdgeGrid::init(const BoundingBox2& box, double cell, std::size_t expected_points) {
  const double margin = cell;
  origin_ = box.min - Vec2(margin, margin);
  const Vec2 extent = box.max - box.min + Vec2(2 * margin, 2 * margin);
  // About as many cells as points, at most 4 per point (memory stays linear).
  const double max_cells = std::max(4096.0, 4.0 * static_cast<double>(expected_points));
  while ((extent.x() / cell + 1) * (extent.y() / cell + 1) > max_cells) cell *= 1.5;
  cell_ = cell;
  inv_cell_ = 1 / cell;
  nx_ = static_cast<int>(extent.x() * inv_cell_) + 1;
  ny_ = static_cast<int>(extent.y() * inv_cell_) + 1;
  head_.assign(static_cast<std::size_t>(nx_) * ny_, kInvalidIndex);
}

void EdgeGrid::cell_range(const Vec2& lo, const Vec2& hi, int& x0, int& y0, int& x1, int& y1) const {
  auto cx = [&](double v) {
    return std::clamp(static_cast<int>(std::floor((v - origin_.x()) * inv_cell_)), 0, nx_ - 1);
  };
  auto cy = [&](double v) {
    return std::clamp(static_cast<int>(std::floor((v - origin_.y()) * inv_cell_)), 0, ny_ - 1);
  };
  x0 = cx(lo.x());
  x1 = cx(hi.x());
  y0 = cy(lo.y());
  y1 = cy(hi.y());
}

void EdgeGrid::insert(Index node, Index next, const Vec2& a, const Vec2& b) {
  int x0, y0, x1, y1;
  cell_range(a.cwiseMin(b), a.cwiseMax(b), x0, y0, x1, y1);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      Index e;
      if (free_ != kInvalidIndex) {
        e = free_;
        free_ = link_[e];
        node_[e] = node;
        next_node_[e] = next;
      } else {
        e = static_cast<Index>(node_.size());
        node_.push_back(node);
        next_node_.push_back(next);
        link_.push_back(kInvalidIndex);
      }
      Index& h = head_[static_cast<std::size_t>(y) * nx_ + x];
      link_[e] = h;
      h = e;
    }
  }
}

// ---------------------------------------------------------------------------

Index Paver::new_node(Index point, Index loop) {
  const auto n = static_cast<Index>(node_point_.size());
  node_point_.push_back(point);
  node_next_.push_back(kInvalidIndex);
  node_prev_.push_back(kInvalidIndex);
  node_loop_.push_back(loop);
  node_alive_.push_back(1);
  if (point >= point_fronts_.size()) point_fronts_.resize(point + 1, 0);
  ++point_fronts_[point];
  return n;
}

void Paver::set_next(Index a, Index b) {
  node_next_[a] = b;
  node_prev_[b] = a;
  grid_.insert(a, b, pos(a), pos(b));
}

void Paver::kill_node(Index n) {
  node_alive_[n] = 0;
  const Index p = node_point_[n];
  if (--point_fronts_[p] == 0 && p >= mesh_.fixed_count) released_.push_back(p);
}

double Paver::interior_angle(Index node) const {
  const Vec2& p = pos(node);
  return ccw_angle(pos(node_next_[node]) - p, pos(node_prev_[node]) - p);
}

std::vector<Index> Paver::loop_nodes(Index loop) const {
  std::vector<Index> nodes;
  nodes.reserve(loops_[loop].size);
  Index n = loops_[loop].head;
  do {
    nodes.push_back(n);
    n = node_next_[n];
  } while (n != loops_[loop].head && nodes.size() <= node_next_.size());
  return nodes;
}

void Paver::relabel(Index start, Index stop, Index loop) {
  for (Index n = start;; n = node_next_[n]) {
    node_loop_[n] = loop;
    if (n == stop) break;
  }
}

bool Paver::segment_blocked(const Vec2& a, const Vec2& b, Index pa, Index pb) {
  bool blocked = false;
  grid_.visit(
      a.cwiseMin(b), a.cwiseMax(b), [this](Index n, Index m) { return edge_live(n, m); },
      [&](Index n, Index m) {
        const Index u = node_point_[n], v = node_point_[m];
        if (u == pa || u == pb || v == pa || v == pb) return true;
        if (segments_intersect(a, b, mesh_.points[u], mesh_.points[v])) {
          blocked = true;
          return false;
        }
        return true;
      });
  return blocked;
}

double Paver::clearance(const Vec2& p, double radius, std::span<const Index> ignore) {
  double best = radius;
  const Vec2 r(radius, radius);
  grid_.visit(
      p - r, p + r, [this](Index n, Index m) { return edge_live(n, m); },
      [&](Index n, Index m) {
        const Index u = node_point_[n], v = node_point_[m];
        for (const Index i : ignore)
          if (u == i || v == i) return true;
        best = std::min(best, point_segment_distance(p, mesh_.points[u], mesh_.points[v]));
        return true;
      });
  return best;
}

double Paver::segment_clearance(const Vec2& a, const Vec2& b, double radius, std::span<const Index> ignore) {
  double best = radius;
  const Vec2 r(radius, radius);
  grid_.visit(
      a.cwiseMin(b) - r, a.cwiseMax(b) + r, [this](Index n, Index m) { return edge_live(n, m); },
      [&](Index n, Index) {
        const Index u = node_point_[n];
        for (const Index i : ignore)
          if (u == i) return true;
        best = std::min(best, point_segment_distance(mesh_.points[u], a, b));
        return true;
      });
  return best;
}

bool Paver::point_inside(const std::array<Vec2, 4>& q, std::span<const Index> ignore) {
  Vec2 lo = q[0], hi = q[0];
  for (const Vec2& c : q) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  bool inside = false;
  grid_.visit(
      lo, hi, [this](Index n, Index m) { return edge_live(n, m); },
      [&](Index n, Index) {
        const Index u = node_point_[n];
        for (const Index i : ignore)
          if (u == i) return true;
        const Vec2& p = mesh_.points[u];
        for (int j = 0; j < 4; ++j)
          if (orient(q[j], q[(j + 1) % 4], p) <= 0) return true;
        inside = true;
        return false;
      });
  return inside;
}

bool Paver::try_quad(const std::array<Slot, 4>& slots, double min_quality, double local_size) {
  std::array<Index, 4> fn{};
  std::array<bool, 4> existing{};
  int count = 0;
  for (int j = 0; j < 4; ++j) {
    Index n = kInvalidIndex;
    if (!slots[j].planned) {
      n = slots[j].id;
    } else {
      n = planned_node_[slots[j].id];
    }
    if (n != kInvalidIndex) {
      if (!node_alive_[n]) return false;
      fn[j] = n;
      existing[j] = true;
      ++count;
    }
  }
  if (count < 2) return false;
  const Index loop = node_loop_[fn[std::find(existing.begin(), existing.end(), true) - existing.begin()]];
  for (int j = 0; j < 4; ++j)
    if (existing[j] && node_loop_[fn[j]] != loop) return false;
  // The existing nodes must be one chain e0 -> ... -> ek of front edges in quad order.
  int r = -1, k = 0;
  if (count == 4) {
    for (int j = 0; j < 4 && r < 0; ++j)
      if (node_next_[fn[j]] == fn[(j + 1) % 4] && node_next_[fn[(j + 1) % 4]] == fn[(j + 2) % 4] &&
          node_next_[fn[(j + 2) % 4]] == fn[(j + 3) % 4])
        r = j;
    if (r < 0) return false;
    k = node_next_[fn[(r + 3) % 4]] == fn[r] ? 4 : 3;
  } else {
    for (int j = 0; j < 4; ++j) {
      if (existing[j] && !existing[(j + 3) % 4]) {
        if (r >= 0) return false;  // two separate runs
        r = j;
      }
    }
    k = count - 1;
    for (int t = 0; t < k; ++t)
      if (node_next_[fn[(r + t) % 4]] != fn[(r + t + 1) % 4]) return false;
  }
  std::array<Vec2, 4> q;
  std::array<Index, 4> qp{};
  for (int j = 0; j < 4; ++j) {
    q[j] = existing[j] ? pos(fn[j]) : planned_pos_[slots[j].id];
    qp[j] = existing[j] ? node_point_[fn[j]] : kInvalidIndex;
  }
  if (scaled_jacobian(q[0], q[1], q[2], q[3]) < min_quality) return false;

  if (k == 4) {
    if (loops_[loop].size != 4) return false;
    for (int j = 0; j < 4; ++j)
      if (makes_doublet(qp[j], 1)) return false;
    emit_quad(qp);
    for (int j = 0; j < 4; ++j) kill_node(fn[j]);
    loops_[loop].alive = false;
    loops_[loop].size = 0;
    return true;
  }

  const Index e0 = fn[r], ek = fn[(r + k) % 4];
  for (int t = 1; t < k; ++t)
    if (makes_doublet(qp[(r + t) % 4], 1)) return false;
  // Wedge test: the quad's corner at each chain end must fit in the front's angle there.
  const Vec2& p0 = q[r];
  const double corner0 = ccw_angle(q[(r + 1) % 4] - p0, q[(r + 3) % 4] - p0);
  const double angle0 = interior_angle(e0);
  if (corner0 >= angle0 - 1e-9) return false;
  // No sliver of front left at either end: the angle that remains is at least 30°
  // unless it was that sharp already.
  constexpr double kMinLeft = kPi / 6;
  if (angle0 - corner0 < kMinLeft && angle0 - corner0 < 0.9 * angle0) return false;
  const Vec2& pk = q[(r + k) % 4];
  const double cornerk = ccw_angle(q[(r + k + 1) % 4] - pk, q[(r + k + 3) % 4] - pk);
  const double anglek = interior_angle(ek);
  if (cornerk >= anglek - 1e-9) return false;
  if (anglek - cornerk < kMinLeft && anglek - cornerk < 0.9 * anglek) return false;

  // The new edges (ek -> new points -> e0) must cross no front edge.
  for (int t = k; t < 4; ++t) {
    const int a = (r + t) % 4, b = (r + t + 1) % 4;
    if (segment_blocked(q[a], q[b], qp[a], qp[b])) return false;
  }
  std::array<Index, 4> chain_points{kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex};
  for (int t = 0; t <= k; ++t) chain_points[t] = qp[(r + t) % 4];
  const std::span<const Index> ignore(chain_points.data(), static_cast<std::size_t>(k + 1));
  const double min_clearance = 0.3 * local_size;
  for (int t = k + 1; t < 4; ++t) {
    const int a = (r + t) % 4;
    if (clearance(q[a], min_clearance, ignore) < min_clearance) return false;
  }
  // ... and no front point close to a new edge.
  for (int t = k; t < 4; ++t) {
    const int a = (r + t) % 4, b = (r + t + 1) % 4;
    if (segment_clearance(q[a], q[b], 0.5 * min_clearance, ignore) < 0.5 * min_clearance) return false;
  }
  if (point_inside(q, ignore)) return false;
  // Never leave a loop of 4 that is not a decent quad.
  if (loops_[loop].size + 4 - 2 * k == 4) {
    std::array<Vec2, 4> rest;
    int c = 0;
    rest[c++] = q[r];
    for (int t = 3; t > k; --t) rest[c++] = q[(r + t) % 4];
    for (Index m = ek; c < 4; m = node_next_[m]) rest[c++] = pos(m);
    if (scaled_jacobian(rest[0], rest[1], rest[2], rest[3]) < 0.2) return false;
  }

  // Commit: new points, the quad, and the front e0 -> (new points reversed) -> ek.
  std::array<Index, 4> nodes = fn;
  for (int t = k + 1; t < 4; ++t) {
    const int a = (r + t) % 4;
    qp[a] = mesh_.add_point(q[a]);
    nodes[a] = new_node(qp[a], loop);
    planned_node_[slots[a].id] = nodes[a];
  }
  emit_quad(qp);
  for (int t = 1; t < k; ++t) kill_node(fn[(r + t) % 4]);
  Index at = e0;
  for (int t = 3; t >= k; --t) {
    const Index to = t == k ? ek : nodes[(r + t) % 4];
    set_next(at, to);
    at = to;
  }
  Loop& l = loops_[loop];
  l.size = static_cast<Index>(static_cast<int>(l.size) + 4 - 2 * k);
  l.area -= quad_area(q[0], q[1], q[2], q[3]);
  l.head = e0;
  return true;
}

void Paver::emit_quad(const std::array<Index, 4>& q) { mesh_.add_quad(q); }

}  // namespace structmesh::paving
