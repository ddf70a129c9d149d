// quad_quality and singular_vertices_per_part on meshes whose counts are known by hand.
#include "quality/test_meshes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>
#include <numeric>
#include <random>

namespace structmesh {
namespace {

TEST(QuadQuality, RegularGridIsPerfectWithoutSingularities) {
  const QuadQuality q = quad_quality(test::quad_grid(3, 3));
  EXPECT_TRUE(q.planar);
  ASSERT_EQ(q.scaled_jacobian.size(), 9u);
  for (double s : q.scaled_jacobian) EXPECT_DOUBLE_EQ(s, 1.0);
  EXPECT_EQ(q.scaled_jacobian_stats.count, 9u);
  EXPECT_DOUBLE_EQ(q.scaled_jacobian_stats.mean, 1.0);
  EXPECT_DOUBLE_EQ(q.scaled_jacobian_stats.stddev, 0.0);
  ASSERT_EQ(q.scaled_jacobian_histogram.size(), 20u);
  EXPECT_EQ(q.scaled_jacobian_histogram.back(), 9u);
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_EQ(q.singular_vertices, 0u);
  EXPECT_EQ(q.interior_vertices, 4u);
  EXPECT_EQ(q.boundary_vertices, 12u);
}

TEST(QuadQuality, QuadMeshedTriangleHasOneValenceThreeVertex) {
  const QuadQuality q = quad_quality(test::polygon_fan(3));
  EXPECT_EQ(q.interior_vertices, 1u);
  EXPECT_EQ(q.boundary_vertices, 6u);
  EXPECT_EQ(q.singular_vertices, 1u);
  EXPECT_EQ(q.inverted, 0u);
  // Refining keeps the one singularity and adds only regular vertices.
  const QuadMesh refined = test::subdivide(test::subdivide(test::polygon_fan(3)));
  const QuadQuality r = quad_quality(refined);
  EXPECT_EQ(r.singular_vertices, 1u);
  EXPECT_GT(r.interior_vertices, 10u);
  EXPECT_GT(r.scaled_jacobian_stats.min, 0.0);
}

TEST(QuadQuality, QuadMeshedPentagonHasOneValenceFiveVertex) {
  const QuadQuality q = quad_quality(test::subdivide(test::polygon_fan(5)));
  EXPECT_EQ(q.singular_vertices, 1u);
  EXPECT_EQ(q.inverted, 0u);
}

TEST(QuadQuality, ClosedCubeSurfaceUsesVerdictNormalsAndHasEightSingularities) {
  // 6 quads, outward; every vertex has valence 3 and there is no boundary.
  QuadMesh cube;
  for (int i = 0; i < 8; ++i) cube.points.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  cube.quads = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  const QuadQuality q = quad_quality(cube);
  EXPECT_FALSE(q.planar);
  for (double s : q.scaled_jacobian) EXPECT_DOUBLE_EQ(s, 1.0);
  EXPECT_EQ(q.boundary_vertices, 0u);
  EXPECT_EQ(q.interior_vertices, 8u);
  EXPECT_EQ(q.singular_vertices, 8u);
}

TEST(QuadQuality, FlippedAndNonConvexQuadsOfAPlanarMeshAreInverted) {
  QuadMesh mesh = test::quad_grid(3, 3);
  std::swap(mesh.quads[0][1], mesh.quads[0][3]);  // clockwise
  mesh.points[10] = Vec3(1.3, 1.3, 0);            // vertex (2,2) pushed past the diagonal of quad 4
  const QuadQuality q = quad_quality(mesh);
  EXPECT_DOUBLE_EQ(q.scaled_jacobian[0], -1.0);
  EXPECT_LT(q.scaled_jacobian[4], 0.0);
  EXPECT_EQ(q.inverted, 2u);
  EXPECT_EQ(q.scaled_jacobian_histogram[0], 1u);  // -1 falls in the first bin
}

TEST(QuadQuality, UnusedPointsAreNeitherBoundaryNorInterior) {
  QuadMesh mesh = test::quad_grid(2, 2);
  mesh.points.emplace_back(10, 10, 0);
  const QuadQuality q = quad_quality(mesh);
  EXPECT_EQ(q.boundary_vertices + q.interior_vertices, 9u);
  EXPECT_EQ(q.singular_vertices, 0u);
}

TEST(QuadQuality, EmptyMesh) {
  const QuadQuality q = quad_quality(QuadMesh{});
  EXPECT_TRUE(q.scaled_jacobian.empty());
  EXPECT_EQ(q.scaled_jacobian_stats.count, 0u);
  EXPECT_EQ(q.singular_vertices, 0u);
}

TEST(QuadQuality, ResultDoesNotDependOnThreadCount) {
  QuadMesh mesh = test::quad_grid(150, 120);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> jitter(-0.45, 0.45);
  for (Vec3& p : mesh.points) p += Vec3(jitter(random), jitter(random), 0);
  const QuadQuality parallel = quad_quality(mesh);
  QuadQuality serial;
  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    serial = quad_quality(mesh);
  }
  EXPECT_EQ(parallel.scaled_jacobian, serial.scaled_jacobian);
  EXPECT_EQ(std::memcmp(&parallel.scaled_jacobian_stats, &serial.scaled_jacobian_stats, sizeof(Statistics)), 0);
  EXPECT_EQ(parallel.inverted, serial.inverted);
  EXPECT_GT(parallel.inverted, 0u);  // the jitter is large enough to fold some quads
}

TEST(SingularVerticesPerPart, SeparatorVerticesGoToTheSmallestPart) {
  const QuadMesh pentagon = test::polygon_fan(5);
  EXPECT_EQ(singular_vertices_per_part(pentagon, {3, 1, 4, 1, 2}), (std::vector<std::size_t>{0, 1, 0, 0, 0}));
  // Refined: the centre (valence 5) is shared by all parts, the rest is regular.
  const QuadMesh refined = test::subdivide(pentagon);
  std::vector<std::int32_t> parts(refined.quads.size());
  for (std::size_t i = 0; i < parts.size(); ++i) parts[i] = static_cast<std::int32_t>(i / 4) + 2;
  const std::vector<std::size_t> counts = singular_vertices_per_part(refined, parts);
  EXPECT_EQ(counts, (std::vector<std::size_t>{0, 0, 1, 0, 0, 0, 0}));
  EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), std::size_t{0}), quad_quality(refined).singular_vertices);
}

TEST(SingularVerticesPerPart, RejectsBadPartIds) {
  const QuadMesh grid = test::quad_grid(2, 1);
  EXPECT_THROW(singular_vertices_per_part(grid, {0}), InputError);
  EXPECT_THROW(singular_vertices_per_part(grid, {0, -1}), InputError);
  EXPECT_TRUE(singular_vertices_per_part(QuadMesh{}, {}).empty());
}

}  // namespace
}  // namespace structmesh
