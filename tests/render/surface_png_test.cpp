// surface_image(): the z-buffer shows the face nearest the viewer, labels pick colours,
// markers are drawn on top, bad arguments are refused.
#include "structmesh/error.hpp"
#include "structmesh/render.hpp"

#include <gtest/gtest.h>

#include <array>
#include <set>
#include <vector>

namespace structmesh {
namespace {

// Two parallel squares facing +z, at z = 0 (label 0) and z = 1 (label 1), the upper one
// smaller.
TriMesh two_squares() {
  TriMesh mesh;
  mesh.points = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {1, 1, 1}, {3, 1, 1}, {3, 3, 1}, {1, 3, 1}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  return mesh;
}

std::array<std::uint8_t, 3> pixel(const Image& image, int x, int y) {
  const std::uint8_t* p = &image.rgb[(static_cast<std::size_t>(y) * image.width + x) * 3];
  return {p[0], p[1], p[2]};
}

// Lit straight on, a face shows its label's colour at full brightness.
TEST(SurfacePng, NearestFaceWinsAndLabelsPickColours) {
  SurfacePictureOptions options;
  options.width_px = 200;
  options.azimuth_deg = 0;
  options.elevation_deg = 90;  // looking down -z: the z = 1 square is in front
  const std::vector<std::int32_t> labels{0, 0, 1, 1};
  const Image image = surface_image(two_squares(), labels, {}, options);
  const int cx = image.width / 2, cy = image.height / 2;
  EXPECT_EQ(pixel(image, cx, cy), label_color(1));  // the upper square covers the centre
  EXPECT_EQ(pixel(image, 20, cy), label_color(0));  // only the lower one out there
  EXPECT_NE(label_color(0), label_color(1));
  // From below the lower square hides the upper one.
  options.elevation_deg = -90;
  const Image below = surface_image(two_squares(), labels, {}, options);
  EXPECT_EQ(pixel(below, below.width / 2, below.height / 2), label_color(0));
}

TEST(SurfacePng, DistinctLabelsGetDistinctColoursAndMarkersAreDrawn) {
  std::set<std::array<std::uint8_t, 3>> colours;
  for (std::int32_t label = 0; label < 24; ++label) colours.insert(label_color(label));
  EXPECT_EQ(colours.size(), 24u);
  EXPECT_EQ(label_color(-1), (std::array<std::uint8_t, 3>{200, 200, 200}));
  SurfacePictureOptions options;
  options.width_px = 200;
  options.azimuth_deg = 0;
  options.elevation_deg = 90;
  const std::vector<Vec3> marker{{2, 2, 0.5}};
  const Image image = surface_image(two_squares(), std::vector<std::int32_t>{0, 0, 1, 1}, marker, options);
  EXPECT_EQ(pixel(image, image.width / 2, image.height / 2), (std::array<std::uint8_t, 3>{255, 255, 255}));
  const std::string png = surface_png(two_squares(), std::vector<std::int32_t>{0, 0, 1, 1}, marker, options);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
}

TEST(SurfacePng, BadArgumentsAreRefused) {
  EXPECT_THROW(surface_image(two_squares(), std::vector<std::int32_t>{0}, {}, {}), Error);
  SurfacePictureOptions tiny;
  tiny.width_px = 4;
  EXPECT_THROW(surface_image(two_squares(), std::vector<std::int32_t>{0, 0, 1, 1}, {}, tiny), InputError);
}

}  // namespace
}  // namespace structmesh
