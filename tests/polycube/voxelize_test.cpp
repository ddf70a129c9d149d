// Voxelization of §4.4.1: the scanline fill against analytic inside tests (rays through
// vertices and edges included), the Morse resolution on shapes with known critical
// heights, and the distance field against analytic distances.
#include "polycube/shapes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace structmesh {
namespace {

using test::torus;

/// Axis-aligned box [lo, hi], 12 outward triangles.
TriMesh box_surface(const Vec3& lo, const Vec3& hi) {
  TriMesh mesh;
  for (int k = 0; k < 8; ++k)
    mesh.points.emplace_back((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
  const std::array<std::array<Index, 4>, 6> quads{
      {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  }
  return mesh;
}

/// The octahedron |x| + |y| + |z| <= r, outward.
TriMesh octahedron(double r) {
  TriMesh mesh;
  mesh.points = {{r, 0, 0}, {-r, 0, 0}, {0, r, 0}, {0, -r, 0}, {0, 0, r}, {0, 0, -r}};
  for (const Index x : {0u, 1u})
    for (const Index y : {2u, 3u})
      for (const Index z : {4u, 5u}) {
        // Outward when (x, y, z) is counter-clockwise seen from outside: the sign of
        // the octant flips the order once per negative axis.
        const bool flip = ((x == 1) + (y == 3) + (z == 5)) % 2 == 1;
        mesh.triangles.push_back(flip ? std::array<Index, 3>{x, z, y} : std::array<Index, 3>{x, y, z});
      }
  return mesh;
}

Vec3 voxel_centre(const VoxelGrid& grid, int x, int y, int z) {
  return grid.origin + grid.size * Vec3(x + 0.5, y + 0.5, z + 0.5);
}

TEST(Voxelize, BoxKeepsExactlyTheCentresInsideAndAnEmptyLayer) {
  const TriMesh box = box_surface({0.03, -0.2, 0.1}, {1.01, 0.55, 0.47});
  const VoxelGrid grid = voxelize(box, 0.07);
  std::size_t inside = 0;
  for (int z = 0; z < grid.dims[2]; ++z)
    for (int y = 0; y < grid.dims[1]; ++y)
      for (int x = 0; x < grid.dims[0]; ++x) {
        const Vec3 c = voxel_centre(grid, x, y, z);
        const bool expected =
            c.x() > 0.03 && c.x() < 1.01 && c.y() > -0.2 && c.y() < 0.55 && c.z() > 0.1 && c.z() < 0.47;
        EXPECT_EQ(grid.at(x, y, z), expected) << x << " " << y << " " << z;
        inside += expected;
        if (x == 0 || y == 0 || z == 0 || x + 1 == grid.dims[0] || y + 1 == grid.dims[1] || z + 1 == grid.dims[2]) {
          EXPECT_FALSE(grid.at(x, y, z));
        }
      }
  EXPECT_EQ(grid.count(), inside);
  EXPECT_GT(inside, 100U);
}

TEST(Voxelize, RaysThroughVerticesAndEdgesCountCrossingsOnce) {
  // Size 0.4 on [-1, 1]^3 puts rows of centres at multiples of 0.4: the row y = z = 0
  // passes through the vertices (+-1, 0, 0) and rows z = +-0.4 through edges.
  const VoxelGrid grid = voxelize(octahedron(1.0), 0.4);
  for (int z = 0; z < grid.dims[2]; ++z)
    for (int y = 0; y < grid.dims[1]; ++y)
      for (int x = 0; x < grid.dims[0]; ++x) {
        const Vec3 c = voxel_centre(grid, x, y, z);
        const double l1 = std::abs(c.x()) + std::abs(c.y()) + std::abs(c.z());
        ASSERT_GT(std::abs(l1 - 1.0), 1e-9);  // no centre on the surface itself
        EXPECT_EQ(grid.at(x, y, z), l1 < 1.0) << c.transpose();
      }
  EXPECT_NEAR(std::abs(voxel_centre(grid, 3, 3, 3).y()), 0.0, 1e-12);  // the vertex row is there
}

TEST(Voxelize, TorusMatchesTheAnalyticSolidUpToTheFacetingError) {
  const double big = 2, small = 0.7;
  const TriMesh mesh = torus(big, small, 96, 48);
  const VoxelGrid grid = voxelize(mesh, 0.05);
  // The polyhedron lies inside the smooth torus, within r (1 - cos(pi / 48)) < 0.0015 of it.
  std::size_t checked = 0;
  for (int z = 0; z < grid.dims[2]; ++z)
    for (int y = 0; y < grid.dims[1]; ++y)
      for (int x = 0; x < grid.dims[0]; ++x) {
        const Vec3 c = voxel_centre(grid, x, y, z);
        const double ring = std::hypot(std::hypot(c.x(), c.y()) - big, c.z());
        if (ring < small - 0.01) {
          EXPECT_TRUE(grid.at(x, y, z)) << c.transpose();
          ++checked;
        } else if (ring > small) {
          EXPECT_FALSE(grid.at(x, y, z)) << c.transpose();
        }
      }
  EXPECT_GT(checked, 10000U);
}

TEST(Voxelize, RejectsBadInput) {
  EXPECT_THROW(voxelize(TriMesh{}, 0.1), InputError);
  EXPECT_THROW(voxelize(box_surface({0, 0, 0}, {1, 1, 1}), 0.0), InputError);
  EXPECT_THROW(voxelize(box_surface({0, 0, 0}, {1, 1, 1}), -1.0), InputError);
  EXPECT_THROW(voxelize(box_surface({0, 0, 0}, {1, 1, 1}), 1e-4, 1'000'000), InputError);  // 10^12 voxels
}

TEST(MorseVoxelSize, BoxGivesAThirdOfItsShortestSide) {
  const MorseResolution morse = morse_voxel_size(box_surface({0, 0, 0}, {3, 2, 1}), 0.01, 10.0);
  EXPECT_NEAR(morse.size, 1.0 / 3, 1e-12);
  for (int axis = 0; axis < 3; ++axis) {
    ASSERT_EQ(morse.levels[axis].size(), 2U) << axis;  // the two end faces
    EXPECT_NEAR(morse.levels[axis][0], 0.0, 1e-12);
  }
  EXPECT_NEAR(morse.levels[0][1], 3.0, 1e-12);
  // The cap applies.
  EXPECT_NEAR(morse_voxel_size(box_surface({0, 0, 0}, {3, 2, 1}), 0.01, 0.1).size, 0.1, 1e-12);
}

TEST(MorseVoxelSize, TorusSeesItsHoleAlongXAndY) {
  // Height x on a torus around z: maximum and minimum at +-(R + r), saddles at
  // +-(R - r); the gaps are 2r, 2(R - r), 2r. Height z: extremal circles at +-r.
  const double big = 2, small = 0.5;
  const MorseResolution morse = morse_voxel_size(torus(big, small, 64, 32), 0.05, 10.0);
  ASSERT_EQ(morse.levels[0].size(), 4U);
  EXPECT_NEAR(morse.levels[0][0], -(big + small), 0.02);
  EXPECT_NEAR(morse.levels[0][1], -(big - small), 0.02);
  EXPECT_NEAR(morse.levels[0][2], big - small, 0.02);
  EXPECT_NEAR(morse.levels[0][3], big + small, 0.02);
  ASSERT_EQ(morse.levels[2].size(), 2U);
  EXPECT_NEAR(morse.size, 2 * small / 3, 0.02);
  // A coarse epsilon merges the saddles into the extrema: the hole is no longer resolved.
  EXPECT_LT(morse_voxel_size(torus(big, small, 64, 32), 1.2, 10.0).levels[0].size(), 4U);
}

TEST(VertexDistances, MatchTheDistanceToABoxInTheBandAndBoundItOutside) {
  const Vec3 lo(0.1, 0.2, 0.3), hi(1.3, 0.9, 0.8);
  const TriMesh box = box_surface(lo, hi);
  const VoxelGrid grid = voxelize(box, 0.05);
  const int band = 2;
  const std::vector<double> distance = vertex_distances(grid, box, band);
  ASSERT_EQ(distance.size(), grid.vertex_count());
  std::size_t exact = 0, far = 0;
  for (int z = 0; z <= grid.dims[2]; ++z)
    for (int y = 0; y <= grid.dims[1]; ++y)
      for (int x = 0; x <= grid.dims[0]; ++x) {
        const Vec3 p = grid.vertex_position(x, y, z);
        const Vec3 outside = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
        const double analytic =
            outside.norm() > 0 ? outside.norm() : std::min((p - lo).minCoeff(), (hi - p).minCoeff());
        const double d = distance[grid.vertex_index(x, y, z)];
        if (std::abs(d - analytic) < 1e-12) {
          ++exact;
        } else {
          // Outside the band: the band's width, which the true distance reaches.
          EXPECT_DOUBLE_EQ(d, band * grid.size);
          EXPECT_GE(analytic, (band - 1) * grid.size) << p.transpose();
          ++far;
        }
      }
  EXPECT_GT(exact, 1000U);
  EXPECT_GT(far, 100U);
  EXPECT_THROW(vertex_distances(grid, TriMesh{}), InputError);
}

}  // namespace
}  // namespace structmesh
