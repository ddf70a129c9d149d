// solid_moments(): volume, centroid and covariance of the solid a closed triangle
// surface bounds, by the divergence theorem over signed tetrahedra (a few lines; no
// library call needed).
#include "polycube/solid_moments.hpp"

#include <Eigen/Geometry>

namespace structmesh::polycube_detail {

SolidMoments solid_moments(std::span<const Vec3> points, std::span<const std::array<Index, 3>> triangles) {
  BoundingBox3 box;
  for (const auto& t : triangles)
    for (const Index v : t) box.extend(points[v]);
  const Vec3 reference = box.empty() ? Vec3::Zero() : Vec3(0.5 * (box.min + box.max));
  double volume = 0;
  Vec3 first = Vec3::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const auto& t : triangles) {
    const Vec3 a = points[t[0]] - reference, b = points[t[1]] - reference, c = points[t[2]] - reference;
    const double v = a.dot(b.cross(c)) / 6.0;
    const Vec3 s = a + b + c;
    volume += v;
    first += v / 4.0 * s;
    second += v / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  SolidMoments moments;
  moments.volume = volume;
  if (volume == 0) return moments;
  const Vec3 centroid = first / volume;
  moments.centroid = reference + centroid;
  moments.covariance = second / volume - centroid * centroid.transpose();
  return moments;
}

}  // namespace structmesh::polycube_detail
