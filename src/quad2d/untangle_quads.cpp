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

#include "mesh/foldover_free.hpp"
#include "structmesh/quality.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace structmesh::paving {
namespace {

constexpr int kPolishSteps = 3;
// L-BFGS iterations per polish step: 100 gave the Key's parts the same results as 300
// in two thirds of the time.
constexpr int kPolishIterations = 100;
constexpr Index kPolishLimit = 20000;

struct Corner {
  Index a, b, c;  // corner point, next point, previous point
};

}  // namespace

UntangleResult untangle_quads(std::vector<Vec2>& points, std::span<const std::array<Index, 4>> quads,
                              std::span<const Index> free, double size, int max_steps, const CornerEnergy& energy_kind,
                              int max_iterations) {
  const double beta = energy_kind.legs, theta = energy_kind.area;
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
      const double c = detail::foldover_chi(eps, det), dc = detail::foldover_chi_derivative(eps, det);
      const double lu = std::max(u.norm(), 1e-12), lw = std::max(w.norm(), 1e-12);
      const double shape = 2 * lu * lw + beta * (lu - lw) * (lu - lw);
      const double numerator = (1 - theta) * shape + theta * (det * det + 1);
      total += numerator / c;
      // dE/d det and dE/du, dE/dw (det = u.x w.y - u.y w.x).
      const double d_det = -numerator * dc / (c * c) + theta * 2 * det / c;
      const Vec2 fu = ((2 * lw + 2 * beta * (lu - lw)) / lu) * u, fw = ((2 * lu + 2 * beta * (lw - lu)) / lw) * w;
      const Vec2 du = ((1 - theta) / c) * fu + d_det * Vec2(w.y(), -w.x());
      const Vec2 dw = ((1 - theta) / c) * fw + d_det * Vec2(-u.y(), u.x());
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

  detail::FoldoverFreeSettings settings;
  settings.max_steps = max_steps;
  settings.max_iterations = max_iterations;
  const detail::FoldoverFreeResult minimised = detail::minimize_foldover_free(x, eps, energy, min_det, settings);
  result.min_det_before = minimised.min_det_before;
  result.outer_iterations = minimised.outer_iterations;
  const Eigen::VectorXd& best = x;
  const double best_detmin = minimised.min_det_after;
  for (std::size_t k = 0; k < free.size(); ++k) points[free[k]] = Vec2(best[2 * k], best[2 * k + 1]);
  result.min_det_after = best_detmin;
  result.valid = best_detmin > 0;
  return result;
}

namespace {

struct QualitySummary {
  double min = std::numeric_limits<double>::infinity();
  double mean = 0;
};

QualitySummary summarize(std::span<const Vec2> points, std::span<const std::array<Index, 4>> quads) {
  const Vec3 up(0, 0, 1);
  QualitySummary summary;
  std::size_t count = 0;
  double sum = 0;
  for (const auto& q : quads) {
    if (q[0] == kInvalidIndex) continue;
    std::array<Vec3, 4> c;
    for (int m = 0; m < 4; ++m) c[m] = Vec3(points[q[m]].x(), points[q[m]].y(), 0);
    double sj = quad_scaled_jacobian(c, &up);
    if (std::isnan(sj)) sj = -std::numeric_limits<double>::infinity();
    summary.min = std::min(summary.min, sj);
    sum += sj;
    ++count;
  }
  summary.mean = count > 0 ? sum / static_cast<double>(count) : 0;
  return summary;
}

}  // namespace

double min_scaled_jacobian(std::span<const Vec2> points, std::span<const std::array<Index, 4>> quads) {
  return summarize(points, quads).min;
}

double mean_scaled_jacobian(std::span<const Vec2> points, std::span<const std::array<Index, 4>> quads) {
  return summarize(points, quads).mean;
}

double polish_quads(std::vector<Vec2>& points, std::span<const std::array<Index, 4>> quads, Index fixed_count,
                    double size, double threshold, const CornerEnergy& energy) {
  // Only meshes of a part of a few thousand quads: the chords of polar blocks and the
  // grid lines need the whole part to even out, and on larger parts the optimisation
  // costs more than paving them (measured on the Key at 2M quads in 64 parts: polishing
  // 20 rings around the bad quads of 30k-quad parts tripled the meshing time and lifted
  // none of them over the threshold).
  const auto n = static_cast<Index>(points.size());
  std::vector<Index> free;
  if (n - std::min(n, fixed_count) <= kPolishLimit)
    for (Index p = fixed_count; p < n; ++p) free.push_back(p);
  const QualitySummary before = summarize(points, quads);
  if (free.empty()) return before.min;
  std::vector<Vec2> kept(free.size());
  for (std::size_t k = 0; k < free.size(); ++k) kept[k] = points[free[k]];
  // A few continuation steps: what they do not fix, the part's fallback (paving) will.
  // A folded start is untangled with the conformal energy first (an energy with a
  // small leg weight alone leaves folds in place: measured on the Key's polar parts).
  if (!(before.min > 0)) untangle_quads(points, quads, free, size, kPolishSteps, kConformalEnergy, kPolishIterations);
  untangle_quads(points, quads, free, size, kPolishSteps, energy, kPolishIterations);
  const QualitySummary after = summarize(points, quads);
  // Kept when the worst quad improves, or when the mean does without the worst
  // falling below both its old value and the threshold.
  if (after.min > before.min || (after.min >= std::min(before.min, threshold) && after.mean > before.mean))
    return after.min;
  for (std::size_t k = 0; k < free.size(); ++k) points[free[k]] = kept[k];
  return before.min;
}

}  // namespace structmesh::paving
