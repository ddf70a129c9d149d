// polish_hexes(): joint ascent of the worst scaled Jacobian of a few hexes.
//
// The smoothing sweeps move one point at a time and keep a move only if no hex around it
// gets worse than the worst one there. Where two or three points hold each other in place
// (fertility at 18k hexes: a padding hex whose inner edge shrank to a sixth of its outer
// one, with 5 more hexes within 0.02 of it), no single move raises the worst hex, and it
// stays at 0.28. Here the points of such a cluster move together: L-BFGS (LBFGS++) minimises
// the soft minimum
//   F(x) = -(1/k) log sum exp(-k s_i(x))
// over every Verdict sample s_i (8 corners and the centre) of the hexes that use them,
// whose gradient is a weighted sum of the samples' analytic gradients (the weights favour
// the samples near the worst). The shape energy of the joint untangling (untangle_hexes)
// is no substitute: on that cluster it took the worst hex from 0.28 to 0.08.
#include "hex/untangle_hexes.hpp"
#include "mesh/lbfgs_parameters.hpp"
#include "structmesh/quality.hpp"

#include <LBFGS.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace structmesh::hex_detail {
namespace {

// Sharpness of the soft minimum: samples more than about 3/k above the worst hardly count.
// Softer minima trade the worst sample for the ones near it (fertility's worst cluster:
// k = 60 took the worst from 0.280 to 0.278, 200 to 0.287, 3000 to 0.291 per round).
constexpr double kSharpness = 3000.0;

class SoftMinimum {
 public:
  // The unknowns are the free points in units of `size` (the mean edge length) from the
  // first free point, so that L-BFGS's first step, of unit length, is about an edge.
  SoftMinimum(const std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes, std::span<const Index> free,
              double size)
      : points_(points),
        hexes_(hexes),
        free_(free),
        slot_(points.size(), kInvalidIndex),
        size_(size),
        origin_(points[free[0]]) {
    for (std::size_t k = 0; k < free.size(); ++k) slot_[free[k]] = static_cast<Index>(k);
  }

  Eigen::VectorXd initial() const {
    Eigen::VectorXd x(3 * static_cast<Eigen::Index>(free_.size()));
    for (std::size_t k = 0; k < free_.size(); ++k)
      x.segment<3>(3 * static_cast<Eigen::Index>(k)) = (points_[free_[k]] - origin_) / size_;
    return x;
  }

  // The worst sample of the hexes at x (or -infinity if one is degenerate).
  double worst(const Eigen::VectorXd& x) {
    double result = std::numeric_limits<double>::infinity();
    visit(x, [&](double s, const std::array<Vec3, 8>*) { result = std::min(result, s); });
    return result;
  }

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    // Shifted by the worst sample so that the exponentials stay in range.
    const double shift = worst(x);
    grad.setZero(x.size());
    if (!std::isfinite(shift)) return std::numeric_limits<double>::infinity();
    double total = 0;
    visit(x, [&](double s, const std::array<Vec3, 8>* gradient) {
      const double weight = std::exp(-kSharpness * (s - shift));
      total += weight;
      for (int i = 0; i < 8; ++i) {
        const Index k = slot_[(*current_)[static_cast<std::size_t>(i)]];
        if (k != kInvalidIndex) grad.segment<3>(3 * static_cast<Eigen::Index>(k)) -= weight * (*gradient)[i];
      }
    });
    grad *= size_ / total;                        // x is in units of size_
    return std::log(total) / kSharpness - shift;  // minus the soft minimum: L-BFGS minimises
  }

  void write(const Eigen::VectorXd& x, std::vector<Vec3>& points) const {
    for (std::size_t k = 0; k < free_.size(); ++k)
      points[free_[k]] = origin_ + size_ * Vec3(x.segment<3>(3 * static_cast<Eigen::Index>(k)));
  }

 private:
  // Calls f(sample, gradient by node) for each of the 9 samples of every hex; a hex with a
  // degenerate sample is reported once, as -infinity with no gradient.
  template <class F>
  void visit(const Eigen::VectorXd& x, F&& f) {
    std::array<Vec3, 8> p;
    for (const auto& hex : hexes_) {
      current_ = &hex;
      for (std::size_t i = 0; i < 8; ++i) {
        const Index k = slot_[hex[i]];
        p[i] = k == kInvalidIndex ? points_[hex[i]]
                                  : Vec3(origin_ + size_ * Vec3(x.segment<3>(3 * static_cast<Eigen::Index>(k))));
      }
      if (!std::isfinite(hex_samples_with_gradients(p, value_, gradient_))) {
        f(-std::numeric_limits<double>::infinity(), nullptr);
        continue;
      }
      for (std::size_t s = 0; s < 9; ++s) f(value_[s], &gradient_[s]);
    }
  }

  const std::vector<Vec3>& points_;
  std::span<const std::array<Index, 8>> hexes_;
  std::span<const Index> free_;
  std::vector<Index> slot_;
  double size_;
  Vec3 origin_;
  const std::array<Index, 8>* current_ = nullptr;
  std::array<double, 9> value_{};
  std::array<std::array<Vec3, 8>, 9> gradient_{};
};

}  // namespace

HexPolishResult polish_hexes(std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes,
                             std::span<const Index> free, int max_iterations) {
  HexPolishResult result;
  if (free.empty() || hexes.empty()) return result;
  const double size = mean_hex_edge_length(points, hexes);
  if (!(size > 0)) return result;
  SoftMinimum energy(points, hexes, free, size);
  Eigen::VectorXd x = energy.initial();
  result.worst_before = energy.worst(x);
  result.worst_after = result.worst_before;
  if (!std::isfinite(result.worst_before)) return result;
  const LBFGSpp::LBFGSParam<double> param = detail::lbfgs_parameters(1e-10, max_iterations, false);
  LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchBacktracking> solver(param);
  const Eigen::VectorXd start = x;
  double value = 0;
  try {
    solver.minimize(energy, x, value);
  } catch (const std::exception&) {
    // A failed line search leaves x at its last trial point; it is judged like any other.
  }
  const double after = x.allFinite() ? energy.worst(x) : -std::numeric_limits<double>::infinity();
  if (after > result.worst_before) {
    energy.write(x, points);
    result.worst_after = after;
  }
  return result;
}

}  // namespace structmesh::hex_detail
