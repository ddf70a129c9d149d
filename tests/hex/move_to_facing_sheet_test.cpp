// move_boundary_points_to_facing_sheet() on a slab 0.1 thick: a patch of boundary quads on
// its bottom, one point put on the top sheet across it (as the map can put a point across a
// narrow gap), comes back to the bottom; a patch lying right is left as it is.
#include "polycube/shapes.hpp"
#include "structmesh/hex.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace structmesh {
namespace {

// A 4 x 4 patch of quads (5 x 5 points) on the slab's bottom z = 0, over [0.3, 0.7]^2.
struct Patch {
  std::vector<Vec3> points;
  std::vector<std::array<Index, 4>> quads;
};
Patch bottom_patch() {
  Patch patch;
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) patch.points.emplace_back(0.3 + 0.1 * i, 0.3 + 0.1 * j, 0);
  const auto id = [](int i, int j) { return static_cast<Index>(j * 5 + i); };
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) patch.quads.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
  return patch;
}

TEST(MoveBoundaryPointsToFacingSheet, APointAcrossTheSlabComesBack) {
  const TriMesh slab = test::subdivided_box(1, 1, 0.1, 10);
  const SurfaceProjection onto_slab(slab);
  Patch patch = bottom_patch();
  const std::vector<Vec3> right = patch.points;
  patch.points[12] = Vec3(0.53, 0.48, 0.1);  // the centre (0.5, 0.5) on the top sheet, off by a little
  EXPECT_EQ(move_boundary_points_to_facing_sheet(patch.points, patch.quads, slab, onto_slab), 1u);
  // Back on the bottom, at its neighbours' centroid.
  EXPECT_NEAR((patch.points[12] - Vec3(0.5, 0.5, 0)).norm(), 0.0, 1e-12);
  for (Index v = 0; v < patch.points.size(); ++v)
    if (v != 12) {
      EXPECT_EQ(patch.points[v], right[v]) << v;
    }
}

TEST(MoveBoundaryPointsToFacingSheet, PointsOnTheirSheetStay) {
  const TriMesh slab = test::subdivided_box(1, 1, 0.1, 10);
  const SurfaceProjection onto_slab(slab);
  Patch patch = bottom_patch();
  patch.points[12] = Vec3(0.53, 0.48, 0);  // off the grid, but on the bottom
  const std::vector<Vec3> before = patch.points;
  EXPECT_EQ(move_boundary_points_to_facing_sheet(patch.points, patch.quads, slab, onto_slab), 0u);
  EXPECT_EQ(patch.points, before);

  // Around the slab's edge y = 0, z = 0: points on the side y = 0 face -y, their neighbours
  // on the bottom -z; a bend of 90 degrees is no fold.
  Patch bend;
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 4; ++i) {
      const double s = 0.05 * (j - 1);  // arc length from the edge: < 0 on the side, > 0 on the bottom
      bend.points.emplace_back(0.3 + 0.1 * i, s > 0 ? s : 0, s < 0 ? -s : 0);
    }
  const auto id = [](int i, int j) { return static_cast<Index>(j * 5 + i); };
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 4; ++i) bend.quads.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
  const std::vector<Vec3> bent = bend.points;
  EXPECT_EQ(move_boundary_points_to_facing_sheet(bend.points, bend.quads, slab, onto_slab), 0u);
  EXPECT_EQ(bend.points, bent);
}

}  // namespace
}  // namespace structmesh
