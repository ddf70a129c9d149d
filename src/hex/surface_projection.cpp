// SurfaceProjection: closest points on the input surface, which keep the boundary of the
// smoothed hex mesh on the input (§5.3: the geometric deviation D_g is measured against it).
// A CGAL AABB tree with its distance-query KD tree built up front, so that queries only read
// the tree and may run from TBB tasks at the same time.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <iterator>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace structmesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 to_cgal(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
Vec3 to_vec(const Kernel::Point_3& p) { return {p.x(), p.y(), p.z()}; }

// Barycentric coordinates of q, a point of triangle abc (Ericson, Real-Time Collision
// Detection §3.4), clamped to [0, 1] against rounding. A degenerate triangle is a segment
// (its longest edge) or a point.
Vec3 barycentric(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = q - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double denominator = d00 * d11 - d01 * d01;
  Vec3 weights;
  if (denominator > 1e-12 * d00 * d11) {
    const double v = (d11 * d20 - d01 * d21) / denominator, w = (d00 * d21 - d01 * d20) / denominator;
    weights = {1 - v - w, v, w};
  } else {
    const std::array<Vec3, 3> corner{a, b, c};
    int longest = 0;
    double longest_length = -1;
    for (int i = 0; i < 3; ++i)
      if (const double l = (corner[(i + 1) % 3] - corner[i]).squaredNorm(); l > longest_length)
        longest = i, longest_length = l;
    weights.setZero();
    const int from = longest, to = (longest + 1) % 3;
    const double t = longest_length > 0
                         ? std::clamp((q - corner[from]).dot(corner[to] - corner[from]) / longest_length, 0.0, 1.0)
                         : 0.0;
    weights[from] = 1 - t;
    weights[to] = t;
  }
  weights = weights.cwiseMax(0.0).cwiseMin(1.0);
  return weights / weights.sum();
}

// Barycentric coordinates of a line hit (a point of triangle abc's plane) from signed
// sub-triangle areas, clamped to >= 0 and normalised. Equal to barycentric() up to rounding;
// kept because the hex meshes measured in bench/results/hex.md were made with it, and the
// smoothing of a few models (the screwdriver) is sensitive to that rounding.
Vec3 hit_barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double area = n.squaredNorm();
  if (!(area > 0)) return Vec3(1, 0, 0);
  const double u = (b - p).cross(c - p).dot(n) / area, v = (c - p).cross(a - p).dot(n) / area;
  const Vec3 w = Vec3(u, v, 1 - u - v).cwiseMax(0.0);
  return w / w.sum();
}

// The point of triangle abc closest to p (Ericson, Real-Time Collision Detection §5.1.5:
// the Voronoi regions of the corners, then of the edges, then the face). By hand: CGAL's
// projection computes the triangle's plane and orientation tests each time, and this one
// runs for every candidate of every smoothing try (the closed dog: 18M calls).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denominator = 1 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

// Steps a walk takes before it gives up for the tree's search (a walk crosses a triangle or
// two per smoothing try; this many means a long way off the hint, where the tree is faster).
constexpr int kMaxWalkSteps = 256;

}  // namespace

struct SurfaceProjection::Impl {
  std::vector<Triangle> triangles;  // the tree's primitives point into this vector
  std::vector<std::array<Vec3, 3>> corners;
  std::vector<Index> original;  // the surface's index of each kept triangle
  Tree tree;
  // For the walk: the points of each kept triangle; per surface triangle, its kept index
  // (kInvalidIndex if it was left out); per surface point, the kept triangles around it.
  std::vector<std::array<Index, 3>> kept_points;
  std::vector<Index> kept_of;
  CompressedRows star;
  Vec3 normal(std::size_t kept) const {
    const auto& c = corners[kept];
    return (c[1] - c[0]).cross(c[2] - c[0]);
  }
};

SurfaceProjection::SurfaceProjection(const TriMesh& surface) : impl_(std::make_unique<Impl>()) {
  if (surface.triangles.empty()) throw InputError("SurfaceProjection: the surface has no triangles");
  impl_->triangles.reserve(surface.triangles.size());
  impl_->corners.reserve(surface.triangles.size());
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    std::array<Vec3, 3> corner;
    for (int i = 0; i < 3; ++i) {
      const Index v = surface.triangles[t][i];
      if (v >= surface.points.size())
        throw InputError("SurfaceProjection: triangle " + std::to_string(t) + " refers to point " + std::to_string(v) +
                         " of " + std::to_string(surface.points.size()));
      corner[i] = surface.points[v];
    }
    // A degenerate (collinear) triangle is left out: it adds no point its neighbours do not
    // have, and CGAL's segment-triangle intersection asserts on it. The input surfaces have
    // none (check_surface rejects them), but Q projected onto the polycube has many.
    const Triangle triangle(to_cgal(corner[0]), to_cgal(corner[1]), to_cgal(corner[2]));
    if (triangle.is_degenerate()) continue;
    impl_->corners.push_back(corner);
    impl_->original.push_back(static_cast<Index>(t));
    impl_->triangles.push_back(triangle);
  }
  if (impl_->triangles.empty()) throw InputError("SurfaceProjection: every triangle of the surface is degenerate");
  impl_->kept_of.assign(surface.triangles.size(), kInvalidIndex);
  for (std::size_t k = 0; k < impl_->original.size(); ++k) {
    impl_->kept_of[impl_->original[k]] = static_cast<Index>(k);
    impl_->kept_points.push_back(surface.triangles[impl_->original[k]]);
  }
  impl_->star = build_vertex_elements(std::span<const std::array<Index, 3>>(impl_->kept_points), surface.points.size());
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

SurfaceProjection::~SurfaceProjection() = default;
SurfaceProjection::SurfaceProjection(SurfaceProjection&&) noexcept = default;
SurfaceProjection& SurfaceProjection::operator=(SurfaceProjection&&) noexcept = default;

Vec3 SurfaceProjection::closest_point(const Vec3& p, Index* triangle, Vec3* barycentric_coordinates) const {
  const auto [point, primitive] = impl_->tree.closest_point_and_primitive(to_cgal(p));
  const Vec3 closest = to_vec(point);
  const auto t = static_cast<std::size_t>(primitive - impl_->triangles.cbegin());
  if (triangle) *triangle = impl_->original[t];
  if (barycentric_coordinates) {
    const auto& c = impl_->corners[t];
    *barycentric_coordinates = barycentric(closest, c[0], c[1], c[2]);
  }
  return closest;
}

Vec3 SurfaceProjection::closest_point_walking(const Vec3& p, Index& triangle) const {
  const Impl& impl = *impl_;
  if (triangle >= impl.kept_of.size() || impl.kept_of[triangle] == kInvalidIndex) return closest_point(p, &triangle);
  Index current = impl.kept_of[triangle];
  const auto& start = impl.corners[current];
  Vec3 best = closest_on_triangle(p, start[0], start[1], start[2]);
  double best_distance = (best - p).squaredNorm();
  for (int step = 0; step < kMaxWalkSteps; ++step) {
    // On to the closest of the triangles that share a point with the current one, if it is
    // strictly closer (so the walk cannot cycle). All of them, not only those across the
    // edge or corner the current closest point lies on: on a polyhedral surface the face
    // under p's perpendicular is a local minimum among its edge neighbours even where a
    // triangle beyond them bends closer (a point a little inside a curved part).
    Index next = kInvalidIndex;
    for (const Index v : impl.kept_points[current])
      for (const Index k : impl.star.row(v)) {
        if (k == current) continue;
        const auto& c = impl.corners[k];
        const Vec3 candidate = closest_on_triangle(p, c[0], c[1], c[2]);
        if (const double distance = (candidate - p).squaredNorm(); distance < best_distance)
          next = k, best = candidate, best_distance = distance;
      }
    if (next == kInvalidIndex) {  // a local minimum
      triangle = impl.original[current];
      return best;
    }
    current = next;
  }
  return closest_point(p, &triangle);
}

bool SurfaceProjection::nearest_on_line(const Vec3& p, const Vec3& direction, double reach, Vec3& hit, Index& triangle,
                                        Vec3& barycentric_coordinates, const Vec3* facing) const {
  const Vec3 d = direction.normalized() * reach;
  const Kernel::Segment_3 segment(to_cgal(p - d), to_cgal(p + d));
  using Intersection = Tree::Intersection_and_primitive_id<Kernel::Segment_3>::Type;
  std::vector<Intersection> hits;
  impl_->tree.all_intersections(segment, std::back_inserter(hits));
  double best = std::numeric_limits<double>::infinity();
  std::size_t kept = 0;
  for (const Intersection& h : hits) {
    const auto index = static_cast<std::size_t>(h.second - impl_->triangles.cbegin());
    if (facing && !(impl_->normal(index).dot(*facing) > 0)) continue;
    // A segment lying in a triangle's plane meets it in a segment: its ends count.
    std::vector<Kernel::Point_3> candidates;
    if (const auto* q = boost::get<Kernel::Point_3>(&h.first))
      candidates.push_back(*q);
    else if (const auto* s = boost::get<Kernel::Segment_3>(&h.first))
      candidates.insert(candidates.end(), {s->source(), s->target()});
    for (const auto& q : candidates)
      if (const double distance = (to_vec(q) - p).squaredNorm(); distance < best) {
        best = distance;
        hit = to_vec(q);
        kept = index;
      }
  }
  if (best == std::numeric_limits<double>::infinity()) return false;
  triangle = impl_->original[kept];
  const auto& c = impl_->corners[kept];
  barycentric_coordinates = hit_barycentric(hit, c[0], c[1], c[2]);
  return true;
}

void SurfaceProjection::triangles_near(const Vec3& p, double radius, std::vector<Index>& triangles) const {
  const Kernel::Iso_cuboid_3 box(to_cgal(p - Vec3::Constant(radius)), to_cgal(p + Vec3::Constant(radius)));
  std::vector<Primitive::Id> hits;
  impl_->tree.all_intersected_primitives(box, std::back_inserter(hits));
  for (const auto& hit : hits)
    triangles.push_back(impl_->original[static_cast<std::size_t>(hit - impl_->triangles.cbegin())]);
}

double SurfaceProjection::squared_distance(const Vec3& p) const {
  return CGAL::to_double(impl_->tree.squared_distance(to_cgal(p)));
}

}  // namespace structmesh
