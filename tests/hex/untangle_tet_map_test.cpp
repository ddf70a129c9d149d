// untangle_tet_map(): joint untangling of a tet map's flipped tets, the surface freed (on
// springs) where pinning it leaves no valid placement.
#include "hex/map_test_helpers.hpp"
#include "polycube/shapes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace structmesh {
namespace {

using test::flipped;
using test::solid;

std::size_t nearest_point(const std::vector<Vec3>& points, std::size_t begin, std::size_t end, const Vec3& to) {
  std::size_t best = begin;
  for (std::size_t i = begin; i < end; ++i)
    if ((points[i] - to).norm() < (points[best] - to).norm()) best = i;
  return best;
}

// A box's tet mesh mapped to itself but for its interior point nearest the centre, pushed
// far enough to fold its tets; the surface's targets are its own points.
struct InteriorFold {
  TriMesh box = test::subdivided_box(2, 2, 2, 8);
  TetMesh tets = solid(box);
  std::size_t boundary_count = box.points.size();
  std::vector<Vec3> parameter = tets.points;
  std::vector<Vec3> targets{box.points.begin(), box.points.end()};
  InteriorFold() {
    parameter[nearest_point(tets.points, boundary_count, tets.points.size(), Vec3(1, 1, 1))] += Vec3(0.4, 0.3, 0.1);
  }
};

TEST(UntangleTetMap, InteriorFoldIsUntangledWithTheSurfacePinned) {
  InteriorFold fold;
  const TetMesh& tets = fold.tets;
  const std::size_t boundary_count = fold.boundary_count;
  std::vector<Vec3>& parameter = fold.parameter;
  const std::vector<Vec3>& targets = fold.targets;
  const std::size_t before = flipped(tets, parameter);
  ASSERT_GT(before, 0u);

  const TetMapUntangling untangled = untangle_tet_map(tets, parameter, boundary_count, targets);
  EXPECT_EQ(untangled.flipped_before, before);
  EXPECT_EQ(untangled.flipped_after, 0u);
  EXPECT_EQ(flipped(tets, parameter), 0u);
  EXPECT_EQ(untangled.rounds, 1);  // the pinned round sufficed
  EXPECT_EQ(untangled.moved_boundary_points, 0u);
  for (std::size_t i = 0; i < boundary_count; ++i) EXPECT_EQ(parameter[i], targets[i]);
}

TEST(UntangleTetMap, ARoundStopsTheGivenNumberOfStepsAfterItsFirstValidOne) {
  const auto run = [](int steps_once_valid) {
    TetMapUntanglingOptions options;
    options.max_steps_once_valid = steps_once_valid;
    options.max_iterations = 2;  // short steps, so that the reshaping takes several
    InteriorFold fold;
    const TetMapUntangling untangled =
        untangle_tet_map(fold.tets, fold.parameter, fold.boundary_count, fold.targets, options);
    EXPECT_EQ(untangled.flipped_after, 0u);
    EXPECT_EQ(flipped(fold.tets, fold.parameter), 0u);
    return untangled.steps;
  };
  // Uncapped, the reshaping goes on after the fold is undone; capped at 0 the round ends with
  // its first valid step, and at 1 one step later.
  const int uncapped = run(1000), first_valid = run(0);
  EXPECT_GE(first_valid, 1);
  EXPECT_GT(uncapped, first_valid + 1);
  EXPECT_EQ(run(1), first_valid + 1);
}

// A box's tet mesh mapped to itself but for a point of its top face, pushed through the solid
// and out below its bottom: the target surface crosses itself, no placement of the interior
// points is valid, and no star cavity mends it
// (RepairFlippedTets.LeavesWhatNoStarCanMendAndTheMeshValid). The surface's targets are the
// pushed positions.
struct SurfaceFold {
  TriMesh box = test::subdivided_box(2, 2, 1, 6);
  TetMesh tets = solid(box);
  std::size_t boundary_count = box.points.size();
  std::size_t top = nearest_point(box.points, 0, boundary_count, Vec3(1, 1, 1));
  std::vector<Vec3> parameter = tets.points;
  std::vector<Vec3> targets;
  SurfaceFold() {
    parameter[top] = Vec3(1, 1, -0.5);
    targets.assign(parameter.begin(), parameter.begin() + static_cast<std::ptrdiff_t>(boundary_count));
  }
};

TEST(UntangleTetMap, SurfaceFoldFreesTheSurfaceNearItAndLeavesTheRestAlone) {
  SurfaceFold fold;
  const TriMesh& box = fold.box;
  const TetMesh& tets = fold.tets;
  const std::size_t boundary_count = fold.boundary_count, top = fold.top;
  std::vector<Vec3>& parameter = fold.parameter;
  const std::vector<Vec3>& targets = fold.targets;
  ASSERT_LT((box.points[top] - Vec3(1, 1, 1)).norm(), 1e-9);
  const std::size_t before = flipped(tets, parameter);
  ASSERT_GT(before, 0u);
  const std::vector<Vec3> start = parameter;

  const TetMapUntangling untangled = untangle_tet_map(tets, parameter, boundary_count, targets);
  EXPECT_EQ(untangled.flipped_before, before);
  EXPECT_EQ(untangled.flipped_after, 0u);
  EXPECT_EQ(flipped(tets, parameter), 0u);
  EXPECT_GE(untangled.rounds, 2);  // the pinned round cannot do it
  EXPECT_GT(untangled.moved_boundary_points, 0u);
  // The pushed point went back above the bottom face it had crossed.
  EXPECT_GT(parameter[top][2], 0.0);
  // Only the kept round's free points moved, and they are a small part of the mesh: the map
  // away from the fold is untouched.
  std::size_t moved = 0;
  for (std::size_t i = 0; i < parameter.size(); ++i) moved += parameter[i] != start[i] ? 1 : 0;
  EXPECT_GT(moved, 0u);
  EXPECT_LE(moved, untangled.free_points);
  EXPECT_LT(untangled.free_points, parameter.size() / 2);
}

TEST(UntangleTetMap, ARoundThatLeavesNoFewerFlippedGivesUpAfterTheGivenSteps) {
  // The surface fold: with the surface pinned no step can leave fewer tets flipped, so
  // the pinned round gives up after the given number of steps and the freed round still
  // untangles the map; never giving up, the pinned round runs all its steps to no gain.
  const auto run = [](int give_up_after) {
    SurfaceFold fold;
    TetMapUntanglingOptions options;
    options.rings = {3};
    options.give_up_after_steps = give_up_after;
    const TetMapUntangling untangled =
        untangle_tet_map(fold.tets, fold.parameter, fold.boundary_count, fold.targets, options);
    EXPECT_EQ(untangled.rounds, 2);
    EXPECT_EQ(untangled.flipped_after, 0u);
    EXPECT_EQ(flipped(fold.tets, fold.parameter), 0u);
    return untangled.rounds_given_up;
  };
  EXPECT_EQ(run(3), 1);
  EXPECT_EQ(run(1000), 0);
}

TEST(UntangleTetMap, AFlatTetCountsAsFlippedAndIsMended) {
  // An interior point moved to a billionth of its height above the opposite face of one of its
  // tets: that tet keeps a positive volume, which a sign test passes, but it is flat.
  const TriMesh box = test::subdivided_box(2, 2, 2, 8);
  const TetMesh tets = solid(box);
  const std::size_t boundary_count = box.points.size();
  const std::size_t v = nearest_point(tets.points, boundary_count, tets.points.size(), Vec3(1, 1, 1));
  std::vector<Vec3> parameter;
  bool placed = false;
  for (const auto& tet : tets.tets) {
    if (std::find(tet.begin(), tet.end(), static_cast<Index>(v)) == tet.end()) continue;
    Vec3 centroid = Vec3::Zero();
    for (const Index u : tet)
      if (u != v) centroid += tets.points[u] / 3;
    parameter = tets.points;
    parameter[v] = centroid + 1e-9 * (tets.points[v] - centroid);
    if (flipped(tets, parameter) == 0) {  // no other tet of v inverted by the move
      placed = true;
      break;
    }
  }
  ASSERT_TRUE(placed);
  EXPECT_EQ(flipped_or_flat_tets(tets, parameter, 0), 0u);  // the sign alone
  ASSERT_EQ(flipped_or_flat_tets(tets, parameter), 1u);
  const std::vector<Vec3> targets(box.points.begin(), box.points.end());
  const TetMapUntangling untangled = untangle_tet_map(tets, parameter, boundary_count, targets);
  EXPECT_EQ(untangled.flipped_before, 1u);
  EXPECT_EQ(untangled.flipped_after, 0u);
  EXPECT_EQ(flipped_or_flat_tets(tets, parameter), 0u);
  EXPECT_EQ(untangled.moved_boundary_points, 0u);
  parameter.pop_back();
  EXPECT_THROW(flipped_or_flat_tets(tets, parameter), InputError);
}

TEST(UntangleTetMap, NothingToDoOnAValidMapAndMismatchedSizesAreRejected) {
  const TriMesh box = test::subdivided_box(1, 1, 1, 4);
  const TetMesh tets = solid(box);
  std::vector<Vec3> parameter = tets.points;
  const std::vector<Vec3> targets(box.points.begin(), box.points.end());
  const TetMapUntangling untangled = untangle_tet_map(tets, parameter, targets.size(), targets);
  EXPECT_EQ(untangled.flipped_before, 0u);
  EXPECT_EQ(untangled.rounds, 0);
  EXPECT_EQ(parameter, tets.points);
  EXPECT_THROW(untangle_tet_map(tets, parameter, targets.size() + 1, targets), InputError);
  parameter.pop_back();
  EXPECT_THROW(untangle_tet_map(tets, parameter, targets.size(), targets), InputError);
}

}  // namespace
}  // namespace structmesh
