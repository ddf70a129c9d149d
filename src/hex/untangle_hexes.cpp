// untangle_hexes(): the continuation method of Garanzha et al. 2021 ("Foldover-free maps in
// 50 lines of code", the 3D energy) on the corner tets of hexes. Each corner o with edges to
// i, j, k (Verdict's order, positive for a VTK-ordered cube) has the Jacobian
// J = [p_i - p_o, p_j - p_o, p_k - p_o] / size, and the energy
//   E = sum over corners of (1 - θ) |J|² / χ(det J, ε)^(2/3) + θ (det J² + 1) / χ(det J, ε),
//   χ(D, ε) = (D + sqrt(ε² + D²)) / 2,
// is finite for inverted corners while ε > 0 and tends to a barrier as ε -> 0: minimising it
// while ε shrinks pulls all corners positive without a feasible start. Written here (as the
// 2D version in quad2d/untangle_quads.cpp) because no Debian library untangles hex meshes;
// LBFGS++ does the minimisation.
//
// The energy is evaluated per hex in parallel (TBB) into a buffer of per-node gradients, which
// are then summed per free point in a fixed order: the result does not depend on the thread
// count.
#include "hex/untangle_hexes.hpp"
#include "mesh/foldover_free.hpp"
#include "structmesh/quality.hpp"

#include <Eigen/Geometry>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace structmesh::hex_detail {
namespace {

// Verdict's corner samples and the node signs of its centre sample (quality.hpp); a quarter
// of each axis is an edge of a cube's centre "corner".
using hex_jacobian_sample::kAxisSigns;
using hex_jacobian_sample::kCorners;
// Hexes per parallel block; the blocks are fixed, so sums do not depend on the threads.
constexpr std::size_t kBlock = 512;

// The hexes that use a free point, their nodes' positions (in units of size) and, per free
// point, where its gradient contributions lie in the per-hex buffer.
class HexEnergy {
 public:
  HexEnergy(const std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes, std::span<const Index> free,
            double size)
      : points_(points), free_(free), inv_size_(1.0 / size), origin_(points[free[0]]) {
    std::vector<Index> slot(points.size(), kInvalidIndex);
    for (std::size_t k = 0; k < free.size(); ++k) slot[free[k]] = static_cast<Index>(k);
    for (const auto& h : hexes) {
      if (std::none_of(h.begin(), h.end(), [&](Index v) { return slot[v] != kInvalidIndex; })) continue;
      hexes_.push_back(h);
      std::array<Index, 8> s;
      for (int i = 0; i < 8; ++i) s[i] = slot[h[i]];
      slots_.push_back(s);
    }
    // Per free point, the (hex, node) entries of the gradient buffer, in hex order.
    incidence_offsets_.assign(free.size() + 1, 0);
    for (const auto& s : slots_)
      for (const Index k : s)
        if (k != kInvalidIndex) ++incidence_offsets_[k + 1];
    for (std::size_t k = 0; k < free.size(); ++k) incidence_offsets_[k + 1] += incidence_offsets_[k];
    incidence_.resize(incidence_offsets_.back());
    std::vector<std::size_t> fill(incidence_offsets_.begin(), incidence_offsets_.end() - 1);
    for (std::size_t h = 0; h < slots_.size(); ++h)
      for (int i = 0; i < 8; ++i)
        if (slots_[h][i] != kInvalidIndex) incidence_[fill[slots_[h][i]]++] = static_cast<Index>(8 * h + i);
    node_gradient_.resize(8 * hexes_.size());
    block_sums_.resize((hexes_.size() + kBlock - 1) / kBlock);
  }

  Eigen::VectorXd initial() const {
    Eigen::VectorXd x(3 * static_cast<Eigen::Index>(free_.size()));
    for (std::size_t k = 0; k < free_.size(); ++k)
      x.segment<3>(3 * static_cast<Eigen::Index>(k)) = (points_[free_[k]] - origin_) * inv_size_;
    return x;
  }
  void write(const Eigen::VectorXd& x, std::vector<Vec3>& points) const {
    for (std::size_t k = 0; k < free_.size(); ++k)
      points[free_[k]] = origin_ + Vec3(x.segment<3>(3 * static_cast<Eigen::Index>(k))) / inv_size_;
  }

  double eps = 0;

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    for_blocks([&](std::size_t b) {
      double total = 0;
      for (std::size_t h = b * kBlock; h < std::min(hexes_.size(), (b + 1) * kBlock); ++h) {
        const std::array<Vec3, 8> p = nodes(x, h);
        std::array<Vec3, 8> g;
        g.fill(Vec3::Zero());
        Vec3 ga, gb, gd;
        for (const auto& [o, i, j, k] : kCorners) {
          total += detail::foldover_energy_3d(eps, p[i] - p[o], p[j] - p[o], p[k] - p[o], ga, gb, gd);
          g[i] += ga, g[j] += gb, g[k] += gd, g[o] -= ga + gb + gd;
        }
        const auto axes = centre_axes(p);
        total += detail::foldover_energy_3d(eps, axes[0], axes[1], axes[2], ga, gb, gd);
        for (int i = 0; i < 8; ++i)
          g[i] += 0.25 * (kAxisSigns[i][0] * ga + kAxisSigns[i][1] * gb + kAxisSigns[i][2] * gd);
        std::copy(g.begin(), g.end(), node_gradient_.begin() + static_cast<std::ptrdiff_t>(8 * h));
      }
      block_sums_[b] = total;
    });
    grad.resize(x.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, free_.size(), kBlock), [&](const auto& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        Vec3 sum = Vec3::Zero();
        for (std::size_t e = incidence_offsets_[k]; e < incidence_offsets_[k + 1]; ++e)
          sum += node_gradient_[incidence_[e]];
        grad.segment<3>(3 * static_cast<Eigen::Index>(k)) = sum;
      }
    });
    double total = 0;
    for (const double s : block_sums_) total += s;
    return total;
  }

  double min_det(const Eigen::VectorXd& x) {
    for_blocks([&](std::size_t b) {
      double smallest = std::numeric_limits<double>::infinity();
      for (std::size_t h = b * kBlock; h < std::min(hexes_.size(), (b + 1) * kBlock); ++h) {
        const std::array<Vec3, 8> p = nodes(x, h);
        for (const auto& [o, i, j, k] : kCorners)
          smallest = std::min(smallest, (p[i] - p[o]).dot((p[j] - p[o]).cross(p[k] - p[o])));
        const auto axes = centre_axes(p);
        smallest = std::min(smallest, axes[0].dot(axes[1].cross(axes[2])));
      }
      block_sums_[b] = smallest;
    });
    return block_sums_.empty() ? 0.0 : *std::min_element(block_sums_.begin(), block_sums_.end());
  }

 private:
  template <class F>
  void for_blocks(F&& f) {
    tbb::parallel_for(std::size_t{0}, block_sums_.size(), f);
  }
  std::array<Vec3, 8> nodes(const Eigen::VectorXd& x, std::size_t h) const {
    std::array<Vec3, 8> p;
    for (int i = 0; i < 8; ++i) {
      const Index s = slots_[h][i];
      p[i] = s == kInvalidIndex ? Vec3((points_[hexes_[h][i]] - origin_) * inv_size_)
                                : Vec3(x.segment<3>(3 * static_cast<Eigen::Index>(s)));
    }
    return p;
  }
  static std::array<Vec3, 3> centre_axes(const std::array<Vec3, 8>& p) {
    std::array<Vec3, 3> axis{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    for (int i = 0; i < 8; ++i)
      for (int a = 0; a < 3; ++a) axis[a] += 0.25 * kAxisSigns[i][a] * p[i];
    return axis;
  }

  const std::vector<Vec3>& points_;
  std::span<const Index> free_;
  double inv_size_;
  Vec3 origin_;
  std::vector<std::array<Index, 8>> hexes_, slots_;
  std::vector<std::size_t> incidence_offsets_;
  std::vector<Index> incidence_;  // 8 * hex + node
  std::vector<Vec3> node_gradient_;
  std::vector<double> block_sums_;
};

}  // namespace

HexUntangleResult untangle_hexes(std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes,
                                 std::span<const Index> free, double size, int max_steps) {
  HexUntangleResult result;
  if (free.empty() || !(size > 0)) return result;
  // The unknowns are the free points in units of `size` from the first free point, so that
  // L-BFGS's first step (of unit length) is about one edge.
  HexEnergy energy(points, hexes, free, size);
  Eigen::VectorXd x = energy.initial();
  detail::FoldoverFreeSettings loop;
  loop.max_steps = max_steps;
  // Armijo, and back to the start of a step whose line search failed: with Wolfe's
  // curvature test the flattened hexes of a thin tip stopped every step at once.
  loop.wolfe = false;
  loop.restore_on_failure = true;
  const detail::FoldoverFreeResult minimised = detail::minimize_foldover_free(
      x, energy.eps, [&](const Eigen::VectorXd& v, Eigen::VectorXd& g) { return energy(v, g); },
      [&](const Eigen::VectorXd& v) { return energy.min_det(v); }, loop);
  result.min_det_before = minimised.min_det_before;
  result.min_det_after = minimised.min_det_after;
  result.outer_iterations = minimised.outer_iterations;
  energy.write(x, points);
  return result;
}

}  // namespace structmesh::hex_detail
