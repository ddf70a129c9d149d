// Volume moments of the solid bounded by a closed triangle surface, shared by the
// principal-axis alignment and the pre-deformation of §4.3 (which keeps volume and
// centroid).
#pragma once

#include "structmesh/mesh.hpp"

#include <Eigen/Core>

#include <array>
#include <span>

namespace structmesh::polycube_detail {

struct SolidMoments {
  double volume = 0;                                     ///< signed: > 0 for outward triangles
  Vec3 centroid = Vec3::Zero();                          ///< of the solid (not of the vertices)
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< E[(p - c)(p - c)^T] over the solid
};

/// Moments of the solid bounded by `triangles` on `points`, by signed tetrahedra on a
/// reference point: for a tetrahedron (0, a, b, c) of volume V, the integral of p is
/// V (a + b + c) / 4 and the integral of p p^T is V / 20 (a a^T + b b^T + c c^T + s s^T)
/// with s = a + b + c. The reference point is the bounding box centre, so the sums do
/// not cancel far from the origin.
SolidMoments solid_moments(std::span<const Vec3> points, std::span<const std::array<Index, 3>> triangles);

}  // namespace structmesh::polycube_detail
