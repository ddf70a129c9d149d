// cover_thin_features(): a tilted plate thinner than a voxel, which voxelize() cuts into
// stripes (one component each), comes out as one piece without handles or voids, through
// voxels the plate passes through; build_polycube() takes that route when the centre voxels
// lose the topology. And the topological numbers it relies on, on configurations whose
// counts are known.
#include "polycube/shapes.hpp"
#include "polycube/voxel_checks.hpp"
#include "polycube/voxel_neighbourhood.hpp"
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <numbers>

namespace structmesh {
namespace {

constexpr double kThickness = 0.06, kVoxel = 0.25, kTiltDegrees = 17;

/// A 4 x 4 plate of the given thickness, centred at the origin and turned about x.
TriMesh tilted_plate() {
  TriMesh plate = test::subdivided_box(4.0, 4.0, kThickness, 4);
  const Eigen::AngleAxisd turn(kTiltDegrees * std::numbers::pi / 180, Vec3::UnitX());
  for (Vec3& p : plate.points) p = turn * (p - Vec3(2, 2, kThickness / 2));
  return plate;
}

TEST(CoverThinFeatures, TiltedPlateThinnerThanAVoxelBecomesOnePiece) {
  const TriMesh plate = tilted_plate();
  VoxelGrid grid = voxelize(plate, kVoxel);
  const VoxelTopology centres = voxel_topology(grid);
  ASSERT_GT(centres.components, 1);  // the stripes: what this test is about
  const VoxelGrid before = grid;

  const std::size_t kept = cover_thin_features(grid, plate);
  const VoxelTopology covered = voxel_topology(grid);
  EXPECT_EQ(covered.components, 1);
  EXPECT_EQ(covered.handles, 0);
  EXPECT_EQ(covered.voids, 0);
  EXPECT_EQ(grid.count(), before.count() + kept);

  // Only voxels are added, each one the plate passes through: its centre is within half a
  // voxel diagonal of the plate's middle plane, give or take half the thickness.
  const Vec3 normal = Eigen::AngleAxisd(kTiltDegrees * std::numbers::pi / 180, Vec3::UnitX()) * Vec3::UnitZ();
  test::expect_only_additions(before, grid, [&](int x, int y, int z) {
    const Vec3 centre = grid.origin + kVoxel * Vec3(x + 0.5, y + 0.5, z + 0.5);
    EXPECT_LE(std::abs(normal.dot(centre)), std::sqrt(3.0) / 2 * kVoxel + kThickness / 2 + 1e-12);
  });
}

TEST(CoverThinFeatures, LeavesAShapeWithoutThinPartsAsItWas) {
  // A 2 x 2 x 2 box at voxel size 0.25: the centre voxels are the box; any voxel the
  // surface touches outside them is simple to remove again.
  const TriMesh box = test::subdivided_box(2.0, 2.0, 2.0, 2);
  VoxelGrid grid = voxelize(box, kVoxel);
  const VoxelGrid before = grid;
  EXPECT_EQ(cover_thin_features(grid, box), 0u);
  EXPECT_EQ(grid.occupied, before.occupied);
  EXPECT_THROW(cover_thin_features(grid, TriMesh{}), InputError);
}

TEST(BuildPolycube, CoversAPlateThinnerThanAVoxel) {
  PolycubeOptions options;
  options.align = false;                   // keep the tilt: aligned, the plate would fill a voxel layer
  options.deformation.max_iterations = 0;  // nor straighten it
  options.voxel_size = kVoxel;
  const PolycubeResult result = build_polycube(tilted_plate(), options);
  EXPECT_GT(result.thin_feature_voxels, 0u);
  EXPECT_EQ(result.final.components, 1);
  EXPECT_EQ(result.final.handles, 0);
  EXPECT_EQ(result.final.voids, 0);
  EXPECT_TRUE(is_well_composed(result.voxels));
}

TEST(TopologicalNumbers, CountPiecesAndSides) {
  std::array<std::uint32_t, 26> pieces{};
  const auto bit = [](int dx, int dy, int dz) { return 1u << ((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1)); };
  // Two voxels on opposite sides of the centre: two pieces, and the empty space around
  // them one side.
  const std::uint32_t opposite = bit(-1, 0, 0) | bit(1, 0, 0);
  EXPECT_EQ(voxel::occupied_components(opposite, pieces), 2);
  EXPECT_EQ(pieces[0] | pieces[1], opposite);
  EXPECT_EQ(voxel::empty_face_components(opposite), 1);
  // The eight voxels around the centre in its z = 0 plane: one piece, and the empty space
  // above and below it two sides (occupying the centre closes a tunnel).
  std::uint32_t ring = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (dx != 0 || dy != 0) ring |= bit(dx, dy, 0);
  EXPECT_EQ(voxel::occupied_components(ring, pieces), 1);
  EXPECT_EQ(voxel::empty_face_components(ring), 2);
  // Nothing around: no piece; everything around: no empty side.
  EXPECT_EQ(voxel::occupied_components(0, pieces), 0);
  EXPECT_EQ(voxel::empty_face_components(voxel::kAllNeighbourhood), 0);
}

}  // namespace
}  // namespace structmesh
