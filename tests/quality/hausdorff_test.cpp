// Hausdorff distance (D_g of §5.3) on cases with exact answers.
#include "structmesh/error.hpp"
#include "structmesh/quality.hpp"
#include "structmesh/solids.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

namespace structmesh {
namespace {

// Icosahedron subdivided `levels` times, vertices on the unit sphere.
TriMesh icosphere(int levels) {
  return structmesh::icosphere(levels, [](const Vec3&) { return 1.0; });
}

TriMesh rectangle(double x0, double x1, double y0, double y1) {
  return {{Vec3(x0, y0, 0), Vec3(x1, y0, 0), Vec3(x1, y1, 0), Vec3(x0, y1, 0)}, {{0, 1, 2}, {0, 2, 3}}};
}

TriMesh merged(const TriMesh& a, const TriMesh& b) {
  TriMesh m = a;
  const Index offset = static_cast<Index>(a.points.size());
  m.points.insert(m.points.end(), b.points.begin(), b.points.end());
  for (const auto& [i, j, k] : b.triangles) m.triangles.push_back({i + offset, j + offset, k + offset});
  return m;
}

TEST(Hausdorff, SurfaceToItselfIsZero) {
  const TriMesh sphere = icosphere(3);
  const HausdorffResult h = hausdorff_distance(sphere, sphere, 1e-2);
  EXPECT_LT(h.distance, 1e-12);
  EXPECT_GT(h.samples, 2 * sphere.triangles.size());
}

TEST(Hausdorff, TranslatedConvexSurfaceIsTheTranslationLength) {
  // For a convex polytope P, d_H(dP, dP + t) = |t| exactly: the vertex extreme in
  // direction t is |t| away from P, and no point is farther. Vertices are samples.
  const TriMesh sphere = icosphere(3);
  TriMesh moved = sphere;
  const double d = 0.05;
  const Vec3 t = d * sphere.points[5];  // direction of a vertex
  for (Vec3& p : moved.points) p += t;
  const HausdorffResult h = hausdorff_distance(sphere, moved, 1e-2);
  EXPECT_NEAR(h.distance, d, 1e-12);
  EXPECT_NEAR(h.relative, d / sphere.bounding_box().diagonal(), 1e-12);
  // Any direction: within the sampling tolerance of |t| (and never above it).
  TriMesh skew = sphere;
  const Vec3 s = Vec3(0.3, -0.2, 0.7).normalized() * d;
  for (Vec3& p : skew.points) p += s;
  const HausdorffResult k = hausdorff_distance(sphere, skew, 1e-2);
  EXPECT_LE(k.distance, d + 1e-12);
  EXPECT_GE(k.distance, d - k.tolerance);
}

TEST(Hausdorff, IsTwoSided) {
  // Every point of the unit square is on the 2x1 rectangle, but the rectangle's far
  // end is 1 away from the square.
  const TriMesh square = rectangle(0, 1, 0, 1), wide = rectangle(0, 2, 0, 1);
  EXPECT_NEAR(hausdorff_distance(square, wide, 1e-2).distance, 1.0, 1e-12);
  EXPECT_NEAR(hausdorff_distance(wide, square, 1e-2).distance, 1.0, 1e-12);
}

TEST(Hausdorff, FindsAMaximumInsideATriangleWithinTheTolerance) {
  // Two unit squares 2 apart; a strip over both has its farthest points (x = 2,
  // distance 1) inside its triangles, not at a vertex.
  const TriMesh pair = merged(rectangle(0, 1, 0, 1), rectangle(3, 4, 0, 1));
  const TriMesh strip = rectangle(0, 4, 0, 1);
  for (double ratio : {0.05, 0.01}) {
    const HausdorffResult h = hausdorff_distance(pair, strip, ratio);
    EXPECT_LE(h.distance, 1.0 + 1e-12) << ratio;
    EXPECT_GE(h.distance, 1.0 - h.tolerance) << ratio;
    EXPECT_NEAR(h.tolerance, std::sqrt(5.0) / 2 * ratio * std::sqrt(17.0), 1e-12);
  }
}

// An n x n grid of the unit square (2 triangles per cell), its centre point lifted by `lift`.
TriMesh tent(int n, double lift) {
  TriMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.points.emplace_back(double(i) / n, double(j) / n, i == n / 2 && j == n / 2 ? lift : 0.0);
  const auto at = [&](int i, int j) { return static_cast<Index>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

TEST(Hausdorff, SkipsOnlySamplesThatCannotRaiseTheMaximum) {
  // A flat grid and the same grid with its centre lifted by 0.3: the apex, one sample
  // among thousands near the plane, is the farthest point, 0.3 exactly. Most samples lie
  // so near one whose distance was looked up that they are not looked up themselves.
  const TriMesh flat = tent(20, 0.0), lifted = tent(20, 0.3);
  for (const auto& [a, b] : {std::pair{&flat, &lifted}, std::pair{&lifted, &flat}}) {
    const HausdorffResult h = hausdorff_distance(*a, *b, 5e-3);
    EXPECT_NEAR(h.distance, 0.3, 1e-12);
    EXPECT_GT(h.queried_samples, 0U);
    EXPECT_LT(h.queried_samples, h.samples / 2);
  }
}

TEST(Hausdorff, TrianglesLyingOnOneTriangleOfTheOtherAreNotSampled) {
  // A fine grid lying on two big triangles: the grid's corners all find their closest point
  // on one of the two, so each grid triangle off the diagonal is no farther than its corners
  // (0) and none of its samples is looked up. The big triangles' samples all are (a maximum
  // of 0 rules none out).
  const TriMesh fine = tent(40, 0.0), coarse = rectangle(0, 1, 0, 1);
  const HausdorffResult both = hausdorff_distance(coarse, fine, 2e-3);
  EXPECT_LT(both.distance, 1e-12);
  const HausdorffResult coarse_only = hausdorff_distance(coarse, coarse, 2e-3);
  // Every sample of the big triangles; of the fine grid's, its corners and those of the
  // triangles along the diagonal.
  const std::size_t coarse_samples = coarse_only.samples / 2, fine_samples = both.samples - coarse_samples;
  ASSERT_GE(both.queried_samples, coarse_samples);
  EXPECT_LT(both.queried_samples - coarse_samples, fine_samples / 10) << fine_samples;
}

TEST(Hausdorff, RejectsUnusableInput) {
  const TriMesh square = rectangle(0, 1, 0, 1);
  EXPECT_THROW(hausdorff_distance(square, TriMesh{}), InputError);
  EXPECT_THROW(hausdorff_distance(TriMesh{}, square), InputError);
  EXPECT_THROW(hausdorff_distance(square, square, 0.0), InputError);
  EXPECT_THROW(hausdorff_distance(square, square, 1e-7), InputError);  // ~1e14 samples
}

}  // namespace
}  // namespace structmesh
