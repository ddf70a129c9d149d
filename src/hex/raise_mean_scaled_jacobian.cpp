// raise_mean_scaled_jacobian(): joint ascent of the mean scaled Jacobian of a hex mesh with
// a floor under every hex.
//
// The smoothing sweeps (smooth_hex_mesh.cpp) move one point at a time and keep a move only if
// no hex around it falls below the worst one there: they raise the worst hex and stop where
// every single move would lower some hex, which leaves the mean short of what the points
// could reach together. On fertility at 18k hexes the sweeps end at a mean of 0.932 however
// many are allowed (100 or 400: the same); moving the interior points jointly here takes it
// to 0.941 with the same worst hex.
//
// L-BFGS (LBFGSpp) minimises
//   F(x) = - sum_h [ softmin_k(s_h1 .. s_h9) + mu sum_i log(s_hi - floor_h) ]
// over the free points, where s_h1 .. s_h9 are the 9 Verdict samples of hex h (8 corners and
// the centre), softmin_k(s) = -(1/k) log sum exp(-k s_i) is a smooth stand-in for the hex's
// score (its worst sample), and the log barrier keeps every sample above the hex's floor.
// A point where a sample reaches its floor scores +infinity, so a line search never accepts
// it. Without the barrier a single hex close to its floor cut every step short (the line
// search is global): fertility gained 0.001 instead of 0.009.
//
// Free points with a normal (boundary points) also pay normal_stiffness (d . n)^2 for their
// offset d from where they started (in units of the mean edge) along it: they slide along
// the surface and leave it only a little; the caller puts them back on it.
#include "hex/untangle_hexes.hpp"
#include "mesh/lbfgs_parameters.hpp"

#include <LBFGS.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace structmesh::hex_detail {
namespace {

// Sharpness k of each hex's soft minimum: within log(9)/k = 0.007 of the worst sample.
constexpr double kSharpness = 300.0;
// Weight mu of the barrier: its pull, mu / gap, matters only within a few hundredths of the floor.
constexpr double kBarrier = 1e-3;
// Hexes per block of the parallel evaluation; the blocks' sums are added in order, so the
// value does not depend on the thread count.
constexpr std::size_t kBlock = 512;
// L-BFGS runs at most this many times (restarted after a failed line search), and is not
// restarted once it has evaluated the energy twice per iteration allowed, nor once a run
// lowered the energy by less than kRestartGain of its value.
constexpr int kRestarts = 10;
constexpr double kRestartGain = 1e-6;

class MeanEnergy {
 public:
  // The unknowns are the free points in units of `size` (the mean edge length), so that
  // L-BFGS's first step, of unit length, is about an edge.
  MeanEnergy(const std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes, std::span<const Index> free,
             std::span<const double> floor, double size, std::span<const Vec3> normal, double normal_stiffness)
      : points_(points),
        normal_(normal),
        normal_stiffness_(normal_stiffness),
        hexes_(hexes),
        free_(free),
        floor_(floor),
        slot_(points.size(), kInvalidIndex),
        size_(size),
        node_gradient_(8 * hexes.size()),
        block_sum_((hexes.size() + kBlock - 1) / kBlock) {
    for (std::size_t k = 0; k < free.size(); ++k) slot_[free[k]] = static_cast<Index>(k);
    // Free point -> the (hex, corner) slots of node_gradient_ that belong to it.
    uses_start_.assign(free.size() + 1, 0);
    for (const auto& hex : hexes)
      for (const Index v : hex)
        if (slot_[v] != kInvalidIndex) ++uses_start_[slot_[v] + 1];
    for (std::size_t k = 0; k < free.size(); ++k) uses_start_[k + 1] += uses_start_[k];
    uses_.resize(uses_start_.back());
    std::vector<std::size_t> next(uses_start_.begin(), uses_start_.end() - 1);
    for (std::size_t h = 0; h < hexes.size(); ++h)
      for (std::size_t i = 0; i < 8; ++i)
        if (const Index k = slot_[hexes[h][i]]; k != kInvalidIndex) uses_[next[k]++] = 8 * h + i;
    if (!normal_.empty()) start_ = initial();
  }

  Eigen::VectorXd initial() const {
    Eigen::VectorXd x(3 * static_cast<Eigen::Index>(free_.size()));
    for (std::size_t k = 0; k < free_.size(); ++k)
      x.segment<3>(3 * static_cast<Eigen::Index>(k)) = points_[free_[k]] / size_;
    return x;
  }

  void write(const Eigen::VectorXd& x, std::vector<Vec3>& points) const {
    for (std::size_t k = 0; k < free_.size(); ++k)
      points[free_[k]] = size_ * Vec3(x.segment<3>(3 * static_cast<Eigen::Index>(k)));
  }

  // The sum of the hexes' scores (their worst samples) at x; -infinity if a hex is at or
  // below its floor.
  double score_sum(const Eigen::VectorXd& x) {
    std::atomic<bool> below{false};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, block_sum_.size()), [&](const auto& blocks) {
      Scratch scratch;
      for (std::size_t b = blocks.begin(); b != blocks.end(); ++b) {
        double sum = 0;
        for (std::size_t h = b * kBlock; h < std::min(hexes_.size(), (b + 1) * kBlock); ++h) {
          const double worst = samples(x, h, scratch);
          if (!(worst > floor_[h])) below.store(true, std::memory_order_relaxed);
          sum += worst;
        }
        block_sum_[b] = sum;
      }
    });
    if (below.load()) return -std::numeric_limits<double>::infinity();
    double total = 0;
    for (const double s : block_sum_) total += s;
    return total;
  }

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    ++evaluations_;
    std::atomic<bool> below{false};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, block_sum_.size()), [&](const auto& blocks) {
      Scratch scratch;
      for (std::size_t b = blocks.begin(); b != blocks.end() && !below.load(std::memory_order_relaxed); ++b) {
        double sum = 0;
        for (std::size_t h = b * kBlock; h < std::min(hexes_.size(), (b + 1) * kBlock); ++h) {
          const double worst = samples(x, h, scratch);
          if (!(worst > floor_[h])) {
            below.store(true, std::memory_order_relaxed);
            break;
          }
          // d softmin / d s_i = w_i / sum w (w_i = exp(-k (s_i - worst))), plus mu / gap_i.
          std::array<double, 9> weight;
          double weights = 0;
          for (int s = 0; s < 9; ++s) weights += weight[s] = std::exp(-kSharpness * (scratch.value[s] - worst));
          sum += worst - std::log(weights) / kSharpness;
          for (int s = 0; s < 9; ++s) {
            const double gap = scratch.value[s] - floor_[h];
            sum += kBarrier * std::log(gap);
            weight[s] = weight[s] / weights + kBarrier / gap;
          }
          for (std::size_t i = 0; i < 8; ++i) {
            Vec3 g = Vec3::Zero();
            for (int s = 0; s < 9; ++s) g += weight[s] * scratch.gradient[s][i];
            node_gradient_[8 * h + i] = g;
          }
        }
        block_sum_[b] = sum;
      }
    });
    grad.setZero(x.size());
    if (below.load()) return std::numeric_limits<double>::infinity();
    double total = 0;
    for (const double s : block_sum_) total += s;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, free_.size(), 1024), [&](const auto& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        Vec3 g = Vec3::Zero();
        for (std::size_t u = uses_start_[k]; u < uses_start_[k + 1]; ++u) g += node_gradient_[uses_[u]];
        grad.segment<3>(3 * static_cast<Eigen::Index>(k)) = -size_ * g;  // x is in units of size_
      }
    });
    // Springs along the surface normal hold the boundary points near the surface: they
    // slide along it freely, and the caller puts them back on it.
    if (!normal_.empty())
      for (std::size_t k = 0; k < free_.size(); ++k) {
        if (normal_[k].squaredNorm() == 0) continue;
        const auto segment = 3 * static_cast<Eigen::Index>(k);
        const double off = (Vec3(x.segment<3>(segment)) - Vec3(start_.segment<3>(segment))).dot(normal_[k]);
        total -= normal_stiffness_ * off * off;
        grad.segment<3>(segment) += 2 * normal_stiffness_ * off * normal_[k];
      }
    // The line search may end on a worse point than one it tried (LBFGSpp throws when it
    // gives up): the best feasible point seen is what counts.
    if (-total < best_value_) best_value_ = -total, best_ = x;
    return -total;
  }

  const Eigen::VectorXd& best() const { return best_; }
  double best_value() const { return best_value_; }
  int evaluations() const { return evaluations_; }

 private:
  struct Scratch {
    std::array<double, 9> value;
    std::array<std::array<Vec3, 8>, 9> gradient;
  };

  // The 9 samples of hex h at x with their gradients by node; returns the worst, or
  // -infinity if one is degenerate.
  double samples(const Eigen::VectorXd& x, std::size_t h, Scratch& scratch) const {
    const auto& hex = hexes_[h];
    std::array<Vec3, 8> p;
    for (std::size_t i = 0; i < 8; ++i) {
      const Index k = slot_[hex[i]];
      p[i] = k == kInvalidIndex ? points_[hex[i]] : Vec3(size_ * Vec3(x.segment<3>(3 * static_cast<Eigen::Index>(k))));
    }
    return hex_samples_with_gradients(p, scratch.value, scratch.gradient);
  }

  const std::vector<Vec3>& points_;
  std::span<const Vec3> normal_;
  double normal_stiffness_;
  Eigen::VectorXd start_;
  std::span<const std::array<Index, 8>> hexes_;
  std::span<const Index> free_;
  std::span<const double> floor_;
  std::vector<Index> slot_;
  double size_;
  std::vector<Vec3> node_gradient_;  // per hex corner: d(its hex's term)/d(the corner's point)
  std::vector<double> block_sum_;
  std::vector<std::size_t> uses_start_, uses_;
  double best_value_ = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_;
  int evaluations_ = 0;
};

}  // namespace

HexMeanAscentResult raise_mean_scaled_jacobian(std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes,
                                               std::span<const Index> free, std::span<const double> floor,
                                               int max_iterations, std::span<const Vec3> normal,
                                               double normal_stiffness) {
  HexMeanAscentResult result;
  if (free.empty() || hexes.empty() || floor.size() != hexes.size()) return result;
  const double size = mean_hex_edge_length(points, hexes);
  if (!(size > 0)) return result;
  MeanEnergy energy(points, hexes, free, floor, size, normal, normal_stiffness);
  Eigen::VectorXd x = energy.initial();
  result.score_sum_before = energy.score_sum(x);
  result.score_sum_after = result.score_sum_before;
  if (!std::isfinite(result.score_sum_before)) return result;
  const LBFGSpp::LBFGSParam<double> param = detail::lbfgs_parameters(1e-8, max_iterations, false);
  // The line search gives up (LBFGSpp throws) where the soft minima bend sharply, long
  // before the gains end: L-BFGS starts again from the best point, with its memory cleared,
  // while that gains.
  double best = std::numeric_limits<double>::infinity();
  for (int start = 0; start < kRestarts && energy.evaluations() < 2 * max_iterations; ++start) {
    LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchBacktracking> solver(param);
    double value = 0;
    try {
      solver.minimize(energy, x, value);
      break;
    } catch (const std::exception&) {
    }
    if (energy.best().size() != x.size() ||
        (std::isfinite(best) && !(energy.best_value() < best - kRestartGain * std::abs(best))))
      break;
    best = energy.best_value();
    x = energy.best();
  }
  result.evaluations = energy.evaluations();
  if (energy.best().size() == x.size()) x = energy.best();
  const double after = x.allFinite() ? energy.score_sum(x) : -std::numeric_limits<double>::infinity();
  if (after > result.score_sum_before) {
    energy.write(x, points);
    result.score_sum_after = after;
  }
  return result;
}

}  // namespace structmesh::hex_detail
