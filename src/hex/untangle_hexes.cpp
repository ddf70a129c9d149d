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
// The energy is evaluated per hex in fixed parallel blocks (mesh/free_point_elements.hpp): the
// result does not depend on the thread count.
#include "hex/untangle_hexes.hpp"
#include "mesh/foldover_free.hpp"
#include "mesh/free_point_elements.hpp"
#include "structmesh/quality.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace structmesh::hex_detail {
namespace {

// Verdict's corner samples and the node signs of its centre sample (quality.hpp); a quarter
// of each axis is an edge of a cube's centre "corner".
using hex_jacobian_sample::kAxisSigns;
using hex_jacobian_sample::kCorners;
// The joint energy of the hexes that use a free point (their corner and centre samples).
class HexEnergy {
 public:
  HexEnergy(const std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes, std::span<const Index> free,
            double size)
      : layout_(points, free, size) {
    for (const auto& h : hexes)
      if (layout_.uses_free_point(h)) layout_.add(h);
    layout_.finish();
  }

  Eigen::VectorXd initial() const { return layout_.initial(); }
  void write(const Eigen::VectorXd& x, std::vector<Vec3>& points) const { layout_.write(x, points); }

  double eps = 0;

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    return layout_.sum_with_gradient(
        [&](std::size_t h) {
          const std::array<Vec3, 8> p = layout_.nodes(x, h);
          Vec3* g = layout_.node_gradient(h);
          std::fill(g, g + 8, Vec3::Zero());
          double total = 0;
          Vec3 ga, gb, gd;
          for (const auto& [o, i, j, k] : kCorners) {
            total += detail::foldover_energy_3d(eps, p[i] - p[o], p[j] - p[o], p[k] - p[o], ga, gb, gd);
            g[i] += ga, g[j] += gb, g[k] += gd, g[o] -= ga + gb + gd;
          }
          const auto axes = centre_axes(p);
          total += detail::foldover_energy_3d(eps, axes[0], axes[1], axes[2], ga, gb, gd);
          for (int i = 0; i < 8; ++i)
            g[i] += 0.25 * (kAxisSigns[i][0] * ga + kAxisSigns[i][1] * gb + kAxisSigns[i][2] * gd);
          return total;
        },
        grad);
  }

  double min_det(const Eigen::VectorXd& x) {
    return layout_.minimum([&](std::size_t h) {
      const std::array<Vec3, 8> p = layout_.nodes(x, h);
      double smallest = std::numeric_limits<double>::infinity();
      for (const auto& [o, i, j, k] : kCorners)
        smallest = std::min(smallest, (p[i] - p[o]).dot((p[j] - p[o]).cross(p[k] - p[o])));
      const auto axes = centre_axes(p);
      return std::min(smallest, axes[0].dot(axes[1].cross(axes[2])));
    });
  }

 private:
  static std::array<Vec3, 3> centre_axes(const std::array<Vec3, 8>& p) {
    std::array<Vec3, 3> axis{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    for (int i = 0; i < 8; ++i)
      for (int a = 0; a < 3; ++a) axis[a] += 0.25 * kAxisSigns[i][a] * p[i];
    return axis;
  }

  detail::FreePointElements<8> layout_;
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
