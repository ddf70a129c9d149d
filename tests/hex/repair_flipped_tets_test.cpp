// repair_flipped_tets(): cavities around flipped tets re-triangulated as stars, valid in both
// the source and the parameter domain.
#include "hex/map_test_helpers.hpp"
#include "polycube/shapes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/quality.hpp"
#include "structmesh/tetmesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

namespace structmesh {
namespace {

using test::flipped;
using test::solid;

double total_volume(const TetMesh& tets, const std::vector<Vec3>& points) {
  double sum = 0;
  for (const auto& t : tets.tets) sum += tet_signed_volume(points, t);
  return sum;
}

/// Each face's tet count, by sorted corners: 1 on the boundary, 2 inside a conforming mesh.
std::map<std::array<Index, 3>, int> face_uses(const TetMesh& tets) {
  std::map<std::array<Index, 3>, int> uses;
  for (const auto& t : tets.tets)
    for (const auto& f : kTetFaces) {
      std::array<Index, 3> key{t[f[0]], t[f[1]], t[f[2]]};
      std::sort(key.begin(), key.end());
      ++uses[key];
    }
  return uses;
}

std::set<std::array<Index, 3>> boundary_faces(const TetMesh& tets) {
  std::set<std::array<Index, 3>> faces;
  for (const auto& [key, uses] : face_uses(tets))
    if (uses == 1) faces.insert(key);
  return faces;
}

TEST(RepairFlippedTets, StarCavityMakesEveryTetPositiveInBothDomainsAndKeepsTheBoundary) {
  const TriMesh box = test::subdivided_box(2, 2, 2, 8);
  TetMesh tets = solid(box);
  const std::size_t boundary_count = box.points.size();
  // A map that is the identity but for one interior point near the centre, thrown a tet
  // length and a half away: the tets around it flip.
  std::vector<Vec3> parameter = tets.points;
  std::size_t moved = boundary_count;
  for (std::size_t i = boundary_count; i < tets.points.size(); ++i)
    if ((tets.points[i] - Vec3(1, 1, 1)).norm() < (tets.points[moved] - Vec3(1, 1, 1)).norm()) moved = i;
  parameter[moved] += Vec3(0.4, 0.3, 0.1);
  const std::size_t before = flipped(tets, parameter);
  ASSERT_GT(before, 0u);
  const std::set<std::array<Index, 3>> surface = boundary_faces(tets);
  const std::vector<Vec3> boundary_images(parameter.begin(),
                                          parameter.begin() + static_cast<std::ptrdiff_t>(boundary_count));
  const double source_volume = total_volume(tets, tets.points);
  const double parameter_volume = total_volume(tets, parameter);

  const FlippedTetRepair repair = repair_flipped_tets(tets, parameter);
  EXPECT_EQ(repair.flipped_before, before);
  EXPECT_EQ(repair.flipped_after, 0u);
  EXPECT_GE(repair.cavities, 1u);
  EXPECT_EQ(flipped(tets, parameter), 0u);
  EXPECT_EQ(flipped(tets, tets.points), 0u);
  ASSERT_EQ(parameter.size(), tets.points.size());
  // Conforming, with the same surface; the boundary's images are untouched.
  for (const auto& [key, uses] : face_uses(tets)) EXPECT_LE(uses, 2) << key[0] << " " << key[1] << " " << key[2];
  EXPECT_EQ(boundary_faces(tets), surface);
  for (std::size_t i = 0; i < boundary_count; ++i) EXPECT_EQ(parameter[i], boundary_images[i]);
  // Both domains are still covered once: the volumes add up as before (the parameter's signed
  // sum is the volume its boundary encloses, which did not move).
  EXPECT_NEAR(total_volume(tets, tets.points), source_volume, 1e-9 * source_volume);
  EXPECT_NEAR(total_volume(tets, parameter), parameter_volume, 1e-9 * parameter_volume);
}

TEST(RepairFlippedTets, LeavesWhatNoStarCanMendAndTheMeshValid) {
  // A boundary point of the top face pushed through the solid and out below its bottom: the
  // image surface crosses itself, so no cavity's boundary is star-shaped there.
  const TriMesh box = test::subdivided_box(2, 2, 1, 6);
  TetMesh tets = solid(box);
  std::vector<Vec3> parameter = tets.points;
  std::size_t top = 0;
  for (std::size_t i = 0; i < box.points.size(); ++i)
    if ((box.points[i] - Vec3(1, 1, 1)).norm() < (box.points[top] - Vec3(1, 1, 1)).norm()) top = i;
  ASSERT_LT((box.points[top] - Vec3(1, 1, 1)).norm(), 1e-9);
  parameter[top] = Vec3(1, 1, -0.5);
  const FlippedTetRepair repair = repair_flipped_tets(tets, parameter);
  EXPECT_GT(repair.flipped_before, 0u);
  EXPECT_GT(repair.flipped_after, 0u);
  EXPECT_EQ(repair.flipped_after, flipped(tets, parameter));
  EXPECT_EQ(flipped(tets, tets.points), 0u);
  for (const auto& [key, uses] : face_uses(tets)) EXPECT_LE(uses, 2);
}

TEST(RepairFlippedTets, NothingToDoOnAValidMapAndMismatchedSizesAreRejected) {
  const TriMesh box = test::subdivided_box(1, 1, 1, 4);
  TetMesh tets = solid(box);
  std::vector<Vec3> parameter = tets.points;
  const auto tets_before = tets.tets;
  const FlippedTetRepair repair = repair_flipped_tets(tets, parameter);
  EXPECT_EQ(repair.flipped_before, 0u);
  EXPECT_EQ(repair.cavities, 0u);
  EXPECT_EQ(tets.tets, tets_before);
  parameter.pop_back();
  EXPECT_THROW(repair_flipped_tets(tets, parameter), InputError);
}

}  // namespace
}  // namespace structmesh
