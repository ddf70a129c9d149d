// volumetric_map(): the least squares (5.1) with a smooth frame field, boundary pinned.
#include "hex/map_test_helpers.hpp"
#include "polycube/shapes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/quality.hpp"
#include "structmesh/tetmesh.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

namespace structmesh {
namespace {

using test::flipped;
using test::solid;

TriMesh mapped(TriMesh surface, const auto& f) {
  for (Vec3& p : surface.points) p = f(p);
  return surface;
}

/// A map that squeezes a bar along x = 2 (its middle) to 1 - depth of its width, over a
/// Gaussian exp(-sharpness (x - 2)^2) along the bar.
auto squeeze_middle(double depth, double sharpness) {
  return [depth, sharpness](const Vec3& p) {
    const double s = 1 - depth * std::exp(-sharpness * (p.x() - 2) * (p.x() - 2));
    return Vec3(p.x(), 0.5 + (p.y() - 0.5) * s, 0.5 + (p.z() - 0.5) * s);
  };
}

TEST(VolumetricMap, IdentityAndRigidMotionsAreReproducedExactly) {
  const TriMesh box = test::subdivided_box(2, 1.5, 1, 6);
  const TetMesh tets = solid(box);
  ASSERT_GT(tets.points.size(), box.points.size());  // there are interior points to solve for
  const VolumetricMap identity = volumetric_map(tets, box, box);
  EXPECT_EQ(identity.flipped, 0u);
  EXPECT_NEAR(identity.volume_distortion, 1.0, 1e-9);
  for (std::size_t i = 0; i < tets.points.size(); ++i) EXPECT_LT((identity.parameter[i] - tets.points[i]).norm(), 1e-9);
  // A rotation and a shift: every frame is the rotation, so u = R x + t solves (5.1) exactly.
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.6, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 shift(5, -1, 2);
  const auto motion = [&](const Vec3& p) { return Vec3(rotation * p + shift); };
  const VolumetricMap rigid = volumetric_map(tets, box, mapped(box, motion));
  EXPECT_EQ(rigid.flipped_before_untangling, 0u);
  for (std::size_t i = 0; i < tets.points.size(); ++i)
    EXPECT_LT((rigid.parameter[i] - motion(tets.points[i])).norm(), 1e-8) << "point " << i;
}

TEST(VolumetricMap, TwistedAndStretchedBarsMapWithoutFlips) {
  const TriMesh bar = test::subdivided_box(4, 1, 1, 8);
  const TetMesh tets = solid(bar);
  // A quarter turn along the bar's length: the boundary frames turn with it and the interior
  // frames interpolate them.
  const auto twist = [](const Vec3& p) {
    const double angle = 0.5 * std::numbers::pi * p.x() / 4;
    const Vec3 c(p.x(), 0.5, 0.5);
    const Vec3 r = Eigen::AngleAxisd(angle, Vec3::UnitX()) * (p - c);
    return Vec3(c + r);
  };
  const TriMesh twisted = mapped(bar, twist);
  const VolumetricMap map = volumetric_map(tets, bar, twisted);
  EXPECT_EQ(map.flipped, 0u);
  EXPECT_EQ(flipped(tets, map.parameter), 0u);
  EXPECT_GT(map.volume_distortion, 0.99);
  EXPECT_LT(map.volume_distortion, 1.05);
  // The boundary is pinned to the target.
  for (std::size_t i = 0; i < bar.points.size(); ++i) EXPECT_EQ(map.parameter[i], twisted.points[i]);
  // Interior points follow the twist closely (the map is smooth, not exactly the twist).
  double worst = 0;
  for (std::size_t i = bar.points.size(); i < tets.points.size(); ++i)
    worst = std::max(worst, (map.parameter[i] - twist(tets.points[i])).norm());
  EXPECT_LT(worst, 0.1);
}

TEST(VolumetricMap, FoldedInteriorIsUntangled) {
  // A target that squeezes the bar's middle to a tenth of its width: the linear solve folds
  // tets there (the test checks it does, so the untangling is exercised), the untangling
  // repairs every one.
  const TriMesh bar = test::subdivided_box(4, 1, 1, 8);
  const TetMesh tets = solid(bar);
  const auto squeeze = squeeze_middle(0.9, 8);
  const VolumetricMap map = volumetric_map(tets, bar, mapped(bar, squeeze));
  EXPECT_GT(map.flipped_before_untangling, 0u);
  EXPECT_EQ(map.flipped, 0u) << map.flipped_before_untangling << " flipped before untangling";
  EXPECT_EQ(flipped(tets, map.parameter), 0u);
  // Stopped after each of the first sweeps, the count kept sweep by sweep (only the tets of
  // the points that moved are measured again) is the count of the map returned.
  for (int sweeps = 1; sweeps <= 3; ++sweeps) {
    VolumetricMapOptions options;
    options.untangle_sweeps = sweeps;
    const VolumetricMap partial = volumetric_map(tets, bar, mapped(bar, squeeze), options);
    EXPECT_EQ(partial.flipped, flipped(tets, partial.parameter)) << sweeps << " sweeps";
    if (sweeps == 1) {
      EXPECT_GT(partial.flipped, 0u);  // else the check would compare nothing but zeros
    }
  }
}

TEST(VolumetricMap, UntanglingSweepsGiveTheSameMapOnOneAndTwoThreads) {
  // The sweeps run in wavefronts of points that share no tet (volumetric_map.cpp), each
  // reading its neighbours as the serial sweep in ascending order would: the map must not
  // depend on how a wavefront is split between threads. A finer bar than above, so that the
  // wavefronts are large enough to be split.
  const TriMesh bar = test::subdivided_box(4, 1, 1, 16);
  const TetMesh tets = solid(bar);
  const TriMesh target = mapped(bar, squeeze_middle(0.95, 4));
  for (const int sweeps : {1, 5, 300}) {
    VolumetricMapOptions options;
    options.untangle_sweeps = sweeps;
    VolumetricMap one, two;
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
      one = volumetric_map(tets, bar, target, options);
    }
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
      two = volumetric_map(tets, bar, target, options);
    }
    ASSERT_GT(one.flipped_before_untangling, 100u);  // a fold large enough for wide wavefronts
    EXPECT_EQ(one.flipped, two.flipped) << sweeps << " sweeps";
    ASSERT_EQ(one.parameter.size(), two.parameter.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < one.parameter.size(); ++i) differing += one.parameter[i] != two.parameter[i];
    EXPECT_EQ(differing, 0u) << sweeps << " sweeps";
  }
}

TEST(VolumetricMap, RejectsMismatchedInput) {
  const TriMesh box = test::subdivided_box(1, 1, 1, 2);
  const TetMesh tets = solid(box);
  TriMesh other = box;
  other.triangles.pop_back();
  EXPECT_THROW(volumetric_map(tets, box, other), InputError);
  TriMesh moved = box;
  moved.points[0].x() += 0.1;
  EXPECT_THROW(volumetric_map(tets, moved, box), InputError);  // not the tet mesh's points
  EXPECT_THROW(volumetric_map(TetMesh{}, box, box), InputError);
  VolumetricMapOptions options;
  options.boundary_positions.assign(box.points.size() - 1, Vec3::Zero());
  EXPECT_THROW(volumetric_map(tets, box, box, options), InputError);
}

TEST(VolumetricMap, BoundaryPositionsOverrideTheTargetsPointsButNotItsFrames) {
  // Frames from the identity, the boundary pinned to the box shifted by t: the map is the
  // shift only where the frames agree with it, which they do (a shift has no rotation).
  const TriMesh box = test::subdivided_box(2, 1.5, 1, 4);
  const TetMesh tets = solid(box);
  const Vec3 shift(0.5, -2, 1);
  VolumetricMapOptions options;
  for (const Vec3& p : box.points) options.boundary_positions.push_back(p + shift);
  const VolumetricMap moved = volumetric_map(tets, box, box, options);
  EXPECT_EQ(moved.flipped, 0u);
  for (std::size_t i = 0; i < tets.points.size(); ++i)
    EXPECT_LT((moved.parameter[i] - (tets.points[i] + shift)).norm(), 1e-8) << "point " << i;
  // Scaled positions with unscaled frames: the boundary still goes exactly where asked.
  options.boundary_positions.clear();
  for (const Vec3& p : box.points) options.boundary_positions.push_back(1.2 * p);
  const VolumetricMap scaled = volumetric_map(tets, box, box, options);
  for (std::size_t i = 0; i < box.points.size(); ++i) EXPECT_EQ(scaled.parameter[i], Vec3(1.2 * box.points[i]));
  EXPECT_EQ(scaled.flipped, 0u);
}

}  // namespace
}  // namespace structmesh

namespace structmesh {
namespace {

TEST(SplitBoundaryTets, NoTetIsPinnedByTheBoundaryAndTheMeshStaysConforming) {
  // A coarse box: TetGen fills it with tets whose four points are all on the surface.
  const TriMesh box = test::subdivided_box(2, 1, 1, 2);
  TetmeshOptions options;
  options.size = 5;  // no interior points wanted
  TetMesh tets = tetrahedralize(box, options).mesh;
  const auto pinned = [&] {
    std::size_t count = 0;
    for (const auto& t : tets.tets)
      if (std::all_of(t.begin(), t.end(), [&](Index v) { return v < box.points.size(); })) ++count;
    return count;
  };
  ASSERT_GT(pinned(), 0u);
  double volume_before = 0;
  for (const auto& t : tets.tets)
    volume_before += tet_signed_volume(tets.points[t[0]], tets.points[t[1]], tets.points[t[2]], tets.points[t[3]]);
  const std::size_t boundary_faces_before = boundary_surface(tets).triangles.size();

  const std::size_t split = split_boundary_tets(tets, box.points.size());
  EXPECT_GT(split, 0u);
  EXPECT_EQ(pinned(), 0u);
  double volume_after = 0;
  for (const auto& t : tets.tets) {
    const double v = tet_signed_volume(tets.points[t[0]], tets.points[t[1]], tets.points[t[2]], tets.points[t[3]]);
    EXPECT_GT(v, 0);
    volume_after += v;
  }
  EXPECT_NEAR(volume_after, volume_before, 1e-12);
  // Conforming: every face in one or two tets, and the boundary is still the box's triangles.
  const FaceAdjacency<3> faces = build_faces(tets);
  EXPECT_TRUE(faces.extra_cells.empty());
  EXPECT_EQ(boundary_surface(tets).triangles.size(), boundary_faces_before);
  // No edge joins two boundary points unless it is an edge of the box's triangles.
  std::set<std::pair<Index, Index>> surface_edges;
  for (const auto& t : box.triangles)
    for (int k = 0; k < 3; ++k) surface_edges.emplace(std::minmax(t[k], t[(k + 1) % 3]));
  for (const auto& t : tets.tets)
    for (const auto& e : kTetEdges) {
      const Index a = t[e[0]], b = t[e[1]];
      if (a < box.points.size() && b < box.points.size()) {
        EXPECT_TRUE(surface_edges.count(std::minmax(a, b))) << a << " " << b;
      }
    }
  // Nothing to do the second time.
  EXPECT_EQ(split_boundary_tets(tets, box.points.size()), 0u);
  EXPECT_THROW(split_boundary_tets(tets, tets.points.size() + 1), InputError);
}

}  // namespace
}  // namespace structmesh
