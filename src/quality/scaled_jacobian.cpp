// Scaled Jacobians of quads and hexes with Verdict's definitions (V_QuadMetric.cpp,
// V_HexMetric.cpp, as built into VTK 9.1's vtkMeshQuality), so our numbers compare
// with ParaView, HexaLab and the published tables (§3.4.3 Table 3.4, §5.3 Table 5.2).
#include "structmesh/quality.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace structmesh {

namespace {

// Verdict's VERDICT_DBL_MIN: its zero-length tests are absolute, not relative to
// the element size; we keep them so that "invalid" means what it means in Verdict.
constexpr double kVerdictDblMin = 1.0e-30;

// Verdict's tri_scaled_jacobian: twice the area times 2/sqrt(3) over the largest
// product of two edge lengths. It uses the cross product's length, so it is never
// negative: Verdict cannot see a flipped triangle without a reference normal.
double triangle_scaled_jacobian(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, bc = c - b;
  const double lab = ab.norm(), lac = ac.norm(), lbc = bc.norm();
  const double largest_product = std::max({lab * lac, lac * lbc, lab * lbc});
  if (largest_product < kVerdictDblMin) return 0.0;
  return ab.cross(ac).norm() * (2.0 / std::sqrt(3.0)) / largest_product;
}

// The 9 samples of Verdict's hex_scaled_jacobian: the centre sample and the 8 corners.
// nullopt when any of them is degenerate: Verdict then returns VERDICT_DBL_MAX
// whatever the other samples are, so the order of evaluation does not matter.
std::optional<std::pair<double, double>> hex_samples(const std::array<Vec3, 8>& p) {
  const std::optional<double> centre = hex_jacobian_sample::centre(p);
  if (!centre) return std::nullopt;
  double corner_min = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 8; ++c) {
    const std::optional<double> sample = hex_jacobian_sample::corner(p, c);
    if (!sample) return std::nullopt;
    corner_min = std::min(corner_min, *sample);
  }
  return std::pair{std::min(*centre, corner_min), corner_min};
}

}  // namespace

double quad_scaled_jacobian(const std::array<Vec3, 4>& p, const Vec3* reference_normal) {
  // Verdict's is_collapsed_quad: only node 3 == node 2 (exact coordinates) makes a
  // triangle; other repeated nodes fall to the zero-length-edge rule below.
  if (p[3] == p[2]) {
    const double sj = triangle_scaled_jacobian(p[0], p[1], p[2]);
    if (reference_normal != nullptr && (p[1] - p[0]).cross(p[2] - p[0]).dot(*reference_normal) < 0) return -sj;
    return sj;
  }
  const std::array<Vec3, 4> edges{p[1] - p[0], p[2] - p[1], p[3] - p[2], p[0] - p[3]};
  std::array<double, 4> lengths{};
  for (int i = 0; i < 4; ++i) {
    lengths[i] = edges[i].norm();
    if (lengths[i] < kVerdictDblMin) return 0.0;  // Verdict's answer for a zero-length edge
  }
  // Verdict's normal: cross product of the principal axes (= 2x the diagonals'
  // cross product), left at zero when it vanishes (VerdictVector::normalize).
  Vec3 normal = (edges[0] - edges[2]).cross(edges[1] - edges[3]);
  if (reference_normal != nullptr && reference_normal->norm() != 0) normal = *reference_normal;
  if (const double length = normal.norm(); length != 0) normal /= length;
  double result = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i) {
    const int previous = (i + 3) % 4;
    const double corner_area = normal.dot(edges[previous].cross(edges[i]));
    result = std::min(result, corner_area / (lengths[i] * lengths[previous]));
  }
  return result;
}

std::optional<double> hex_scaled_jacobian(const std::array<Vec3, 8>& corners) {
  const auto samples = hex_samples(corners);
  if (!samples) return std::nullopt;
  return samples->first;
}

std::optional<double> hex_corner_scaled_jacobian(const std::array<Vec3, 8>& corners) {
  const auto samples = hex_samples(corners);
  if (!samples) return std::nullopt;
  return samples->second;
}

}  // namespace structmesh
