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
#include "hex/untangle_hexes.hpp"
#include "mesh/foldover_free.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace structmesh::hex_detail {
namespace {

// Verdict's corner samples: corner o and its three edge ends, as in smooth_hex_mesh.cpp.
constexpr std::array<std::array<int, 4>, 8> kCorners{
    {{0, 1, 3, 4}, {1, 2, 0, 5}, {2, 3, 1, 6}, {3, 0, 2, 7}, {4, 7, 5, 0}, {5, 4, 6, 1}, {6, 5, 7, 2}, {7, 6, 4, 3}}};
// The sign of each node in Verdict's principal axes (the centre sample), as in
// smooth_hex_mesh.cpp; a quarter of each axis is an edge of a cube's centre "corner".
constexpr std::array<std::array<double, 3>, 8> kAxisSigns{
    {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}};
// The area term's weight: small, as in the paper (the shape term does the work).
constexpr double kTheta = 1.0 / 128;

}  // namespace

HexUntangleResult untangle_hexes(std::vector<Vec3>& points, std::span<const std::array<Index, 8>> hexes,
                                 std::span<const Index> free, double size, int max_steps) {
  HexUntangleResult result;
  if (free.empty() || !(size > 0)) return result;
  std::vector<Index> slot(points.size(), kInvalidIndex);
  for (std::size_t k = 0; k < free.size(); ++k) slot[free[k]] = static_cast<Index>(k);
  std::vector<std::array<Index, 4>> corners;  // o, i, j, k
  std::vector<std::array<Index, 8>> centres;  // the hexes, for Verdict's centre sample
  for (const auto& h : hexes) {
    if (std::none_of(h.begin(), h.end(), [&](Index v) { return slot[v] != kInvalidIndex; })) continue;
    for (const auto& [o, i, j, k] : kCorners) corners.push_back({h[o], h[i], h[j], h[k]});
    centres.push_back(h);
  }
  // The unknowns are the free points in units of `size` from the first free point, so that
  // L-BFGS's first step (of unit length) is about one edge.
  const double inv_h = 1.0 / size;
  const Vec3 origin = points[free.front()];
  const auto n = static_cast<Eigen::Index>(3 * free.size());
  Eigen::VectorXd x(n);
  for (std::size_t k = 0; k < free.size(); ++k)
    x.segment<3>(3 * static_cast<Eigen::Index>(k)) = (points[free[k]] - origin) * inv_h;
  // Positions in units of size (J = differences of them).
  const auto position = [&](const Eigen::VectorXd& v, Index p) -> Vec3 {
    const Index s = slot[p];
    return s == kInvalidIndex ? Vec3((points[p] - origin) * inv_h)
                              : Vec3(v.segment<3>(3 * static_cast<Eigen::Index>(s)));
  };
  const auto min_det = [&](const Eigen::VectorXd& v) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const auto& c : corners) {
      const Vec3 o = position(v, c[0]);
      const Vec3 a = position(v, c[1]) - o, b = position(v, c[2]) - o, d = position(v, c[3]) - o;
      smallest = std::min(smallest, a.dot(b.cross(d)));
    }
    for (const auto& h : centres) {
      std::array<Vec3, 3> axis{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
      for (int i = 0; i < 8; ++i)
        for (int a = 0; a < 3; ++a) axis[a] += 0.25 * kAxisSigns[i][a] * position(v, h[i]);
      smallest = std::min(smallest, axis[0].dot(axis[1].cross(axis[2])));
    }
    return smallest;
  };

  double eps = 0;
  // The energy of one Jacobian [a b d] and its gradients with respect to a, b and d.
  const auto corner_energy = [&](const Vec3& a, const Vec3& b, const Vec3& d, Vec3& ga, Vec3& gb, Vec3& gd) {
    const Vec3 bd = b.cross(d), da = d.cross(a), ab = a.cross(b);
    const double det = a.dot(bd);
    const double chi_value = detail::foldover_chi(eps, det), chi_slope = detail::foldover_chi_derivative(eps, det);
    const double frobenius = a.squaredNorm() + b.squaredNorm() + d.squaredNorm();
    const double chi_23 = std::cbrt(chi_value * chi_value);
    const double shape = frobenius / chi_23, area = (det * det + 1) / chi_value;
    // dE/d det, then dE/da = 2 (1 - θ) a / χ^(2/3) + dE/d det * (b x d), and so on.
    const double d_det = (1 - kTheta) * (-2.0 / 3.0) * shape * chi_slope / chi_value +
                         kTheta * (2 * det / chi_value - area * chi_slope / chi_value);
    const double stretch = 2 * (1 - kTheta) / chi_23;
    ga = stretch * a + d_det * bd;
    gb = stretch * b + d_det * da;
    gd = stretch * d + d_det * ab;
    return (1 - kTheta) * shape + kTheta * area;
  };
  const auto energy = [&](const Eigen::VectorXd& v, Eigen::VectorXd& grad) {
    grad.setZero(n);
    const auto add = [&](Index p, const Vec3& g) {
      const Index s = slot[p];
      if (s != kInvalidIndex) grad.segment<3>(3 * static_cast<Eigen::Index>(s)) += g;
    };
    double total = 0;
    Vec3 ga, gb, gd;
    for (const auto& c : corners) {
      const Vec3 o = position(v, c[0]);
      total += corner_energy(position(v, c[1]) - o, position(v, c[2]) - o, position(v, c[3]) - o, ga, gb, gd);
      add(c[1], ga);
      add(c[2], gb);
      add(c[3], gd);
      add(c[0], -(ga + gb + gd));
    }
    for (const auto& h : centres) {
      std::array<Vec3, 3> axis{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
      for (int i = 0; i < 8; ++i) {
        const Vec3 p = position(v, h[i]);
        for (int a = 0; a < 3; ++a) axis[a] += 0.25 * kAxisSigns[i][a] * p;
      }
      total += corner_energy(axis[0], axis[1], axis[2], ga, gb, gd);
      for (int i = 0; i < 8; ++i)
        add(h[i], 0.25 * (kAxisSigns[i][0] * ga + kAxisSigns[i][1] * gb + kAxisSigns[i][2] * gd));
    }
    return total;
  };

  detail::FoldoverFreeSettings settings;
  settings.max_steps = max_steps;
  // Armijo, and back to the start of a step whose line search failed: with Wolfe's
  // curvature test the flattened hexes of a thin tip stopped every step at once.
  settings.wolfe = false;
  settings.restore_on_failure = true;
  const detail::FoldoverFreeResult minimised = detail::minimize_foldover_free(x, eps, energy, min_det, settings);
  result.min_det_before = minimised.min_det_before;
  result.min_det_after = minimised.min_det_after;
  result.outer_iterations = minimised.outer_iterations;
  const Eigen::VectorXd& best = x;
  for (std::size_t k = 0; k < free.size(); ++k)
    points[free[k]] = origin + size * Vec3(best.segment<3>(3 * static_cast<Eigen::Index>(k)));
  return result;
}

}  // namespace structmesh::hex_detail
