// Volume distortion D_v of §5.3.
#include "structmesh/error.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>

namespace structmesh {
namespace {

// Two corner tets of the unit cube, not sharing points, so each can be moved alone.
TetMesh two_tets() {
  TetMesh mesh;
  mesh.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
                 Vec3(5, 0, 0), Vec3(6, 0, 0), Vec3(5, 1, 0), Vec3(5, 0, 1)};
  mesh.tets = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  return mesh;
}

TEST(TetSignedVolume, PositiveInVtkOrder) {
  EXPECT_DOUBLE_EQ(tet_signed_volume(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)), 1.0 / 6);
  EXPECT_DOUBLE_EQ(tet_signed_volume(Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)), -1.0 / 6);
}

TEST(VolumeDistortion, IdenticalAndUniformlyScaledImagesGiveOne) {
  const TetMesh source = two_tets();
  EXPECT_DOUBLE_EQ(volume_distortion(source, source), 1.0);
  TetMesh scaled = source;
  for (Vec3& p : scaled.points) p = 3.0 * p + Vec3(1, 2, 3);
  EXPECT_DOUBLE_EQ(volume_distortion(source, scaled), 1.0);
}

TEST(VolumeDistortion, HandComputedNonUniformCase) {
  // The second tet is stretched 2x along x: v_s = (1/6, 1/6), v_t = (1/6, 2/6),
  // V_s = 2/6, V_t = 3/6, sum v_s/v_t = 1 + 1/2, D_v = (1/2) (3/2) (3/2) = 9/8.
  const TetMesh source = two_tets();
  TetMesh target = source;
  target.points[5] = Vec3(7, 0, 0);
  EXPECT_DOUBLE_EQ(volume_distortion(source, target), 9.0 / 8);
}

TEST(VolumeDistortion, AcceptsTheOtherOrientationConvention) {
  TetMesh source = two_tets();
  for (auto& t : source.tets) std::swap(t[1], t[2]);  // every volume negative
  TetMesh target = source;
  target.points[5] = Vec3(7, 0, 0);
  EXPECT_DOUBLE_EQ(volume_distortion(source, target), 9.0 / 8);
}

TEST(VolumeDistortion, RejectsMismatchedFlattenedAndInvertedTets) {
  const TetMesh source = two_tets();
  TetMesh fewer = source;
  fewer.tets.pop_back();
  EXPECT_THROW(volume_distortion(source, fewer), InputError);
  EXPECT_THROW(volume_distortion(TetMesh{}, TetMesh{}), InputError);
  TetMesh flat = source;
  flat.points[7] = Vec3(5, 0.5, 0);  // apex in the base plane
  EXPECT_THROW(volume_distortion(source, flat), InputError);
  EXPECT_THROW(volume_distortion(flat, source), InputError);
  TetMesh inverted = source;
  inverted.points[7] = Vec3(5, 0, -1);
  EXPECT_THROW(volume_distortion(source, inverted), InputError);
}

}  // namespace
}  // namespace structmesh
