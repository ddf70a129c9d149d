// visible_faces() (face rule of §2.2) and the guarding it feeds: thread-count
// independence, and one guard for a convex solid.
#include "guard/shapes.hpp"
#include "structmesh/guard.hpp"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <random>
#include <vector>

namespace structmesh {
namespace {

std::vector<Vec3> points_in_ball(std::mt19937& rng, std::size_t count, double radius) {
  std::uniform_real_distribution<double> coordinate(-radius, radius);
  std::vector<Vec3> points;
  while (points.size() < count) {
    const Vec3 p(coordinate(rng), coordinate(rng), coordinate(rng));
    if (p.norm() < radius) points.push_back(p);
  }
  return points;
}

TEST(VisibleFaces, SameRowsWithOneAndTwoThreads) {
  const TriMesh blob = test::bumpy_sphere(3);
  const VisibilityOracle oracle(blob);
  std::mt19937 rng(5);
  // Inside the blob's smallest radius (0.55): every candidate is interior.
  const std::vector<Vec3> candidates = points_in_ball(rng, 40, 0.5);
  CompressedRows one, two;
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = visible_faces(oracle, blob, candidates);
  }
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = visible_faces(oracle, blob, candidates);
  }
  ASSERT_EQ(one.row_count(), candidates.size());
  EXPECT_EQ(one.offsets, two.offsets);
  EXPECT_EQ(one.items, two.items);
  // Rows ascending, and the face rule: a face is listed iff its three vertices are seen.
  std::size_t listed = 0;
  for (std::size_t c = 0; c < one.row_count(); ++c) {
    const auto row = one.row(c);
    EXPECT_TRUE(std::is_sorted(row.begin(), row.end()));
    listed += row.size();
    if (c % 10 != 0) continue;
    std::size_t expected = 0;
    for (const auto& t : blob.triangles)
      expected +=
          oracle.sees(candidates[c], t[0]) && oracle.sees(candidates[c], t[1]) && oracle.sees(candidates[c], t[2]);
    EXPECT_EQ(row.size(), expected) << "candidate " << c;
  }
  // The blob is not star-shaped from everywhere: some faces are hidden from some candidates.
  EXPECT_LT(listed, candidates.size() * blob.triangles.size());
  EXPECT_GT(listed, candidates.size() * blob.triangles.size() / 2);
}

TEST(VisibleFaces, ConvexSolidNeedsOneGuard) {
  const TriMesh sphere = test::unit_icosphere(3);
  const VisibilityOracle oracle(sphere);
  std::mt19937 rng(11);
  std::vector<Vec3> candidates = points_in_ball(rng, 12, 0.9);
  candidates.insert(candidates.begin() + 5, Vec3::Zero());
  const CompressedRows faces = visible_faces(oracle, sphere, candidates);
  EXPECT_EQ(faces.row(5).size(), sphere.triangles.size());
  const std::vector<Index> greedy = greedy_set_cover(faces, sphere.triangles.size());
  EXPECT_EQ(greedy.size(), 1u);
  const IlpSetCoverResult ilp = ilp_set_cover(faces, sphere.triangles.size());
  EXPECT_EQ(ilp.chosen.size(), 1u);
  EXPECT_TRUE(ilp.optimal);
  EXPECT_TRUE(covers_all(faces, sphere.triangles.size(), ilp.chosen));
}

TEST(VisibleFaces, TwoArmsNeedTwoGuardsOrTheCorner) {
  // An L of unit cubes with arms of 5. Each arm is convex, so a point deep in an arm
  // guards that arm, and a point in the corner cell (in both arms) guards everything.
  std::vector<test::Cell> cells;
  for (int i = 0; i < 5; ++i) cells.push_back({i, 0, 0});
  for (int j = 1; j < 5; ++j) cells.push_back({0, j, 0});
  const TriMesh mesh = test::voxel_surface(cells);
  const VisibilityOracle oracle(mesh);
  std::vector<Vec3> candidates{{4.5, 0.5, 0.5}, {0.5, 4.5, 0.5}};
  const CompressedRows arms = visible_faces(oracle, mesh, candidates);
  EXPECT_LT(arms.row(0).size(), mesh.triangles.size());
  EXPECT_LT(arms.row(1).size(), mesh.triangles.size());
  const IlpSetCoverResult two = ilp_set_cover(arms, mesh.triangles.size());
  EXPECT_EQ(two.chosen, (std::vector<Index>{0, 1}));
  EXPECT_TRUE(two.optimal);

  candidates.emplace_back(0.9, 0.9, 0.5);
  const CompressedRows faces = visible_faces(oracle, mesh, candidates);
  EXPECT_EQ(faces.row(2).size(), mesh.triangles.size());
  EXPECT_EQ(greedy_set_cover(faces, mesh.triangles.size()), (std::vector<Index>{2}));
  EXPECT_EQ(ilp_set_cover(faces, mesh.triangles.size()).chosen, (std::vector<Index>{2}));
}

}  // namespace
}  // namespace structmesh
