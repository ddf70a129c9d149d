// smooth_surface_map (the distortion smoothing of the surface map onto the polycube, after
// §5.2.1's relaxation): an even map stays as it is, a map that crowds a face's points to one
// side spreads them out again without folding a triangle or leaving the cube, a strip squeezed
// over an edge of the cube moves back across it, folded triangles are left to the relaxation,
// and mismatched sizes are an input error.
#include "cube_image_check.hpp"
#include "polycube/shapes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace structmesh {
namespace {

using ImageCheck = test::CubeImageCheck;
ImageCheck check(const TriMesh& source, const std::vector<Vec3>& image) {
  return test::check_cube_image(source, image);
}

bool inside_top_face(const Vec3& p) { return p.z() == 1 && p.x() > 0 && p.x() < 1 && p.y() > 0 && p.y() < 1; }

TEST(SmoothSurfaceMap, AnEvenMapStaysAsItIs) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 6);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  std::vector<Vec3> image = source.points;
  const SurfaceMapSmoothing result = smooth_surface_map(source, image, cube, onto_cube);
  // Every triangle is mapped by a similarity with its share of the area: the energy's minimum.
  EXPECT_NEAR(result.energy_before, 1.0, 1e-9);
  EXPECT_NEAR(result.energy_after, 1.0, 1e-9);
  EXPECT_NEAR(result.worst_area_ratio_before, 1.0, 1e-9);
  double largest_move = 0;
  for (std::size_t v = 0; v < image.size(); ++v)
    largest_move = std::max(largest_move, (image[v] - source.points[v]).norm());
  EXPECT_LT(largest_move, 1e-6);
}

TEST(SmoothSurfaceMap, CrowdedPointsOfAFaceSpreadOut) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 8);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  // The top face's inner points crowd towards x = 0 (x -> x^3): no triangle folds, but those
  // next to the edge x = 1 stretch over most of the face.
  std::vector<Vec3> image = source.points;
  for (Vec3& p : image)
    if (inside_top_face(p)) p.x() = p.x() * p.x() * p.x();
  const ImageCheck before = check(source, image);
  ASSERT_EQ(before.inward, 0u);
  ASSERT_GT(before.worst_area_ratio, 5.0);

  const SurfaceMapSmoothing result = smooth_surface_map(source, image, cube, onto_cube);
  EXPECT_NEAR(result.worst_area_ratio_before, before.worst_area_ratio, 1e-6 * before.worst_area_ratio);
  EXPECT_LT(result.energy_after, result.energy_before);
  EXPECT_LT(result.energy_after, 1.05);
  EXPECT_GT(result.moved_points, 0u);
  const ImageCheck after = check(source, image);
  EXPECT_EQ(after.inward, 0u);
  EXPECT_LT(after.off_surface, 1e-9);
  EXPECT_LT(after.worst_area_ratio, 2.0);  // from 64
  // The function measures a triangle across an edge of the cube a little differently.
  EXPECT_NEAR(result.worst_area_ratio_after, after.worst_area_ratio, 0.05 * after.worst_area_ratio);
}

TEST(SmoothSurfaceMap, AStripSqueezedOverAnEdgeMovesBack) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 8);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  // Between the faces y = 0 and y = 1, the top face's image shrinks to x <= 0.5 and the edge
  // x = 1, z = 1 slides down the side face x = 1 to z = 0.75, that face's points above z = 0
  // squeezed below it: one row of triangles spans the strip x > 0.5 of the top and the strip
  // z > 0.75 of the side.
  std::vector<Vec3> image = source.points;
  for (Vec3& p : image) {
    if (p.y() == 0 || p.y() == 1) continue;  // the faces y = 0, 1 shear a little instead
    if (p.z() == 1 && p.x() < 1) p.x() *= 0.5;
    if (p.x() == 1 && p.z() > 0) p.z() *= 0.75;
  }
  const ImageCheck before = check(source, image);
  ASSERT_EQ(before.inward, 0u);
  ASSERT_GT(before.worst_area_ratio, 2.5);
  const SurfaceMapDefects defects_before = surface_map_defects(source, image, cube, onto_cube);

  const SurfaceMapSmoothing result = smooth_surface_map(source, image, cube, onto_cube);
  EXPECT_LT(result.energy_after, result.energy_before);
  const ImageCheck after = check(source, image);
  EXPECT_EQ(after.inward, 0u);
  EXPECT_LT(after.off_surface, 1e-9);
  EXPECT_LT(after.worst_area_ratio, before.worst_area_ratio / 4);
  EXPECT_LT(result.energy_after, 1.1);
  // Points of the side face went back up over z = 0.75, and points of the top face's
  // source went over the edge x = 1 or up to it.
  double highest_side = 0, furthest_top = 0;
  for (std::size_t v = 0; v < image.size(); ++v) {
    if (source.points[v].x() == 1 && source.points[v].z() < 1) highest_side = std::max(highest_side, image[v].z());
    if (source.points[v].z() == 1 && source.points[v].x() < 1) furthest_top = std::max(furthest_top, image[v].x());
  }
  EXPECT_GT(highest_side, 0.8);
  EXPECT_GT(furthest_top, 0.8);
  // Sliding over the edge wound no more rings other than once around their points (which
  // the barrier alone does not see across an edge), nor folded a triangle.
  const SurfaceMapDefects defects = surface_map_defects(source, image, cube, onto_cube);
  EXPECT_LE(defects.folded, defects_before.folded);
  EXPECT_LE(defects.branched_points, defects_before.branched_points);
}

TEST(SmoothSurfaceMap, FoldedTrianglesAreLeftToTheRelaxation) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 8);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  // Two neighbouring points inside the top face swap places: their triangles fold.
  std::vector<Vec3> image = source.points;
  std::vector<std::size_t> top;
  for (std::size_t v = 0; v < image.size(); ++v)
    if (inside_top_face(image[v]) && std::abs(image[v].y() - 0.5) < 1e-9) top.push_back(v);
  ASSERT_GE(top.size(), 2u);
  std::sort(top.begin(), top.end(), [&](std::size_t a, std::size_t b) { return image[a].x() < image[b].x(); });
  std::swap(image[top[2]], image[top[3]]);
  ASSERT_GT(check(source, image).inward, 0u);
  const std::vector<Vec3> folded = image;

  const SurfaceMapSmoothing result = smooth_surface_map(source, image, cube, onto_cube);
  // The swapped points keep their places; the energy leaves the folded triangles out.
  EXPECT_EQ(image[top[2]], folded[top[2]]);
  EXPECT_EQ(image[top[3]], folded[top[3]]);
  EXPECT_TRUE(std::isfinite(result.energy_before));
  EXPECT_LE(result.energy_after, result.energy_before);
  EXPECT_GT(check(source, image).inward, 0u);
}

TEST(SmoothSurfaceMap, MismatchedSizesAreAnInputError) {
  const TriMesh source = test::subdivided_box(1, 1, 1, 2);
  const TriMesh cube = test::unit_cube();
  const SurfaceProjection onto_cube(cube);
  std::vector<Vec3> image(source.points.size() - 1, Vec3::Zero());
  EXPECT_THROW(smooth_surface_map(source, image, cube, onto_cube), InputError);
}

}  // namespace
}  // namespace structmesh
