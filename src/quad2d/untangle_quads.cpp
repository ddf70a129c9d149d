// Untangling by the continuation method of Garanzha et al. 2021 ("Foldover-free maps in
// 50 lines of code"). Each quad corner (a; next b, previous c) is a triangle whose
// Jacobian against a right angle of legs h is J = [b - a, c - a] / h. The energy
//   E = sum over corners of ((1 - θ) |J|² + θ (det J² + 1)) / χ(det J, ε),
//   χ(D, ε) = (D + sqrt(ε² + D²)) / 2,
// is finite for inverted corners (χ > 0 for every D while ε > 0) and tends to the
// barrier 1/D as ε -> 0, so minimising it while ε shrinks pulls every corner positive
// without a feasible start. The paving's own untangling is a per-point pattern search
// (paving_smooth.cpp), which stalls where a whole zone of quads folded over together;
// this one moves the zone's points jointly with L-BFGS (LBFGS++).
#include "quad2d/untangle_quads.hpp"

#include "structmesh/quality.hpp"

#include <LBFGS.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>

namespace structmesh::paving {
namespace {

constexpr double kTheta = 1.0 / 128;  // weight of the area term (the paper's value)
constexpr int kMaxInner = 300;
constexpr int kPolishSteps = 8;
constexpr int kPolishRings = 20;
constexpr Index kPolishWholeLimit = 20000;

double chi(double eps, double det) {
  // The second form avoids cancellation for negative det.
  if (det > 0) return 0.5 * (det + std::sqrt(eps * eps + det * det));
  return 0.5 * eps * eps / (std::sqrt(eps * eps + det * det) - det);
}

double chi_derivative(double eps, double det) { return 0.5 + det / (2 * std::sqrt(eps * eps + det * det)); }

struct Corner {
  Index a, b, c;  // corner point, next point, previous point
};

}  // namespace

UntangleResult untangle_quads(std::vector<Vec2>& points, std::span<const std::array<Index, 4>> quads,
                              std::span<const Index> free, double size, int max_steps) {
  UntangleResult result;
  if (free.empty() || !(size > 0)) return result;
  // Variable slot of each free point.
  std::vector<Index> slot(points.size(), kInvalidIndex);
  for (std::size_t k = 0; k < free.size(); ++k) slot[free[k]] = static_cast<Index>(k);
  std::vector<Corner> corners;
  for (const auto& q : quads) {
    if (q[0] == kInvalidIndex) continue;
    if (slot[q[0]] == kInvalidIndex && slot[q[1]] == kInvalidIndex && slot[q[2]] == kInvalidIndex &&
        slot[q[3]] == kInvalidIndex)
      continue;
    for (int i = 0; i < 4; ++i) corners.push_back({q[i], q[(i + 1) % 4], q[(i + 3) % 4]});
  }
  const double inv_h = 1.0 / size;
  const auto n = static_cast<Eigen::Index>(2 * free.size());
  Eigen::VectorXd x(n);
  for (std::size_t k = 0; k < free.size(); ++k) x[2 * k] = points[free[k]].x(), x[2 * k + 1] = points[free[k]].y();

  const auto position = [&](const Eigen::VectorXd& v, Index p) {
    const Index s = slot[p];
    return s == kInvalidIndex ? points[p] : Vec2(v[2 * s], v[2 * s + 1]);
  };
  const auto min_det = [&](const Eigen::VectorXd& v) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const Corner& k : corners) {
      const Vec2 a = position(v, k.a), u = (position(v, k.b) - a) * inv_h, w = (position(v, k.c) - a) * inv_h;
      smallest = std::min(smallest, u.x() * w.y() - u.y() * w.x());
    }
    return smallest;
  };

  double eps = 0;
  const auto energy = [&](const Eigen::VectorXd& v, Eigen::VectorXd& grad) {
    grad.setZero(n);
    double total = 0;
    for (const Corner& k : corners) {
      const Vec2 a = position(v, k.a), u = (position(v, k.b) - a) * inv_h, w = (position(v, k.c) - a) * inv_h;
      const double det = u.x() * w.y() - u.y() * w.x();
      const double c = chi(eps, det), dc = chi_derivative(eps, det);
      const double frobenius = u.squaredNorm() + w.squaredNorm();
      const double numerator = (1 - kTheta) * frobenius + kTheta * (det * det + 1);
      total += numerator / c;
      // dE/d det and dE/du, dE/dw (det = u.x w.y - u.y w.x).
      const double d_det = -numerator * dc / (c * c) + kTheta * 2 * det / c;
      const Vec2 du = (2 * (1 - kTheta) / c) * u + d_det * Vec2(w.y(), -w.x());
      const Vec2 dw = (2 * (1 - kTheta) / c) * w + d_det * Vec2(-u.y(), u.x());
      const auto add = [&](Index p, const Vec2& g) {
        const Index s = slot[p];
        if (s == kInvalidIndex) return;
        grad[2 * s] += g.x() * inv_h;
        grad[2 * s + 1] += g.y() * inv_h;
      };
      add(k.b, du);
      add(k.c, dw);
      add(k.a, -(du + dw));
    }
    return total;
  };

  double detmin = min_det(x);
  result.min_det_before = detmin;
  eps = std::sqrt(1e-12 + 0.04 * std::pow(std::min(detmin, 0.0), 2));
  Eigen::VectorXd best = x;
  double best_detmin = detmin;
  LBFGSpp::LBFGSParam<double> param;  // must outlive the solver (held by reference)
  param.m = 8;
  param.epsilon = 1e-8;
  param.epsilon_rel = 0;
  param.past = 2;
  param.delta = 1e-7;
  param.max_iterations = kMaxInner;
  param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_WOLFE;
  param.max_linesearch = 40;
  LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchBacktracking> solver(param);
  Eigen::VectorXd gradient(n);
  for (int outer = 0; outer < max_steps; ++outer) {
    result.outer_iterations = outer + 1;
    const double before = energy(x, gradient);
    double after = before;
    try {
      solver.minimize(energy, x, after);
    } catch (const std::exception&) {
      // A line search that cannot progress leaves x at its last accepted point.
      after = energy(x, gradient);
    }
    if (!std::isfinite(after)) {
      x = best;
      break;
    }
    detmin = min_det(x);
    // Until the zone is valid, keep the placement with the largest smallest corner;
    // once valid, the latest (lower energy: better shaped corners).
    if (detmin > 0 || detmin > best_detmin) best = x, best_detmin = detmin;
    const double sigma = std::max(1 - after / before, 0.1);
    const double mu = (1 - sigma) * chi(eps, detmin);
    eps = detmin < mu ? 2 * std::sqrt(mu * (mu - detmin)) : 1e-10;
    if (detmin > 0 && std::abs(before - after) <= 1e-4 * std::abs(after)) break;
  }
  for (std::size_t k = 0; k < free.size(); ++k) points[free[k]] = Vec2(best[2 * k], best[2 * k + 1]);
  result.min_det_after = best_detmin;
  result.valid = best_detmin > 0;
  return result;
}

double min_scaled_jacobian(std::span<const Vec2> points, std::span<const std::array<Index, 4>> quads) {
  const Vec3 up(0, 0, 1);
  double smallest = std::numeric_limits<double>::infinity();
  for (const auto& q : quads) {
    if (q[0] == kInvalidIndex) continue;
    std::array<Vec3, 4> c;
    for (int m = 0; m < 4; ++m) c[m] = Vec3(points[q[m]].x(), points[q[m]].y(), 0);
    const double sj = quad_scaled_jacobian(c, &up);
    smallest = std::isnan(sj) ? -std::numeric_limits<double>::infinity() : std::min(smallest, sj);
  }
  return smallest;
}

double polish_quads(std::vector<Vec2>& points, std::span<const std::array<Index, 4>> quads, Index fixed_count,
                    double size, double threshold) {
  const Vec3 up(0, 0, 1);
  const auto quality = [&](const std::array<Index, 4>& q) {
    std::array<Vec3, 4> c;
    for (int m = 0; m < 4; ++m) c[m] = Vec3(points[q[m]].x(), points[q[m]].y(), 0);
    return quad_scaled_jacobian(c, &up);
  };
  // Point -> quads (CSR) for growing the zone.
  const auto n = static_cast<Index>(points.size());
  std::vector<Index> offset(n + 1, 0), incident;
  for (const auto& q : quads)
    if (q[0] != kInvalidIndex)
      for (const Index v : q) ++offset[v + 1];
  for (Index p = 0; p < n; ++p) offset[p + 1] += offset[p];
  incident.resize(offset[n]);
  std::vector<Index> fill(offset.begin(), offset.end() - 1);
  for (Index id = 0; id < quads.size(); ++id)
    if (quads[id][0] != kInvalidIndex)
      for (const Index v : quads[id]) incident[fill[v]++] = id;
  std::vector<Index> zone;
  std::vector<std::uint8_t> in_zone(n, 0);
  // Small meshes (a part of a few thousand quads) move as a whole: the chords of
  // polar blocks and the grid lines need room to even out; larger ones only around
  // their bad quads, to bound the cost.
  const bool whole = n - std::min(n, fixed_count) <= kPolishWholeLimit;
  for (const auto& q : quads)
    if (q[0] != kInvalidIndex && (whole || !(quality(q) >= threshold)))
      for (const Index v : q)
        if (!in_zone[v]) in_zone[v] = 1, zone.push_back(v);
  if (zone.empty()) return min_scaled_jacobian(points, quads);
  std::size_t begin = 0;
  for (int ring = 0; ring < (whole ? 0 : kPolishRings); ++ring) {
    const std::size_t end = zone.size();
    for (std::size_t k = begin; k < end; ++k)
      for (Index i = offset[zone[k]]; i < offset[zone[k] + 1]; ++i)
        for (const Index w : quads[incident[i]])
          if (!in_zone[w]) in_zone[w] = 1, zone.push_back(w);
    begin = end;
  }
  std::vector<Index> free;
  for (const Index v : zone)
    if (v >= fixed_count) free.push_back(v);
  std::sort(free.begin(), free.end());
  const double before = min_scaled_jacobian(points, quads);
  if (free.empty()) return before;
  std::vector<Vec2> kept(free.size());
  for (std::size_t k = 0; k < free.size(); ++k) kept[k] = points[free[k]];
  // A few continuation steps: what they do not fix, the part's fallback (paving) will.
  untangle_quads(points, quads, free, size, kPolishSteps);
  const double after = min_scaled_jacobian(points, quads);
  if (after > before) return after;
  for (std::size_t k = 0; k < free.size(); ++k) points[free[k]] = kept[k];
  return before;
}

}  // namespace structmesh::paving
