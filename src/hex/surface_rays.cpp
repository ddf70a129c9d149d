#include "surface_rays.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Geometry>

#include <iterator>
#include <limits>
#include <vector>

namespace structmesh::hex_detail {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
using Point = Kernel::Point_3;
Point to_point(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
}  // namespace

struct SurfaceRays::Impl {
  std::vector<Triangle> triangles;
  Tree tree;
  const TriMesh& surface;
  explicit Impl(const TriMesh& s) : surface(s) {
    triangles.reserve(s.triangles.size());
    for (const auto& t : s.triangles)
      triangles.emplace_back(to_point(s.points[t[0]]), to_point(s.points[t[1]]), to_point(s.points[t[2]]));
    tree.insert(triangles.begin(), triangles.end());
    tree.build();
  }
};

SurfaceRays::SurfaceRays(const TriMesh& surface) : impl_(std::make_unique<Impl>(surface)) {}
SurfaceRays::~SurfaceRays() = default;

Vec3 triangle_barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double area = n.squaredNorm();
  if (!(area > 0)) return Vec3(1, 0, 0);
  const double u = (b - p).cross(c - p).dot(n) / area;
  const double v = (c - p).cross(a - p).dot(n) / area;
  return Vec3(u, v, 1 - u - v);
}

bool SurfaceRays::nearest_hit(const Vec3& p, const Vec3& direction, double reach, Vec3& hit, Index& triangle,
                              Vec3& barycentric) const {
  const Vec3 d = direction.normalized() * reach;
  const Kernel::Segment_3 segment(to_point(p - d), to_point(p + d));
  using Intersection = Tree::Intersection_and_primitive_id<Kernel::Segment_3>::Type;
  std::vector<Intersection> hits;
  impl_->tree.all_intersections(segment, std::back_inserter(hits));
  double best = std::numeric_limits<double>::infinity();
  bool found = false;
  for (const Intersection& h : hits) {
    // A segment lying in a triangle's plane meets it in a segment: its nearer end counts.
    std::vector<Point> candidates;
    if (const Point* q = boost::get<Point>(&h.first))
      candidates.push_back(*q);
    else if (const Kernel::Segment_3* s = boost::get<Kernel::Segment_3>(&h.first)) {
      candidates.push_back(s->source());
      candidates.push_back(s->target());
    }
    for (const Point& q : candidates) {
      const Vec3 x(q.x(), q.y(), q.z());
      const double distance = (x - p).squaredNorm();
      if (distance < best) {
        best = distance;
        hit = x;
        triangle = static_cast<Index>(h.second - impl_->triangles.begin());
        found = true;
      }
    }
  }
  if (found) {
    const auto& t = impl_->surface.triangles[triangle];
    barycentric = triangle_barycentric(hit, impl_->surface.points[t[0]], impl_->surface.points[t[1]],
                                       impl_->surface.points[t[2]]);
  }
  return found;
}

}  // namespace structmesh::hex_detail
