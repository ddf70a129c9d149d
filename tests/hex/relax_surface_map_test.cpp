// relax_surface_map (§5.2.1's relaxation of the surface map onto the polycube): folds put into
// the image of a subdivided box on the unit cube come out, the points stay on the cube, and a
// map without folds is left as it is.
#include "cube_image_check.hpp"
#include "polycube/shapes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace structmesh {
namespace {

using ImageCheck = test::CubeImageCheck;
ImageCheck check(const TriMesh& source, const std::vector<Vec3>& image) {
  return test::check_cube_image(source, image);
}

// The points inside the top face of the unit cube thrown up to 1.2 grid steps (of an 8 x 8
// subdivision) within it: their order no longer matches the source's and many triangles fold.
void shuffle_top_face(std::vector<Vec3>& image) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  for (Vec3& p : image)
    if (p.z() == 1 && p.x() > 0 && p.x() < 1 && p.y() > 0 && p.y() < 1)
      p.x() = std::clamp(p.x() + jitter(random), 0.01, 0.99), p.y() = std::clamp(p.y() + jitter(random), 0.01, 0.99);
}

TEST(RelaxSurfaceMap, AnUnfoldedMapStaysAsItIs) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 6);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  std::vector<Vec3> image = source.points;
  const SurfaceMapRelaxation result = relax_surface_map(source, image, cube, onto_cube);
  EXPECT_EQ(result.folded_before, 0u);
  EXPECT_EQ(result.folded_after, 0u);
  EXPECT_EQ(result.moved_points, 0u);
  EXPECT_EQ(image, source.points);
}

TEST(RelaxSurfaceMap, ShuffledPointsOfAFaceUnfold) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 8);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  std::vector<Vec3> image = source.points;
  shuffle_top_face(image);
  const ImageCheck before = check(source, image);
  ASSERT_GT(before.inward, 10u);

  const SurfaceMapRelaxation result = relax_surface_map(source, image, cube, onto_cube);
  EXPECT_GE(result.folded_before, before.inward);
  EXPECT_EQ(result.folded_after, 0u);
  EXPECT_GT(result.moved_points, 0u);
  const ImageCheck after = check(source, image);
  EXPECT_EQ(after.inward, 0u);
  EXPECT_LT(after.off_surface, 1e-9);
}

TEST(FoldedTriangles, CountsWhatTheRelaxationStartsFromAndMovesNothing) {
  // The shuffled face above: folded_triangles() is the relaxation's own count before it
  // moves anything (polycube_hex_mesh() reads it to skip a hopeless relaxation).
  const TriMesh source = test::subdivided_box(1, 1, 1, 8);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  EXPECT_EQ(folded_triangles(source, source.points, cube, onto_cube), 0u);
  std::vector<Vec3> image = source.points;
  shuffle_top_face(image);
  const std::vector<Vec3> shuffled = image;
  const std::size_t folded = folded_triangles(source, image, cube, onto_cube);
  EXPECT_EQ(image, shuffled);
  EXPECT_GE(folded, check(source, image).inward);
  EXPECT_GT(folded, 10u);
  EXPECT_EQ(relax_surface_map(source, image, cube, onto_cube).folded_before, folded);
  image.pop_back();
  EXPECT_THROW(folded_triangles(source, image, cube, onto_cube), InputError);
}

TEST(RelaxSurfaceMap, AFoldAcrossAnEdgeOfTheCubeUnfolds) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 8);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  // A strip of the top face next to the edge x = 1 is pushed over the edge onto the side
  // face x = 1, past the side face's own first row: the two sheets overlap there.
  std::vector<Vec3> image = source.points;
  for (Vec3& p : image)
    if (p.z() == 1 && p.x() > 0.8 && p.x() < 1 && p.y() > 0 && p.y() < 1) p = Vec3(1, p.y(), 0.8);
  ASSERT_GT(check(source, image).inward, 0u);

  const SurfaceMapRelaxation result = relax_surface_map(source, image, cube, onto_cube);
  EXPECT_GT(result.folded_before, 0u);
  EXPECT_EQ(result.folded_after, 0u);
  const ImageCheck after = check(source, image);
  EXPECT_EQ(after.inward, 0u);
  EXPECT_LT(after.off_surface, 1e-9);
}

TEST(SurfaceMapDefects, AOneToOneMapHasNone) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 6);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  const SurfaceMapDefects defects = surface_map_defects(source, source.points, cube, onto_cube);
  EXPECT_EQ(defects.folded, 0u);
  EXPECT_EQ(defects.branched_points, 0u);
  EXPECT_NEAR(defects.area_excess, 0.0, 1e-12);
  EXPECT_THROW(surface_map_defects(source, std::vector<Vec3>(3, Vec3::Zero()), cube, onto_cube), InputError);
}

// The ring of the top face's centre point laid twice around it (its six neighbours 120
// degrees apart, in their order): every triangle at the centre faces out, yet the image
// covers the face twice there.
std::vector<Vec3> branched_at_top_centre(const TriMesh& source, Index& centre, const Vec3& at = Vec3(0.5, 0.5, 1),
                                         double outer = 0.6) {
  centre = kInvalidIndex;
  for (std::size_t v = 0; v < source.points.size(); ++v)
    if ((source.points[v] - at).norm() < 1e-12) centre = static_cast<Index>(v);
  std::vector<Index> ring;
  for (const auto& t : source.triangles)
    for (int k = 0; k < 3; ++k)
      if (t[k] == centre)
        for (int j = 1; j < 3; ++j)
          if (std::find(ring.begin(), ring.end(), t[(k + j) % 3]) == ring.end()) ring.push_back(t[(k + j) % 3]);
  auto angle = [&](Index v) {
    const Vec3 d = source.points[v] - source.points[centre];
    return std::atan2(d.y(), d.x());
  };
  std::sort(ring.begin(), ring.end(), [&](Index a, Index b) { return angle(a) < angle(b); });
  std::vector<Vec3> image = source.points;
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const double turn =
        angle(ring[0]) + 4 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(ring.size());
    const double radius = (source.points[ring[k]] - source.points[centre]).norm() * (2 * k < ring.size() ? 1.0 : outer);
    image[ring[k]] = source.points[centre] + radius * Vec3(std::cos(turn), std::sin(turn), 0);
  }
  return image;
}

TEST(SurfaceMapDefects, ABranchPointIsFound) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 8);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  Index centre = 0;
  const std::vector<Vec3> image = branched_at_top_centre(source, centre);
  ASSERT_NE(centre, kInvalidIndex);
  const SurfaceMapDefects defects = surface_map_defects(source, image, cube, onto_cube);
  EXPECT_GE(defects.branched_points, 1u);
  EXPECT_GT(defects.area_excess, 0.0);  // the face covered twice near the centre
}

TEST(RelaxSurfaceMap, ABranchPointNextToAnEdgeComesOut) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 8);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  // The branch point next to the edge x = 1 of the top face, two of its neighbours pushed over
  // the edge onto the side face. Whether the fold relaxation alone undoes it depends on the
  // last bits of its arithmetic (it left it at -O3, undid it at -O1); after the relaxation
  // the map must be one-to-one either way.
  Index centre = 0;
  std::vector<Vec3> image = branched_at_top_centre(source, centre, Vec3(7 / 8.0, 4 / 8.0, 1));
  ASSERT_NE(centre, kInvalidIndex);
  for (Vec3& p : image) p = onto_cube.closest_point(p);
  ASSERT_GE(surface_map_defects(source, image, cube, onto_cube).branched_points, 1u);

  const SurfaceMapRelaxation result = relax_surface_map(source, image, cube, onto_cube);
  EXPECT_EQ(result.branched_after, 0u);
  EXPECT_EQ(result.folded_after, 0u);
  const SurfaceMapDefects defects = surface_map_defects(source, image, cube, onto_cube);
  EXPECT_EQ(defects.folded, 0u);
  EXPECT_EQ(defects.branched_points, 0u);
  EXPECT_LE(defects.area_excess, 1e-9);  // one-to-one: the cube covered once
  const ImageCheck after = check(source, image);
  EXPECT_EQ(after.inward, 0u);
  EXPECT_LT(after.off_surface, 1e-9);
}

TEST(UnwindSurfaceMap, ABranchPointIsLaidOutAfresh) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 8);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  Index centre = 0;
  std::vector<Vec3> image = branched_at_top_centre(source, centre);
  ASSERT_NE(centre, kInvalidIndex);
  const std::vector<Vec3> branched = image;

  const SurfaceMapUnwinding result = unwind_surface_map(source, image, cube, onto_cube, 2);
  EXPECT_GE(result.branched_before, 1u);
  EXPECT_EQ(result.branched_after, 0u);
  EXPECT_GT(result.moved_points, 0u);
  // Within a convex rim on one face, the barycentric layout folds nothing: one-to-one.
  const SurfaceMapDefects defects = surface_map_defects(source, image, cube, onto_cube);
  EXPECT_EQ(defects.folded, 0u);
  EXPECT_EQ(defects.branched_points, 0u);
  EXPECT_LE(defects.area_excess, 1e-9);
  const ImageCheck after = check(source, image);
  EXPECT_EQ(after.inward, 0u);
  EXPECT_LT(after.off_surface, 1e-9);
  // Only the region moved: points more than three rings from the centre (an L-infinity
  // distance of over 3 grid steps on the top face, or off it) kept their places.
  for (std::size_t v = 0; v < image.size(); ++v) {
    const Vec3 d = source.points[v] - source.points[centre];
    if (d.cwiseAbs().maxCoeff() > 3.5 / 8) {
      EXPECT_EQ(image[v], branched[v]) << v;
    }
  }
  // A map without branch points is left as it is.
  std::vector<Vec3> even = source.points;
  const SurfaceMapUnwinding none = unwind_surface_map(source, even, cube, onto_cube);
  EXPECT_EQ(none.branched_before, 0u);
  EXPECT_EQ(none.moved_points, 0u);
  EXPECT_EQ(even, source.points);
  EXPECT_THROW(unwind_surface_map(source, even, cube, onto_cube, -1), InputError);
  std::vector<Vec3> short_image(3, Vec3::Zero());
  EXPECT_THROW(unwind_surface_map(source, short_image, cube, onto_cube), InputError);
}

}  // namespace
}  // namespace structmesh
