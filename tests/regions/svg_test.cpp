#include "region_test_util.hpp"
#include "structmesh/regions.hpp"
#include "structmesh/render.hpp"

#include <gtest/gtest.h>

namespace structmesh {
namespace {

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

TEST(Svg, OnePathPerPolygonWithEvenOddHoles) {
  const std::vector<Polygon2> polygons{make_key_region(2000), make_pipe_region(4000)};
  SvgOptions options;
  options.title = "Key & <Pipe>";
  const std::string svg = region_svg(polygons, options);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(occurrences(svg, "<path"), 2u);
  EXPECT_EQ(occurrences(svg, "fill-rule=\"evenodd\""), 2u);
  EXPECT_EQ(occurrences(svg, "Z"), 1u + 1u + 1u + 9u);  // one closed subpath per ring
  EXPECT_NE(svg.find("Key &amp; &lt;Pipe&gt;"), std::string::npos);
  EXPECT_EQ(svg.find("<Pipe>"), std::string::npos);
}

TEST(Svg, NorthIsUpAndCoordinatesAreRounded) {
  // A triangle with its apex north: the apex gets the smallest SVG y.
  SvgOptions options;
  options.width_px = 108;  // margin 4 px, so 100 px for 1 unit
  const std::string svg = region_svg({test::make_polygon({{{0, 0}, {1, 0}, {0.5, 1.0 / 3}}})}, options);
  EXPECT_NE(svg.find("d=\"M4 37.33L104 37.33 54 4Z\""), std::string::npos) << svg;
  EXPECT_NE(svg.find("height=\"42\""), std::string::npos) << svg;
}

TEST(Svg, DropsVerticesThatRoundTogether) {
  std::vector<Vec2> ring{{0, 0}, {1, 0}};
  for (int i = 0; i < 1000; ++i) ring.emplace_back(1, 1 + i * 1e-9);  // all on one pixel spot
  ring.emplace_back(0, 1);
  SvgOptions options;
  options.width_px = 108;
  const std::string svg = region_svg({test::make_polygon({ring})}, options);
  EXPECT_NE(svg.find("d=\"M4 104L104 104 104 4 4 4Z\""), std::string::npos) << svg;
}

TEST(Svg, LargeRegionsStayCompact) {
  const std::string svg = region_svg({make_key_region(200000)});
  EXPECT_LT(svg.size(), 200000u * 16);
  EXPECT_EQ(occurrences(svg, "<path"), 1u);
}

}  // namespace
}  // namespace structmesh
