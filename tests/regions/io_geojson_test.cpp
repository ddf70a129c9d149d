#include "region_test_util.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace structmesh {
namespace {

using test::make_polygon;
using test::rectangle;

// The message of the InputError that `read` throws (fails the test if none).
template <typename Read>
std::string error_of(Read&& read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

std::string geojson_error(const std::string& text) {
  return error_of([&] { read_geojson(text, "in.geojson"); });
}

void expect_same(const std::vector<Polygon2>& a, const std::vector<Polygon2>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t p = 0; p < a.size(); ++p) {
    EXPECT_EQ(a[p].ring_offsets, b[p].ring_offsets) << "polygon " << p;
    EXPECT_EQ(a[p].points, b[p].points) << "polygon " << p;  // exact, bit for bit
    EXPECT_EQ(a[p].coordinates, b[p].coordinates) << "polygon " << p;
  }
}

TEST(GeoJson, RoundTripIsExact) {
  // Values with no short decimal form, tiny and huge magnitudes.
  Polygon2 awkward = make_polygon({{{0.1, 1.0 / 3}, {1e-300, 0.2}, {1234567.890123456789, 0.7}, {0.3, 1e15 / 7}},
                                   {{0.2, 0.9}, {0.35, 0.9}, {0.3, 1.1}}});
  Polygon2 second = make_polygon({rectangle(-5e6, -3e6, -4e6, -2e6)});
  std::vector<Polygon2> polygons{awkward, second};
  for (Polygon2& polygon : polygons) {
    // Normalised first, so the comparison is about coordinates only.
    const auto back = read_geojson(write_geojson({polygon}), "x");
    polygon = back[0];
  }
  expect_same(read_geojson(write_geojson(polygons), "round.geojson"), polygons);
  EXPECT_EQ(polygons[0].coordinates, Polygon2::Coordinates::Planar);
}

TEST(GeoJson, HugeCoordinatesRoundTrip) {
  // The area overflows to infinity, which JSON cannot hold: the property becomes null.
  const std::vector<Polygon2> polygons{make_polygon({{{0, 1e308}, {2, 1}, {3, 0}}})};
  const std::string text = write_geojson(polygons);
  EXPECT_NE(text.find("\"area\":null"), std::string::npos) << text;
  expect_same(read_geojson(text, "huge"), polygons);
  expect_same(read_poly(write_poly(polygons), "huge"), polygons);
}

TEST(GeoJson, OrientationIsNormalisedKeepingTheFirstPoint) {
  const std::string text = R"({"type":"Polygon","coordinates":[
      [[0,0],[0,10],[10,10],[10,0],[0,0]],
      [[2,2],[4,2],[4,4],[2,4],[2,2]]]})";
  const auto polygons = read_geojson(text, "cw.geojson");
  ASSERT_EQ(polygons.size(), 1u);
  const Polygon2& p = polygons[0];
  ASSERT_EQ(p.ring_count(), 2u);
  EXPECT_EQ(p.ring(0).size(), 4u);  // closing point dropped
  EXPECT_GT(signed_area(p.ring(0)), 0);
  EXPECT_LT(signed_area(p.ring(1)), 0);
  EXPECT_EQ(p.ring(0)[0], Vec2(0, 0));
  EXPECT_EQ(p.ring(0)[1], Vec2(10, 0));
  EXPECT_EQ(p.ring(1)[0], Vec2(2, 2));
  EXPECT_EQ(p.ring(1)[1], Vec2(2, 4));
  EXPECT_DOUBLE_EQ(area(p), 96);

  // And the writer emits RFC 7946 orientation even for unnormalised input.
  const Polygon2 clockwise = make_polygon({rectangle(0, 0, 1, 1, true)});
  const std::string out = write_geojson({clockwise});
  EXPECT_NE(out.find("[[0,0],[1,0],[1,1],[0,1],[0,0]]"), std::string::npos) << out;
}

TEST(GeoJson, UnclosedRingsAreRejectedWithTheirLocation) {
  try {
    read_geojson(R"({"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,0]],[[0.2,0.1],[0.8,0.1],[0.8,0.5]]]})",
                 "open.geojson");
    FAIL() << "an unclosed ring was accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("open.geojson"), std::string::npos) << message;
    EXPECT_NE(message.find("ring 1"), std::string::npos) << message;
    EXPECT_NE(message.find("not closed"), std::string::npos) << message;
  }
}

TEST(GeoJson, AllPolygonalContainers) {
  const std::string text = R"({"type":"FeatureCollection","features":[
    {"type":"Feature","properties":null,"geometry":{"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,0]]]}},
    {"type":"Feature","properties":{},"geometry":{"type":"MultiPolygon","coordinates":[
        [[[2,0],[3,0],[3,1],[2,0]]], [[[4,0],[5,0],[5,1],[4,0]]]]}},
    {"type":"Feature","geometry":{"type":"GeometryCollection","geometries":[
        {"type":"Polygon","coordinates":[[[6,0],[7,0],[7,1],[6,0]]]},
        {"type":"GeometryCollection","geometries":[{"type":"Polygon","coordinates":[[[8,0],[9,0],[9,1],[8,0]]]}]}]}}
  ]})";
  const auto polygons = read_geojson(text, "all.geojson");
  ASSERT_EQ(polygons.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(polygons[i].ring(0)[0], Vec2(2.0 * i, 0));
  EXPECT_EQ(
      read_geojson(R"({"type":"Feature","geometry":{"type":"Polygon","coordinates":[[[0,0],[1,0],[0,1],[0,0]]]}})", "f")
          .size(),
      1u);
}

TEST(GeoJson, PartitionSeparatorsAreSkippedOtherLinesRejected) {
  const std::string parts = R"({"type":"FeatureCollection","features":[
    {"type":"Feature","properties":{"part":0,"kind":"part"},"geometry":{"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,0]]]}},
    {"type":"Feature","properties":{"kind":"separator","left":0,"right":1},"geometry":{"type":"LineString","coordinates":[[0,0],[1,1]]}}
  ]})";
  EXPECT_EQ(read_geojson(parts, "parts.geojson").size(), 1u);
  const std::string road = R"({"type":"FeatureCollection","features":[
    {"type":"Feature","properties":{"part":0},"geometry":{"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,0]]]}},
    {"type":"Feature","properties":{"kind":"road"},"geometry":{"type":"LineString","coordinates":[[0,0],[1,1]]}}
  ]})";
  EXPECT_THROW(read_geojson(road, "road.geojson"), InputError);
}

TEST(GeoJson, CoordinateKind) {
  const std::string small = R"({"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,0]]]})";
  EXPECT_EQ(read_geojson(small, "a")[0].coordinates, Polygon2::Coordinates::LonLat);
  const std::string big = R"({"type":"Polygon","coordinates":[[[0,0],[500,0],[1,1],[0,0]]]})";
  EXPECT_EQ(read_geojson(big, "a")[0].coordinates, Polygon2::Coordinates::Planar);
  const std::string marked =
      R"({"type":"Polygon","structmesh:coordinates":"planar","coordinates":[[[0,0],[1,0],[1,1],[0,0]]]})";
  EXPECT_EQ(read_geojson(marked, "a")[0].coordinates, Polygon2::Coordinates::Planar);
  const std::string projected =
      R"({"type":"Polygon","crs":{"type":"name","properties":{"name":"urn:ogc:def:crs:EPSG::3857"}},
          "coordinates":[[[0,0],[1,0],[1,1],[0,0]]]})";
  EXPECT_EQ(read_geojson(projected, "a")[0].coordinates, Polygon2::Coordinates::Planar);
  const std::string crs84 =
      R"({"type":"Polygon","crs":{"type":"name","properties":{"name":"urn:ogc:def:crs:OGC:1.3:CRS84"}},
          "coordinates":[[[0,0],[1,0],[1,1],[0,0]]]})";
  EXPECT_EQ(read_geojson(crs84, "a")[0].coordinates, Polygon2::Coordinates::LonLat);
  EXPECT_NE(geojson_error(R"({"type":"Polygon","structmesh:coordinates":"utm","coordinates":[]})")
                .find("structmesh:coordinates"),
            std::string::npos);
}

TEST(GeoJson, CoordinateKindSurvivesRoundTrip) {
  Polygon2 planar = make_polygon({rectangle(0, 0, 1, 1)});
  Polygon2 lon_lat = make_polygon({rectangle(10, 10, 11, 11)});
  lon_lat.coordinates = Polygon2::Coordinates::LonLat;
  Polygon2 lon_lat_far = make_polygon({rectangle(170, 80, 190, 95)});  // out of range, but says lon/lat
  lon_lat_far.coordinates = Polygon2::Coordinates::LonLat;

  const std::string planar_text = write_geojson({planar});
  EXPECT_NE(planar_text.find("\"structmesh:coordinates\":\"planar\""), std::string::npos);
  EXPECT_EQ(read_geojson(planar_text, "p")[0].coordinates, Polygon2::Coordinates::Planar);

  const std::string lon_lat_text = write_geojson({lon_lat});
  EXPECT_EQ(lon_lat_text.find("structmesh:coordinates"), std::string::npos);  // plain RFC 7946
  EXPECT_EQ(read_geojson(lon_lat_text, "l")[0].coordinates, Polygon2::Coordinates::LonLat);

  const std::vector<Polygon2> mixed{planar, lon_lat, lon_lat_far};
  expect_same(read_geojson(write_geojson(mixed), "m"), mixed);
}

TEST(GeoJson, SyntaxErrorsNameLineAndByte) {
  const std::string message = geojson_error("{\"type\":\"Polygon\",\n\"coordinates\": [[[0,0],[1,0],[1,1]]]\n,,}");
  EXPECT_NE(message.find("in.geojson:3:"), std::string::npos) << message;
  EXPECT_NE(message.find("byte"), std::string::npos) << message;
  EXPECT_NE(geojson_error("").find("invalid JSON"), std::string::npos);
  // NaN is not JSON; overflowing numbers are not finite.
  EXPECT_NE(geojson_error(R"({"type":"Polygon","coordinates":[[[0,0],[NaN,0],[1,1]]]})").find("invalid JSON"),
            std::string::npos);
  const std::string overflow = geojson_error(R"({"type":"Polygon","coordinates":[[[0,0],[1e999,0],[1,1]]]})");
  EXPECT_TRUE(overflow.find("invalid JSON") != std::string::npos || overflow.find("not finite") != std::string::npos)
      << overflow;
}

TEST(GeoJson, StructureErrorsNameTheFeatureAndVertex) {
  const std::string wrong_type = geojson_error(R"({"type":"FeatureCollection","features":[
      {"type":"Feature","geometry":{"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,0]]]}},
      {"type":"Feature","geometry":{"type":"LineString","coordinates":[[0,0],[1,0]]}}]})");
  EXPECT_NE(wrong_type.find("feature 1"), std::string::npos) << wrong_type;
  EXPECT_NE(wrong_type.find("LineString"), std::string::npos) << wrong_type;

  const std::string not_number =
      geojson_error(R"({"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,0]],[[0.1,0.1],[0.2,0.1],["x",0.2]]]})");
  EXPECT_NE(not_number.find("ring 1, vertex 2"), std::string::npos) << not_number;

  const std::string one_coordinate = geojson_error(R"({"type":"Polygon","coordinates":[[[0,0],[1],[1,1]]]})");
  EXPECT_NE(one_coordinate.find("vertex 1"), std::string::npos) << one_coordinate;

  const std::string two_points = geojson_error(R"({"type":"Polygon","coordinates":[[[0,0],[1,0],[0,0],[1,0]]]})");
  EXPECT_NE(two_points.find("fewer than 3 distinct"), std::string::npos) << two_points;

  const std::string multi = geojson_error(R"({"type":"MultiPolygon","coordinates":[
      [[[0,0],[1,0],[1,1],[0,0]]], [[[0,0],[1,0],[1,1],[0,0]]], [[[0,0],[1,0],[1,1],[0,0]],[[0,0],[0,0]]]]})");
  EXPECT_NE(multi.find("polygon 2, ring 1"), std::string::npos) << multi;

  EXPECT_NE(geojson_error(R"({"type":"FeatureCollection","features":[]})").find("no polygons"), std::string::npos);
  EXPECT_NE(geojson_error(R"({"type":"Feature","geometry":null})").find("no geometry"), std::string::npos);
  EXPECT_NE(geojson_error(R"([1,2,3])").find("not a JSON object"), std::string::npos);
  EXPECT_NE(geojson_error(R"({"type":"Polygon","coordinates":[]})").find("no rings"), std::string::npos);
  EXPECT_NE(geojson_error(R"({"coordinates":[]})").find("type"), std::string::npos);
}

struct RegionFile {
  const char* name;
  std::size_t outer_vertices, holes, total_vertices;
};

// /work/shared/data/README.md counts vertices without each ring's repeated closing
// position, which is exactly what Polygon2 stores.
const RegionFile kRegionFiles[] = {
    {"gulf_of_mexico.geojson", 22420, 1624, 41284},
    {"gulf_of_mexico_ne10m.geojson", 5269, 103, 7151},
    {"matagorda_bay.geojson", 861, 26, 991},
    {"west_bay_galveston.geojson", 210, 14, 517},
};

TEST(GeoJson, SharedDataRegionsReadAndAreValid) {
  for (const RegionFile& file : kRegionFiles) {
    SCOPED_TRACE(file.name);
    const auto path = test::data_dir() / "regions" / file.name;
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "missing " << path;
    const auto polygons = read_region(path);
    ASSERT_EQ(polygons.size(), 1u);
    const Polygon2& p = polygons[0];
    EXPECT_EQ(p.coordinates, Polygon2::Coordinates::LonLat);
    EXPECT_EQ(p.ring(0).size(), file.outer_vertices);
    EXPECT_EQ(p.hole_count(), file.holes);
    EXPECT_EQ(p.points.size(), file.total_vertices);
    const RegionReport report = check_region(polygons);
    EXPECT_TRUE(report.valid) << (report.problems.empty() ? "" : report.problems[0].message);
    EXPECT_EQ(report.holes, file.holes);
    EXPECT_GT(report.area, 0);

    // A GeoJSON round trip of real data is exact.
    expect_same(read_geojson(write_geojson(polygons), "again"), polygons);
  }
}

}  // namespace
}  // namespace structmesh
