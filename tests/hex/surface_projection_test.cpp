// SurfaceProjection on the unit cube's surface: closest points, triangles and barycentric
// coordinates known by hand, and parallel queries equal to serial ones.
#include "polycube/shapes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace structmesh {
namespace {

TEST(SurfaceProjection, ClosestPointsOfTheUnitCube) {
  const SurfaceProjection projection(test::unit_cube());
  Index triangle = kInvalidIndex;
  Vec3 weights;
  // Above the top face, over the half y < x: triangle (4, 5, 6) with
  // (0.75, 0.25) = 0.25 (0, 0) + 0.5 (1, 0) + 0.25 (1, 1).
  const Vec3 top = projection.closest_point(Vec3(0.75, 0.25, 5), &triangle, &weights);
  EXPECT_NEAR((top - Vec3(0.75, 0.25, 1)).norm(), 0.0, 1e-12);
  EXPECT_EQ(triangle, 2u);
  EXPECT_NEAR((weights - Vec3(0.25, 0.5, 0.25)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(projection.squared_distance(Vec3(0.75, 0.25, 5)), 16.0, 1e-12);

  // Inside, nearest to the bottom face.
  EXPECT_NEAR((projection.closest_point(Vec3(0.5, 0.4, 0.1)) - Vec3(0.5, 0.4, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(projection.squared_distance(Vec3(0.5, 0.4, 0.1)), 0.01, 1e-12);

  // Beyond a corner: the corner itself, a vertex of the triangle found.
  const Vec3 corner = projection.closest_point(Vec3(2, 3, 4), &triangle, &weights);
  EXPECT_NEAR((corner - Vec3(1, 1, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(projection.squared_distance(Vec3(2, 3, 4)), 1 + 4 + 9, 1e-12);
  EXPECT_NEAR(weights.maxCoeff(), 1.0, 1e-12);
  const TriMesh cube = test::unit_cube();
  Vec3 rebuilt = Vec3::Zero();
  for (int i = 0; i < 3; ++i) rebuilt += weights[i] * cube.points[cube.triangles[triangle][i]];
  EXPECT_NEAR((rebuilt - corner).norm(), 0.0, 1e-12);
}

TEST(SurfaceProjection, MovedProjectionAnswersTheSame) {
  SurfaceProjection first(test::unit_cube());
  SurfaceProjection second = std::move(first);
  EXPECT_NEAR((second.closest_point(Vec3(-1, 0.5, 0.5)) - Vec3(0, 0.5, 0.5)).norm(), 0.0, 1e-12);
}

TEST(SurfaceProjection, ParallelQueriesEqualSerialOnes) {
  const SurfaceProjection projection(test::unit_cube());
  std::vector<Vec3> queries;
  for (int i = 0; i < 2000; ++i) queries.emplace_back(std::sin(i * 0.37) * 2, std::cos(i * 0.11) * 2, (i % 17) * 0.13);
  std::vector<Vec3> serial(queries.size()), parallel(queries.size());
  std::vector<Vec3> serial_weights(queries.size()), parallel_weights(queries.size());
  std::vector<Index> serial_triangle(queries.size()), parallel_triangle(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i)
    serial[i] = projection.closest_point(queries[i], &serial_triangle[i], &serial_weights[i]);
  tbb::parallel_for(std::size_t{0}, queries.size(), [&](std::size_t i) {
    parallel[i] = projection.closest_point(queries[i], &parallel_triangle[i], &parallel_weights[i]);
  });
  EXPECT_EQ(serial, parallel);
  EXPECT_EQ(serial_triangle, parallel_triangle);
  EXPECT_EQ(serial_weights, parallel_weights);
}

TEST(SurfaceProjection, AWalkFromTheLastAnswerFindsTheClosestPointOnAConvexSurface) {
  // A walk of small steps around a sphere of 1,280 triangles, each query walking from the
  // triangle of the last answer (as the smoothing does), inside and outside the sphere: the
  // closest point of the whole surface every time, on a triangle that holds it.
  const TriMesh sphere = test::sphere(1, 16, 32);
  const SurfaceProjection projection(sphere);
  Index triangle = kInvalidIndex;
  Index steps_taken = 0;
  for (int i = 0; i < 3000; ++i) {
    const double t = i * 0.013;
    const Vec3 query =
        (1 + 0.2 * std::sin(7 * t)) * Vec3(std::cos(t), std::sin(t) * std::cos(0.3 * t), std::sin(0.3 * t));
    const Index from = triangle;
    const Vec3 walked = projection.closest_point_walking(query, triangle);
    ASSERT_NEAR((walked - projection.closest_point(query)).norm(), 0.0, 1e-12) << i;
    ASSERT_LT(triangle, sphere.triangles.size());
    const auto& c = sphere.triangles[triangle];
    const Vec3 n = (sphere.points[c[1]] - sphere.points[c[0]]).cross(sphere.points[c[2]] - sphere.points[c[0]]);
    EXPECT_NEAR(n.normalized().dot(walked - sphere.points[c[0]]), 0.0, 1e-12) << i;  // in its plane
    steps_taken += from != triangle;
  }
  EXPECT_GT(steps_taken, 100u);  // the walk did cross triangles
  // From a triangle a quarter of the way round, and from the far side (where the face under
  // p's perpendicular holds the nearest point of its edge neighbours, but not of all the
  // triangles around it): the closest point too.
  const Vec3 p(1.3, 0.2, -0.1);
  Index quarter = kInvalidIndex, far = kInvalidIndex;
  projection.closest_point(Vec3(0.3, 1.2, 0.4), &quarter);
  EXPECT_NEAR((projection.closest_point_walking(p, quarter) - projection.closest_point(p)).norm(), 0.0, 1e-12);
  projection.closest_point(-p, &far);
  EXPECT_NEAR((projection.closest_point_walking(p, far) - projection.closest_point(p)).norm(), 0.0, 1e-12);
}

TEST(SurfaceProjection, AWalkStaysOnItsSheetOfAThinSlab) {
  // A point inside a slab 0.1 thick, nearer its bottom: the global search answers on the
  // bottom, the walk from a top triangle on the top (the sheet the smoothed point came from),
  // never farther than that triangle's own closest point.
  const TriMesh slab = test::subdivided_box(1, 1, 0.1, 4);
  const SurfaceProjection projection(slab);
  Index top = kInvalidIndex;
  projection.closest_point(Vec3(0.3, 0.2, 0.2), &top);
  const Vec3 p(0.5, 0.5, 0.04);
  EXPECT_NEAR((projection.closest_point(p) - Vec3(0.5, 0.5, 0)).norm(), 0.0, 1e-12);
  Index triangle = top;
  EXPECT_NEAR((projection.closest_point_walking(p, triangle) - Vec3(0.5, 0.5, 0.1)).norm(), 0.0, 1e-12);
  EXPECT_NE(triangle, top);  // it walked across the top to the triangle under p
  // Beyond the top's edge x = 1 and below the top: on to the side x = 1.
  triangle = top;
  EXPECT_NEAR((projection.closest_point_walking(Vec3(1.2, 0.5, 0.07), triangle) - Vec3(1, 0.5, 0.07)).norm(), 0.0,
              1e-12);
}

TEST(SurfaceProjection, AWalkWithoutAStartIsTheGlobalSearch) {
  const SurfaceProjection projection(test::unit_cube());
  Index triangle = kInvalidIndex, global = kInvalidIndex;
  const Vec3 expected = projection.closest_point(Vec3(0.75, 0.25, 5), &global);
  EXPECT_EQ(projection.closest_point_walking(Vec3(0.75, 0.25, 5), triangle), expected);
  EXPECT_EQ(triangle, global);
  triangle = 12345;  // no such triangle
  EXPECT_EQ(projection.closest_point_walking(Vec3(0.75, 0.25, 5), triangle), expected);
  EXPECT_EQ(triangle, global);
}

TEST(SurfaceProjection, DegenerateTrianglesAreLeftOutAndIndicesStayTheSurfaces) {
  // The cube with a collinear triangle first (all later indices shift by one) and a
  // zero-area triangle with a repeated point at the end.
  TriMesh cube = test::unit_cube();
  cube.points.emplace_back(0.5, 0, 1);  // 8: the midpoint of edge 4-5
  cube.triangles.insert(cube.triangles.begin(), {4, 8, 5});
  cube.triangles.push_back({6, 6, 7});
  const SurfaceProjection projection(cube);
  Index triangle = kInvalidIndex;
  Vec3 weights;
  projection.closest_point(Vec3(0.75, 0.25, 5), &triangle, &weights);
  EXPECT_EQ(triangle, 3u);  // (4, 5, 6), the unit cube's triangle 2
  Vec3 hit;
  // A vertical line through the top face, and one along the collinear triangle's edge.
  ASSERT_TRUE(projection.nearest_on_line(Vec3(0.75, 0.25, 0.9), Vec3(0, 0, 1), 1.0, hit, triangle, weights));
  EXPECT_NEAR((hit - Vec3(0.75, 0.25, 1)).norm(), 0.0, 1e-12);
  EXPECT_EQ(triangle, 3u);
  EXPECT_NO_THROW(projection.nearest_on_line(Vec3(0.5, 0, 0.5), Vec3(0, 0, 1), 1.0, hit, triangle, weights));
  EXPECT_NE(triangle, 0u);
  TriMesh flat;
  flat.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  flat.triangles = {{0, 1, 2}};
  EXPECT_THROW(SurfaceProjection{flat}, InputError);
}

TEST(SurfaceProjection, TrianglesNearAPointOfAnEdgeAreThoseOfBothFaces) {
  const SurfaceProjection projection(test::unit_cube());
  const auto near = [&](const Vec3& p, double radius) {
    std::vector<Index> triangles;
    projection.triangles_near(p, radius, triangles);
    std::sort(triangles.begin(), triangles.end());
    return triangles;
  };
  // (1, 1, 0.5) is on the edge 2-6 between the faces x = 1 and y = 1: triangles (1, 2, 6)
  // and (2, 7, 6) hold it; (1, 6, 5) and (2, 3, 7) only come within 0.5 of it.
  EXPECT_EQ(near(Vec3(1, 1, 0.5), 1e-9), (std::vector<Index>{6, 9}));
  EXPECT_EQ(near(Vec3(0.75, 0.25, 1), 1e-9), (std::vector<Index>{2}));  // inside the top face
  EXPECT_TRUE(near(Vec3(0.5, 0.5, 0.5), 0.4).empty());                  // the cube's centre
  EXPECT_EQ(near(Vec3(0.5, 0.5, 0.5), 0.5).size(), 12u);                // its box reaches every face
}

// A slab 0.1 thick: a point inside, 0.04 under its top and 0.06 over its bottom, is nearest
// to the top, which faces up. Asked for a hit facing down, the line query gives the bottom
// (what keeps a polycube corner from landing across a narrow gap in the hex extraction).
TEST(SurfaceProjection, FacingLineQuerySkipsTheSheetThatFacesTheOtherWay) {
  const TriMesh slab = test::subdivided_box(1, 1, 0.1, 4);
  const SurfaceProjection projection(slab);
  const Vec3 p(0.5, 0.5, 0.06), down(0, 0, -1), up(0, 0, 1);
  const auto normal = [&](Index t) {
    const auto& c = slab.triangles[t];
    return Vec3((slab.points[c[1]] - slab.points[c[0]]).cross(slab.points[c[2]] - slab.points[c[0]]));
  };
  Index triangle = kInvalidIndex;
  Vec3 hit, weights;
  ASSERT_TRUE(projection.nearest_on_line(p, up, 1.0, hit, triangle, weights));
  EXPECT_NEAR((hit - Vec3(0.5, 0.5, 0.1)).norm(), 0.0, 1e-12);
  EXPECT_GT(normal(triangle).dot(up), 0);
  ASSERT_TRUE(projection.nearest_on_line(p, up, 1.0, hit, triangle, weights, &up));
  EXPECT_NEAR((hit - Vec3(0.5, 0.5, 0.1)).norm(), 0.0, 1e-12);

  ASSERT_TRUE(projection.nearest_on_line(p, up, 1.0, hit, triangle, weights, &down));
  EXPECT_NEAR((hit - Vec3(0.5, 0.5, 0)).norm(), 0.0, 1e-12);
  EXPECT_GT(normal(triangle).dot(down), 0);
  Vec3 rebuilt = Vec3::Zero();
  for (int i = 0; i < 3; ++i) rebuilt += weights[i] * slab.points[slab.triangles[triangle][i]];
  EXPECT_NEAR((rebuilt - hit).norm(), 0.0, 1e-12);
  // Too short to reach the bottom: no facing hit, though the top is within reach.
  EXPECT_FALSE(projection.nearest_on_line(p, up, 0.05, hit, triangle, weights, &down));
  // The line along x meets only the sides x = 0 and x = 1, which face neither up nor down.
  EXPECT_FALSE(projection.nearest_on_line(p, Vec3(1, 0, 0), 1.0, hit, triangle, weights, &down));
}

TEST(SurfaceProjection, RejectsAnEmptySurface) {
  EXPECT_THROW(SurfaceProjection(TriMesh{}), InputError);
  TriMesh broken = test::unit_cube();
  broken.triangles[3][1] = 8;
  EXPECT_THROW(SurfaceProjection{broken}, InputError);
}

}  // namespace
}  // namespace structmesh
