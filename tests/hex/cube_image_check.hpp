// A check of a surface map onto the unit cube for the surface-map tests: the image
// triangles with all three points on one face of the cube that face into it (against the
// face's outward axis, not the function's own measure), the largest distance of an image
// point from the cube's surface, and the largest ratio of a triangle's image area to its
// source area, over the mean ratio (max(a, 1/a)).
#pragma once

#include "structmesh/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace structmesh::test {

struct CubeImageCheck {
  std::size_t inward = 0;
  double off_surface = 0;
  double worst_area_ratio = 1;
};

inline CubeImageCheck check_cube_image(const TriMesh& source, const std::vector<Vec3>& image) {
  CubeImageCheck result;
  for (const Vec3& p : image) {
    const Vec3 inside = p.cwiseMax(0.0).cwiseMin(1.0);
    const double to_face = std::min(inside.minCoeff(), 1 - inside.maxCoeff());
    result.off_surface = std::max(result.off_surface, (p - inside).norm() + to_face);
  }
  std::vector<double> ratio;
  double image_total = 0, source_total = 0;
  for (const auto& t : source.triangles) {
    const Vec3 normal = (image[t[1]] - image[t[0]]).cross(image[t[2]] - image[t[0]]);
    const double source_area =
        (source.points[t[1]] - source.points[t[0]]).cross(source.points[t[2]] - source.points[t[0]]).norm();
    ratio.push_back(normal.norm() / source_area);
    image_total += normal.norm(), source_total += source_area;
    for (int axis = 0; axis < 3; ++axis)
      for (const double side : {0.0, 1.0}) {
        bool on_face = true;
        for (const Index v : t) on_face = on_face && std::abs(image[v][axis] - side) < 1e-9;
        if (!on_face) continue;
        const double outward = side == 1.0 ? normal[axis] : -normal[axis];
        if (!(outward > 0)) ++result.inward;
      }
  }
  for (const double r : ratio) {
    const double a = r * source_total / image_total;
    result.worst_area_ratio = std::max({result.worst_area_ratio, a, 1 / a});
  }
  return result;
}

}  // namespace structmesh::test
