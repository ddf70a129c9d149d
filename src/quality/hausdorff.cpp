// Two-sided Hausdorff distance between triangle surfaces, for the geometric
// deviation D_g = d_H / l_diag of §5.3 (Table 5.2). The only CGAL user of the module:
// CGAL's AABB tree gives exact closest points on the other surface.
#include "structmesh/error.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/quality.hpp"

#include <Eigen/Geometry>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace structmesh {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

// More samples than this means a sampling ratio far below any useful accuracy.
constexpr double kMaxSamples = 2e8;

Point to_point(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
Vec3 to_vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// Sample points of one triangle: rows parallel to its longest edge, at most h apart,
// each sampled at most h apart, first row the longest edge, last row the apex.
// The longest edge's base angles are at most 90 degrees, so every point of the
// triangle projects onto the row below it within distance h and then lies within
// h/2 of a sample along that row: within sqrt(5)/2 h of a sample in all.
class TriangleSampler {
 public:
  TriangleSampler(const Vec3& p0, const Vec3& p1, const Vec3& p2, double spacing) {
    const std::array<Vec3, 3> p{p0, p1, p2};
    const std::array<double, 3> length{(p[1] - p[0]).norm(), (p[2] - p[1]).norm(), (p[0] - p[2]).norm()};
    const int longest = static_cast<int>(std::max_element(length.begin(), length.end()) - length.begin());
    a_ = p[longest];
    b_ = p[(longest + 1) % 3];
    c_ = p[(longest + 2) % 3];
    base_ = length[longest];
    const double height = base_ > 0 ? (b_ - a_).cross(c_ - a_).norm() / base_ : 0.0;
    rows_ = std::max(1.0, std::ceil(height / spacing));
    spacing_ = spacing;
  }

  // Samples in row j (0 .. rows): intervals along the row, +1 points (the apex row is one point).
  double intervals(double j) const {
    const double row_length = (1.0 - j / rows_) * base_;
    return row_length > 0 ? std::max(1.0, std::ceil(row_length / spacing_)) : 0.0;
  }
  double count() const {
    double total = 0;
    for (double j = 0; j <= rows_; ++j) total += intervals(j) + 1;
    return total;
  }
  template <typename Visit>
  void visit(Visit&& f) const {
    for (double j = 0; j <= rows_; ++j) {
      const double t = j / rows_;
      const Vec3 start = a_ + t * (c_ - a_), end = b_ + t * (c_ - b_);
      const double k = intervals(j);
      if (k == 0) {
        f(start);
        continue;
      }
      for (double i = 0; i <= k; ++i) f(start + (i / k) * (end - start));
    }
  }

 private:
  Vec3 a_, b_, c_;
  double base_ = 0, rows_ = 1, spacing_ = 1;
};

struct Directed {
  double squared = 0;
  double samples = 0;
};

// sup over the samples of `from` of the distance to the surface in `tree`.
Directed directed_distance(const TriMesh& from, const Tree& tree, double spacing, Progress& progress) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, from.triangles.size(), 64), Directed{},
      [&](const tbb::blocked_range<std::size_t>& range, Directed result) {
        for (std::size_t t = range.begin(); t != range.end(); ++t) {
          const auto& tri = from.triangles[t];
          const TriangleSampler sampler(from.points[tri[0]], from.points[tri[1]], from.points[tri[2]], spacing);
          // Consecutive samples are close: the previous closest point is a good hint.
          bool first = true;
          Point hint;
          sampler.visit([&](const Vec3& q) {
            const Point query = to_point(q);
            hint = first ? tree.closest_point(query) : tree.closest_point(query, hint);
            first = false;
            result.squared = std::max(result.squared, (to_vec(hint) - q).squaredNorm());
            result.samples += 1;
          });
        }
        progress.advance(range.size());
        return result;
      },
      // max and a sum of integers are exact, so the split does not change the result.
      [](const Directed& x, const Directed& y) {
        return Directed{std::max(x.squared, y.squared), x.samples + y.samples};
      });
}

std::vector<Triangle> cgal_triangles(const TriMesh& mesh) {
  std::vector<Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    triangles.emplace_back(to_point(mesh.points[t[0]]), to_point(mesh.points[t[1]]), to_point(mesh.points[t[2]]));
  return triangles;
}

double sample_count(const TriMesh& mesh, double spacing) {
  double total = 0;
  for (const auto& t : mesh.triangles)
    total += TriangleSampler(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], spacing).count();
  return total;
}

}  // namespace

HausdorffResult hausdorff_distance(const TriMesh& reference, const TriMesh& other, double sampling_ratio) {
  if (reference.triangles.empty() || other.triangles.empty())
    throw InputError("Hausdorff distance: both surfaces need triangles (reference has " +
                     std::to_string(reference.triangles.size()) + ", other has " +
                     std::to_string(other.triangles.size()) + ")");
  if (!(sampling_ratio > 0))
    throw InputError("Hausdorff distance: the sampling ratio must be positive, got " + std::to_string(sampling_ratio));
  const double diagonal = reference.bounding_box().diagonal();
  if (!(diagonal > 0)) throw InputError("Hausdorff distance: the reference surface has no extent");
  const double spacing = sampling_ratio * diagonal;
  const double samples = sample_count(reference, spacing) + sample_count(other, spacing);
  if (samples > kMaxSamples)
    throw InputError("Hausdorff distance: sampling ratio " + std::to_string(sampling_ratio) + " needs " +
                     std::to_string(static_cast<long long>(samples)) + " samples; use a larger ratio");

  const std::vector<Triangle> reference_triangles = cgal_triangles(reference);
  const std::vector<Triangle> other_triangles = cgal_triangles(other);
  Tree reference_tree(reference_triangles.begin(), reference_triangles.end());
  Tree other_tree(other_triangles.begin(), other_triangles.end());
  // Build both trees (and their closest-point search structures) before the
  // parallel queries rather than lazily inside them.
  reference_tree.build();
  reference_tree.accelerate_distance_queries();
  other_tree.build();
  other_tree.accelerate_distance_queries();

  Progress progress("Hausdorff distance", reference.triangles.size() + other.triangles.size());
  const Directed forward = directed_distance(reference, other_tree, spacing, progress);
  const Directed backward = directed_distance(other, reference_tree, spacing, progress);
  progress.finish();
  HausdorffResult result;
  result.distance = std::sqrt(std::max(forward.squared, backward.squared));
  result.relative = result.distance / diagonal;
  result.tolerance = std::sqrt(5.0) / 2.0 * spacing;
  result.samples = static_cast<std::size_t>(forward.samples + backward.samples);
  return result;
}

}  // namespace structmesh
