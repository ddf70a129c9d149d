// SurfaceRays: where a line through a point first meets a triangle surface (CGAL AABB tree
// of the triangles, segment queries; thread-safe). Used to put the polycube grid's boundary
// points on Q along their polycube normal, as §5.2.1 projects along normals.
#pragma once

#include "structmesh/mesh.hpp"

#include <memory>

namespace structmesh::hex_detail {

class SurfaceRays {
 public:
  explicit SurfaceRays(const TriMesh& surface);
  ~SurfaceRays();
  /// The point of the surface on the segment p +- reach * direction nearest to p; false when
  /// the segment misses it. `triangle` and `barycentric` locate the hit.
  bool nearest_hit(const Vec3& p, const Vec3& direction, double reach, Vec3& hit, Index& triangle,
                   Vec3& barycentric) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Barycentric coordinates of p (assumed in the triangle's plane) in triangle abc.
Vec3 triangle_barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace structmesh::hex_detail
