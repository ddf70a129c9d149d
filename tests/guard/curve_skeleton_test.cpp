#include "structmesh/error.hpp"
#include "structmesh/skeleton.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace structmesh {
namespace {

// A closed cylinder along x from 0 to `length`, radius 1: `around` points per ring,
// `rings` rings, each cap a fan around its centre; normals outward.
TriMesh capped_cylinder(double length, int around, int rings) {
  TriMesh mesh;
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < around; ++k) {
      const double angle = 2 * std::numbers::pi * k / around;
      mesh.points.emplace_back(length * r / (rings - 1), std::cos(angle), std::sin(angle));
    }
  const auto at = [&](int r, int k) { return static_cast<Index>(r * around + (k + around) % around); };
  for (int r = 0; r + 1 < rings; ++r)
    for (int k = 0; k < around; ++k) {
      mesh.triangles.push_back({at(r, k), at(r + 1, k + 1), at(r + 1, k)});
      mesh.triangles.push_back({at(r, k), at(r, k + 1), at(r + 1, k + 1)});
    }
  const auto start = static_cast<Index>(mesh.points.size());
  mesh.points.emplace_back(0, 0, 0);
  mesh.points.emplace_back(length, 0, 0);
  for (int k = 0; k < around; ++k) {
    mesh.triangles.push_back({start, at(0, k + 1), at(0, k)});
    mesh.triangles.push_back({start + 1, at(rings - 1, k), at(rings - 1, k + 1)});
  }
  return mesh;
}

TEST(CurveSkeleton, CylinderSkeletonRunsAlongTheAxisInside) {
  const TriMesh cylinder = capped_cylinder(8.0, 24, 33);
  const CurveSkeleton skeleton = curve_skeleton(cylinder);
  ASSERT_GE(skeleton.nodes.size(), 3u);
  for (const Vec3& p : skeleton.nodes) {
    EXPECT_LT(std::hypot(p.y(), p.z()), 0.2) << "node " << p.transpose() << " is off the axis";
    EXPECT_GT(p.x(), 0.0);
    EXPECT_LT(p.x(), 8.0);
  }
  const std::vector<std::uint8_t> inside = inside_solid(cylinder, skeleton.nodes);
  for (std::size_t i = 0; i < inside.size(); ++i) EXPECT_EQ(inside[i], 1) << "node " << i;
  // Every surface vertex was absorbed by one node.
  ASSERT_EQ(skeleton.vertex_node.size(), cylinder.points.size());
  for (const Index node : skeleton.vertex_node) EXPECT_LT(node, skeleton.nodes.size());
  // A path: two ends, every other node of degree 2.
  std::vector<int> degree(skeleton.nodes.size(), 0);
  for (const auto& [a, b] : skeleton.edges) ++degree[a], ++degree[b];
  EXPECT_EQ(std::count(degree.begin(), degree.end(), 1), 2);
}

TEST(CurveSkeleton, OpenSurfaceIsRejected) {
  TriMesh cylinder = capped_cylinder(4.0, 12, 5);
  cylinder.triangles.pop_back();
  EXPECT_THROW(curve_skeleton(cylinder), InputError);
  EXPECT_THROW(curve_skeleton(TriMesh{}), InputError);
}

TEST(ResampleSkeleton, JointsAndEndsKeptBranchesEvenlySampled) {
  // A Y: joint at the origin, branches of length 3, 2 and 1 (as several nodes each).
  CurveSkeleton skeleton;
  skeleton.nodes = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 0, 1}};
  skeleton.edges = {{0, 1}, {1, 2}, {2, 3}, {0, 4}, {4, 5}, {0, 6}};
  const std::vector<Vec3> samples = resample_skeleton(skeleton, 0.5);
  const auto has = [&](const Vec3& p) {
    return std::any_of(samples.begin(), samples.end(), [&](const Vec3& s) { return (s - p).norm() < 1e-12; });
  };
  EXPECT_TRUE(has({0, 0, 0}));
  EXPECT_TRUE(has({3, 0, 0}));
  EXPECT_TRUE(has({0, 2, 0}));
  EXPECT_TRUE(has({0, 0, 1}));
  // 4 kept + 5 + 3 + 1 interior samples at spacing 0.5.
  EXPECT_EQ(samples.size(), 4u + 5u + 3u + 1u);
  EXPECT_TRUE(has({2.5, 0, 0}));
  EXPECT_TRUE(has({0, 1.5, 0}));
  EXPECT_TRUE(has({0, 0, 0.5}));
  EXPECT_THROW(resample_skeleton(skeleton, 0.0), InputError);
}

TEST(ResampleSkeleton, LoopWithoutJointsIsSampled) {
  CurveSkeleton square;
  square.nodes = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  square.edges = {{0, 1}, {1, 2}, {2, 3}, {0, 3}};
  const std::vector<Vec3> samples = resample_skeleton(square, 0.5);
  EXPECT_EQ(samples.size(), 8u);  // perimeter 4 at spacing 0.5
}

TEST(InsideSolid, PointsInsideOnAndOutside) {
  const TriMesh cylinder = capped_cylinder(2.0, 16, 3);
  const std::vector<Vec3> points = {{1, 0, 0}, {1, 0, 0.5}, {1, 0, 2}, {-1, 0, 0}, {0, 0, 0}};
  const std::vector<std::uint8_t> inside = inside_solid(cylinder, points);
  EXPECT_EQ(inside, (std::vector<std::uint8_t>{1, 1, 0, 0, 0}));  // the last is on the cap
}

}  // namespace
}  // namespace structmesh
