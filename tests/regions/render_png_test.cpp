// The raster back end: even-odd fill leaves holes empty, fills the right area, and
// encodes a real PNG.
#include "structmesh/render.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace structmesh {
namespace {

Polygon2 square_with_hole() {
  Polygon2 p;
  const std::vector<Vec2> outer{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  const std::vector<Vec2> hole{{3, 3}, {3, 7}, {7, 7}, {7, 3}};
  p.add_ring(outer);
  p.add_ring(hole);
  return p;
}

std::size_t count_color(const Image& image, const std::array<std::uint8_t, 3>& color) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < image.rgb.size(); i += 3)
    n += image.rgb[i] == color[0] && image.rgb[i + 1] == color[1] && image.rgb[i + 2] == color[2];
  return n;
}

TEST(RenderPng, FillLeavesHoleEmptyAndMatchesArea) {
  const Polygon2 p = square_with_hole();
  Image image = Image::fit(p.bounding_box(), 220, 10);  // 20 px per unit
  ASSERT_EQ(image.width, 220);
  ASSERT_EQ(image.height, 220);
  fill_rings(image, p, {255, 0, 0});
  const double filled = static_cast<double>(count_color(image, {255, 0, 0}));
  const double expected = (100.0 - 16.0) * 20 * 20;  // region area in pixels
  EXPECT_NEAR(filled, expected, 0.01 * expected);
  // The centre of the hole and the margin stay white; a point in the ring is filled.
  const auto pixel = [&](double x, double y) {
    const Vec2 q = image.to_pixel({x, y});
    const std::size_t i = (static_cast<std::size_t>(q.y()) * image.width + static_cast<std::size_t>(q.x())) * 3;
    return std::array<std::uint8_t, 3>{image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]};
  };
  EXPECT_EQ(pixel(5, 5), (std::array<std::uint8_t, 3>{255, 255, 255}));
  EXPECT_EQ(pixel(1, 1), (std::array<std::uint8_t, 3>{255, 0, 0}));
  EXPECT_EQ(pixel(-0.4, 5), (std::array<std::uint8_t, 3>{255, 255, 255}));
}

TEST(RenderPng, NorthIsUp) {
  const Polygon2 p = square_with_hole();
  const Image image = Image::fit(p.bounding_box(), 220, 10);
  EXPECT_LT(image.to_pixel({0, 10}).y(), image.to_pixel({0, 0}).y());
}

TEST(RenderPng, EncodesAPngWithTheSignature) {
  const std::string png = region_png({square_with_hole()}, 64);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

TEST(RenderPng, LinesStayInsideTheImage) {
  Image image = Image::fit(square_with_hole().bounding_box(), 50, 5);
  draw_line(image, {-1e9, -1e9}, {1e9, 1e9}, {0, 0, 0});  // far outside: skipped, no crash
  draw_line(image, {0, 0}, {10, 10}, {0, 0, 0});
  EXPECT_GT(count_color(image, {0, 0, 0}), 30u);
}

}  // namespace
}  // namespace structmesh
