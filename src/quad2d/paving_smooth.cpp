// Smoothing of the paving mesher: after every row the points that just left the
// front, at the end all interior points; then a local optimisation of the worst
// quads. No move is accepted that makes a quad worse than the limit, so smoothing
// never inverts a quad (boundary points never move).
#include "quad2d/paving.hpp"

#include <algorithm>
#include <cmath>

namespace structmesh::paving {

double Paver::smooth_point(Index p) {
  if (p < mesh_.fixed_count || mesh_.first_record[p] == kInvalidIndex) return 0;
  if (p < point_fronts_.size() && point_fronts_[p] != 0) return 0;
  // Laplacian: the mean of the edge neighbours (each quad holds two of them; every
  // edge is counted twice, once per quad). On a grid this keeps the grid.
  Vec2 target(0, 0);
  int count = 0;
  mesh_.for_each_quad(p, [&](Index q) {
    const auto& v = mesh_.quads[q];
    for (int j = 0; j < 4; ++j) {
      if (v[j] != p) continue;
      target += 0.5 * (mesh_.points[v[(j + 1) % 4]] + mesh_.points[v[(j + 3) % 4]]);
      ++count;
    }
  });
  if (count == 0) return 0;
  target /= count;
  const Vec2 now = mesh_.points[p];
  // The quads around must stay above min(their worst now, 0.5): the worst now is only
  // needed when the move would go below 0.5.
  double floor = -1;
  for (const double f : {1.0, 0.5}) {
    const Vec2 to = now + f * (target - now);
    const double after = mesh_.min_quality_around(p, to);
    if (after < 0.5 && floor < 0) floor = std::min(mesh_.min_quality_around(p, now), 0.5);
    if (after > 0 && after >= std::min(floor < 0 ? 0.5 : floor, 0.5)) {
      mesh_.points[p] = to;
      return (to - now).norm();
    }
  }
  return 0;
}

void Paver::smooth_points(std::span<const Index> pts, int sweeps) {
  for (int s = 0; s < sweeps; ++s)
    for (const Index p : pts) smooth_point(p);
}

bool Paver::optimize_point(Index p, double step_scale) {
  if (p < mesh_.fixed_count || mesh_.first_record[p] == kInvalidIndex) return false;
  Vec2 at = mesh_.points[p];
  double now = mesh_.min_quality_around(p, at);
  double len = 0;
  int count = 0;
  mesh_.for_each_quad(p, [&](Index q) {
    const auto& v = mesh_.quads[q];
    for (int j = 0; j < 4; ++j)
      if (v[j] == p) {
        len += (mesh_.points[v[(j + 1) % 4]] - at).norm();
        ++count;
      }
  });
  if (count == 0) return false;
  double step = step_scale * len / count;
  bool improved_any = false;
  const double smallest = 0.01 * step;
  for (int it = 0; it < 16 && step > smallest; ++it) {
    const bool improved =
        pattern_search_round(at, step, now, [&](const Vec2& to) { return mesh_.min_quality_around(p, to); });
    if (!improved) step *= 0.5;
    improved_any |= improved;
  }
  mesh_.points[p] = at;
  return improved_any;
}

void Paver::collapse_diamonds() {
  // Cleanup: a quad whose two opposite corners a, c are interior points of valence 3
  // collapses along that diagonal; the merged point has valence 4 and the other two
  // corners lose one quad. Done only where the number of singular points drops and the
  // quads around stay valid. One pass locks the points it touches (counts stay exact);
  // the records are rebuilt after each pass.
  const auto total = static_cast<Index>(mesh_.points.size());
  for (int pass = 0; pass < 4; ++pass) {
    std::vector<int> valence(total, 0);
    for (const auto& q : mesh_.quads)
      if (q[0] != kInvalidIndex)
        for (const Index v : q) ++valence[v];
    std::vector<std::uint8_t> locked(total, 0);
    std::vector<Index> merged_into(total, kInvalidIndex);
    auto singular = [&](Index v, int val) { return v >= mesh_.fixed_count && val != 4; };
    bool any = false;
    for (Index id = 0; id < mesh_.quads.size(); ++id) {
      const auto q = mesh_.quads[id];
      if (q[0] == kInvalidIndex) continue;
      for (int s = 0; s < 2; ++s) {
        const Index a = q[s], b = q[s + 1], c = q[s + 2], d = q[(s + 3) % 4];
        if (a < mesh_.fixed_count || c < mesh_.fixed_count || valence[a] != 3 || valence[c] != 3) continue;
        if (locked[a] || locked[b] || locked[c] || locked[d]) continue;
        if (valence[b] < 3 || valence[d] < 3) continue;  // b, d keep at least 2 quads
        const int before = 2 + singular(b, valence[b]) + singular(d, valence[d]);
        const int after = singular(b, valence[b] - 1) + singular(d, valence[d] - 1);
        if (after >= before) continue;
        // Geometry: every other quad of a and c with both at the midpoint stays valid.
        const Vec2 mid = 0.5 * (mesh_.points[a] + mesh_.points[c]);
        bool ok = true;
        for (const Index p : {a, c}) {
          mesh_.for_each_quad(p, [&](Index r) {
            if (r == id || !ok || mesh_.quads[r][0] == kInvalidIndex) return;
            std::array<Vec2, 4> corners;
            int hits = 0;
            for (int j = 0; j < 4; ++j) {
              const Index v = mesh_.quads[r][j];
              if (v == a || v == c) ++hits;
              corners[j] = (v == a || v == c) ? mid : mesh_.points[v];
            }
            if (hits > 1 || scaled_jacobian(corners[0], corners[1], corners[2], corners[3]) < 0.1) ok = false;
          });
        }
        if (!ok) continue;
        mesh_.points[a] = mid;
        merged_into[c] = a;
        mesh_.quads[id] = {kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex};
        for (const Index v : {a, b, c, d}) locked[v] = 1;
        for (const Index p : {a, c}) {
          mesh_.for_each_quad(p, [&](Index r) {
            if (mesh_.quads[r][0] == kInvalidIndex) return;
            for (const Index v : mesh_.quads[r]) locked[v] = 1;
          });
        }
        any = true;
        break;
      }
    }
    if (!any) break;
    for (auto& q : mesh_.quads)
      if (q[0] != kInvalidIndex)
        for (Index& v : q)
          if (merged_into[v] != kInvalidIndex) v = merged_into[v];
    mesh_.rebuild_records();
  }
}

void Paver::collapse_doublets() {
  bool any = false;
  for (Index p = mesh_.fixed_count; p < mesh_.points.size(); ++p) {
    if (mesh_.quad_count(p) != 2) continue;
    const Index r = mesh_.first_record[p];
    const Index id1 = mesh_.record_quad[r], id2 = mesh_.record_quad[mesh_.record_next[r]];
    auto rotate_to = [p](std::array<Index, 4> q) {
      while (q[0] != p) std::rotate(q.begin(), q.begin() + 1, q.end());
      return q;
    };
    const auto q1 = rotate_to(mesh_.quads[id1]), q2 = rotate_to(mesh_.quads[id2]);
    if (q1[1] != q2[3] || q1[3] != q2[1]) continue;
    // (p, a, x, b) and (p, b, y, a) become (a, x, b, y).
    mesh_.quads[id1] = {q1[1], q1[2], q1[3], q2[2]};
    mesh_.quads[id2] = {kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex};
    mesh_.rebuild_records();
    any = true;
  }
  if (any) collapse_doublets();
}

void Paver::final_smoothing() {
  const auto total = static_cast<Index>(mesh_.points.size());
  std::vector<std::uint8_t> active(total, 0), next(total, 0);
  for (Index p = mesh_.fixed_count; p < total; ++p) active[p] = 1;
  const double still = 5e-3 * size_;
  for (int sweep = 0; sweep < options_.final_smoothing_iterations; ++sweep) {
    bool any = false;
    std::fill(next.begin(), next.end(), 0);
    for (Index p = mesh_.fixed_count; p < total; ++p) {
      if (!active[p]) continue;
      if (smooth_point(p) > still) {
        any = true;
        mesh_.for_each_quad(p, [&](Index q) {
          for (const Index v : mesh_.quads[q]) next[v] = 1;
        });
      }
    }
    active.swap(next);
    if (!any) break;
  }
  // Local optimisation of the worst quads.
  for (int pass = 0; pass < 3; ++pass) {
    bool any = false;
    for (const auto& q : mesh_.quads) {
      if (q[0] == kInvalidIndex) continue;
      const auto& P = mesh_.points;
      if (scaled_jacobian(P[q[0]], P[q[1]], P[q[2]], P[q[3]]) >= 0.7) continue;
      for (const Index v : q) any |= optimize_point(v);
    }
    if (!any) break;
  }
  // Untangling: quads still (nearly) inverted get their free points, and those of the
  // quads around them, optimised with longer steps.
  for (int pass = 0; pass < 30; ++pass) {
    std::vector<Index> pts;
    for (const auto& q : mesh_.quads) {
      if (q[0] == kInvalidIndex) continue;
      const auto& P = mesh_.points;
      if (scaled_jacobian(P[q[0]], P[q[1]], P[q[2]], P[q[3]]) > 0.05) continue;
      for (const Index v : q) {
        pts.push_back(v);
        mesh_.for_each_quad(v, [&](Index r) {
          for (const Index w : mesh_.quads[r]) pts.push_back(w);
        });
      }
    }
    if (pts.empty()) break;
    std::sort(pts.begin(), pts.end());
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    for (const Index v : pts) optimize_point(v, pass % 2 == 0 ? 0.5 : 0.15);
  }
}

}  // namespace structmesh::paving
