#include "mesh/planar_geometry.hpp"
#include "region_test_util.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/regions.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace structmesh {
namespace {

using test::make_polygon;
using test::rectangle;

std::string poly_error(const std::string& text) {
  try {
    read_poly(text, "in.poly");
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return {};
}

void expect_same(const std::vector<Polygon2>& a, const std::vector<Polygon2>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t p = 0; p < a.size(); ++p) {
    EXPECT_EQ(a[p].ring_offsets, b[p].ring_offsets) << "polygon " << p;
    EXPECT_EQ(a[p].points, b[p].points) << "polygon " << p;
    EXPECT_EQ(a[p].coordinates, b[p].coordinates) << "polygon " << p;
  }
}

// The hole points of a .poly written by write_poly (its last section).
std::vector<Vec2> hole_points(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') lines.push_back(line);
  std::size_t at = 0;
  const std::size_t vertices = std::stoul(lines[at]);
  at += 1 + vertices;
  const std::size_t segments = std::stoul(lines[at]);
  at += 1 + segments;
  const std::size_t holes = std::stoul(lines[at++]);
  std::vector<Vec2> points;
  for (std::size_t h = 0; h < holes; ++h) {
    std::istringstream row(lines[at++]);
    int number;
    double x, y;
    row >> number >> x >> y;
    points.emplace_back(x, y);
  }
  return points;
}

// Two polygons: a square with two holes, and an island (with its own lake) inside
// the first hole, which the hole point of that hole must avoid.
std::vector<Polygon2> islands_in_holes() {
  std::vector<Polygon2> polygons{
      make_polygon({rectangle(0, 0, 10, 10), rectangle(1, 1, 6, 6, true), rectangle(7, 7, 9, 9, true)}),
      make_polygon({rectangle(1.5, 1.5, 5.5, 5.5), rectangle(2, 2, 3, 3, true)})};
  return polygons;
}

TEST(Poly, RoundTripIsExactAndHolePointsAreInTheHoles) {
  std::vector<Polygon2> polygons = islands_in_holes();
  polygons[0].points[5] = Vec2(0.1 + 1.0 / 3, 6);  // an awkward coordinate
  const std::string text = write_poly(polygons);
  expect_same(read_poly(text, "round.poly"), polygons);

  const std::vector<Vec2> holes = hole_points(text);
  ASSERT_EQ(holes.size(), 3u);
  std::vector<std::span<const Vec2>> rings{polygons[0].ring(1), polygons[0].ring(2), polygons[1].ring(1),
                                           polygons[1].ring(0)};
  const detail::RingLocator locator(rings);
  // Hole 0 of polygon 0 (minus the island), hole 1 of polygon 0, the island's lake.
  EXPECT_EQ(locator.containing(holes[0], 99), std::vector<std::uint32_t>{0});
  EXPECT_EQ(locator.containing(holes[1], 99), std::vector<std::uint32_t>{1});
  EXPECT_EQ(locator.containing(holes[2], 99), (std::vector<std::uint32_t>{0, 2, 3}));
}

TEST(Poly, LonLatMarkerSurvivesRoundTrip) {
  Polygon2 polygon = make_polygon({rectangle(-95, 29, -94, 30)});
  polygon.coordinates = Polygon2::Coordinates::LonLat;
  expect_same(read_poly(write_poly({polygon}), "ll.poly"), {polygon});
  polygon.coordinates = Polygon2::Coordinates::Planar;
  expect_same(read_poly(write_poly({polygon}), "pl.poly"), {polygon});
}

TEST(Poly, ReadsTriangleStyleFiles) {
  // Zero-based, comments, blank lines, attributes, markers, shuffled and
  // inconsistently directed segments, a regional attribute section.
  const std::string text = R"(# a square with a square hole
8 2 1 1
0 0 0 5.0 1
1 4 0 5.0 1
2 4 4 5.0 1   # comment after data
3 0 4 5.0 1

4 1 1 0 2
5 1 2 0 2
6 2 2 0 2
7 2 1 0 2
8 1
0 0 1 1
1 2 1 1
2 2 3 1
3 3 0 1
4 4 5 2
5 6 5 2
6 6 7 2
7 7 4 2
1
0 1.5 1.5
1
0 3 3 1 0.1
)";
  const auto polygons = read_poly(text, "tri.poly");
  ASSERT_EQ(polygons.size(), 1u);
  const Polygon2& p = polygons[0];
  ASSERT_EQ(p.ring_count(), 2u);
  EXPECT_EQ(p.coordinates, Polygon2::Coordinates::Planar);
  EXPECT_DOUBLE_EQ(area(p), 15);
  EXPECT_GT(signed_area(p.ring(0)), 0);
  EXPECT_LT(signed_area(p.ring(1)), 0);
  EXPECT_EQ(p.ring(0)[0], Vec2(0, 0));

  // Minimal headers (dimension and counts optional), no hole section at all.
  const auto bare = read_poly("3\n1 0 0\n2 1 0\n3 0 1\n3\n1 1 2\n2 2 3\n3 3 1\n", "bare.poly");
  ASSERT_EQ(bare.size(), 1u);
  EXPECT_EQ(bare[0].ring(0).size(), 3u);
}

TEST(Poly, NestingDecidesHolesAndOwners) {
  // Three nested squares plus a separate one, listed innermost first and with
  // mixed directions: depth 0 and 2 are outer rings, depth 1 a hole.
  std::vector<Polygon2> shuffled{make_polygon({rectangle(4, 4, 6, 6, true)}), make_polygon({rectangle(20, 0, 21, 1)}),
                                 make_polygon({rectangle(0, 0, 10, 10, true)}), make_polygon({rectangle(2, 2, 8, 8)})};
  const auto polygons = read_poly(write_poly(shuffled), "nested.poly");
  ASSERT_EQ(polygons.size(), 3u);
  std::vector<double> areas;
  for (const Polygon2& p : polygons) areas.push_back(area(p));
  EXPECT_EQ(polygons[0].ring_count(), 1u);  // the innermost square, first in the file
  EXPECT_DOUBLE_EQ(areas[0], 4);
  EXPECT_DOUBLE_EQ(areas[1], 1);
  EXPECT_EQ(polygons[2].ring_count(), 2u);  // the big square with the 6x6 hole
  EXPECT_DOUBLE_EQ(areas[2], 64);
  EXPECT_TRUE(check_region(polygons).valid);
}

TEST(Poly, ErrorsNameTheLine) {
  const std::string header = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n";
  // Segment 3 refers to vertex 9 on line 9.
  std::string message = poly_error(header + "4 0\n1 1 2\n2 2 3\n3 3 9\n4 4 1\n0\n");
  EXPECT_NE(message.find("in.poly:9:"), std::string::npos) << message;
  EXPECT_NE(message.find("vertex 9"), std::string::npos) << message;
  // A dangling segment: no segment closes 4 back to 1, so 1-2 (line 7) dangles at vertex 1.
  message = poly_error(header + "3 0\n1 1 2\n2 2 3\n3 3 4\n0\n");
  EXPECT_NE(message.find("in.poly:7:"), std::string::npos) << message;
  EXPECT_NE(message.find("dangling"), std::string::npos) << message;
  // A vertex on three segments.
  message = poly_error(header + "5 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 1 3\n0\n");
  EXPECT_NE(message.find("in.poly:11:"), std::string::npos) << message;
  EXPECT_NE(message.find("more than two"), std::string::npos) << message;
  // A two-vertex loop.
  message = poly_error(header + "2 0\n1 1 2\n2 2 1\n0\n");
  EXPECT_NE(message.find("fewer than 3"), std::string::npos) << message;
  // Coordinates and numbering.
  message = poly_error("3 2 0 0\n1 0 0\n2 nan 0\n3 0 1\n");
  EXPECT_NE(message.find("in.poly:3:"), std::string::npos) << message;
  message = poly_error("3 2 0 0\n1 0 0\n3 1 0\n2 0 1\n");
  EXPECT_NE(message.find("in.poly:3:"), std::string::npos) << message;
  message = poly_error("3 2 0 0\n1 0 0\n2 1\n3 0 1\n");
  EXPECT_NE(message.find("in.poly:3: line ends before the y coordinate"), std::string::npos) << message;
  EXPECT_NE(poly_error("0 2 0 1\n").find(".node"), std::string::npos);
  EXPECT_NE(poly_error("3 3 0 0\n").find("dimension"), std::string::npos);
  EXPECT_NE(poly_error("").find("file ends"), std::string::npos);
  message = poly_error(header + "4 0\n1 1 2\n2 2 3\n");
  EXPECT_NE(message.find("file ends before segment 2 of 4"), std::string::npos) << message;
  EXPECT_NE(poly_error(header + "1 0\n1 1 1\n").find("to itself"), std::string::npos);
  EXPECT_NE(poly_error("1000000000 2 0 0\n1 0 0\n").find("file ends"), std::string::npos);  // no huge allocation
}

TEST(Poly, GulfRoundTrip) {
  const auto path = test::data_dir() / "regions" / "gulf_of_mexico_ne10m.geojson";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "missing " << path;
  const auto polygons = read_region(path);
  expect_same(read_poly(write_poly(polygons), "gulf.poly"), polygons);
}

TEST(Poly, KeyRoundTripThroughAFile) {
  const std::vector<Polygon2> key{make_key_region(3000)};
  const auto path = std::filesystem::path(STRUCTMESH_BINARY_DIR) / "key_roundtrip_test.poly";
  write_region(path, key);
  expect_same(read_region(path), key);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace structmesh
