// relax_surface_map (§5.2.1's relaxation of the surface map onto the polycube): folds put into
// the image of a subdivided box on the unit cube come out, the points stay on the cube, and a
// map without folds is left as it is.
#include "cube_image_check.hpp"
#include "polycube/shapes.hpp"
#include "structmesh/hex.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <vector>

namespace structmesh {
namespace {

using ImageCheck = test::CubeImageCheck;
ImageCheck check(const TriMesh& source, const std::vector<Vec3>& image) {
  return test::check_cube_image(source, image);
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
  // The points inside the top face are thrown up to 1.2 grid steps within it: their order
  // no longer matches the source's and many triangles fold.
  std::vector<Vec3> image = source.points;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  for (Vec3& p : image)
    if (p.z() == 1 && p.x() > 0 && p.x() < 1 && p.y() > 0 && p.y() < 1)
      p.x() = std::clamp(p.x() + jitter(random), 0.01, 0.99), p.y() = std::clamp(p.y() + jitter(random), 0.01, 0.99);
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

}  // namespace
}  // namespace structmesh
