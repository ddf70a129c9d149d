// Partition files (design/partition2d.md §3.4): GeoJSON read back as the parts,
// SVG and PNG pictures with neighbours in different colours, and method names.
#include "partition2d/part_geometry_fixtures.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <gtest/gtest.h>
#include <png.h>
#include <nlohmann/json.hpp>

#include <array>
#include <map>
#include <set>
#include <string>

namespace structmesh::partition2d {
namespace {

using nlohmann::json;
using testing::build;
using testing::grid_faces;
using testing::make_tessellation;
using testing::unit_square;

Partition quadrants() {
  const Polygon2 region = unit_square();
  return build(make_tessellation(grid_faces(4, 4, {0, 0}, 0.25), region), testing::quadrant_labels(), 4, region);
}

Partition square_with_hole() {
  const testing::HoleFixture fixture;
  return build(make_tessellation(fixture.faces, fixture.region), fixture.labels, 2, fixture.region);
}

// The quadrants of a square with inexact input coordinates and a non-trivial frame.
Partition scaled_quadrants(Polygon2& region) {
  const Vec2 origin(0.1, 0.7);
  const double size = 0.3;
  region = testing::make_region({{origin, origin + Vec2(size, 0), origin + Vec2(size, size), origin + Vec2(0, size)}});
  const testing::TestFrame frame{1000, {321.5, 123.25}, 37.3};
  auto faces = grid_faces(4, 4, {0, 0}, 0.25);
  for (auto& face : faces)
    for (Vec2& q : face) q = origin + size * q;
  return build(make_tessellation(faces, region, frame), testing::quadrant_labels(), 4, region, frame);
}

// Part pairs that share a separator.
std::set<std::pair<int, int>> neighbour_pairs(const Partition& partition) {
  std::set<std::pair<int, int>> pairs;
  for (const PartitionCurve& curve : partition.curves)
    if (curve.kind == PartitionCurve::Kind::Separator) pairs.insert({curve.left_part, curve.right_part});
  return pairs;
}

void expect_geojson_round_trip(const Partition& partition, double input_area) {
  const json root = json::parse(write_partition_geojson(partition));
  ASSERT_EQ(root["type"], "FeatureCollection");
  // read_region rejects LineString features, so the polygons go back on their own.
  json polygons = root;
  polygons["features"] = json::array();
  std::size_t separators = 0;
  for (const json& feature : root["features"]) {
    const json& properties = feature["properties"];
    if (properties["kind"] == "part") {
      EXPECT_EQ(feature["geometry"]["type"], "Polygon");
      EXPECT_EQ(properties["part"].get<std::size_t>(), polygons["features"].size());
      EXPECT_EQ(properties["area"].get<double>(), partition.part_areas[properties["part"].get<std::size_t>()]);
      polygons["features"].push_back(feature);
      continue;
    }
    ASSERT_EQ(properties["kind"], "separator");
    ASSERT_EQ(feature["geometry"]["type"], "LineString");
    ++separators;
    // Every separator position is a vertex of both its parts, to the bit.
    for (const json& position : feature["geometry"]["coordinates"]) {
      const Vec2 q(position[0].get<double>(), position[1].get<double>());
      for (const char* side : {"left", "right"}) {
        const Polygon2& part = partition.parts[properties[side].get<std::size_t>()];
        EXPECT_NE(std::find(part.points.begin(), part.points.end(), q), part.points.end())
            << side << " part of a separator lacks (" << q.x() << ", " << q.y() << ")";
      }
    }
  }
  EXPECT_EQ(separators, neighbour_pairs(partition).size());

  const std::vector<Polygon2> parts = read_geojson(polygons.dump(), "parts.geojson");
  ASSERT_EQ(parts.size(), partition.parts.size());
  double total = 0;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    EXPECT_EQ(parts[p].coordinates, partition.parts[p].coordinates);
    EXPECT_EQ(parts[p].ring_offsets, partition.parts[p].ring_offsets);
    ASSERT_EQ(parts[p].points.size(), partition.parts[p].points.size());
    for (std::size_t i = 0; i < parts[p].points.size(); ++i)
      EXPECT_EQ(parts[p].points[i], partition.parts[p].points[i]);
    EXPECT_TRUE(check_region({parts[p]}).valid) << "part " << p;
    total += area(parts[p]);
  }
  EXPECT_NEAR(total, input_area, 1e-9 * input_area);
}

TEST(PartitionOutput, GeoJsonReadsBackAsTheParts) {
  expect_geojson_round_trip(quadrants(), 1.0);
  expect_geojson_round_trip(square_with_hole(), 24.0);
  Polygon2 region;
  const Partition scaled = scaled_quadrants(region);
  expect_geojson_round_trip(scaled, area(region));
}

// The fill colour of each part's path, in part order (the first paths of the SVG).
std::vector<std::string> svg_part_fills(const std::string& svg, std::size_t parts, std::size_t* path_count) {
  std::vector<std::string> fills;
  *path_count = 0;
  for (std::size_t at = svg.find("<path"); at != std::string::npos; at = svg.find("<path", at + 1)) {
    ++*path_count;
    const std::size_t fill = svg.find("fill=\"", at);
    if (fills.size() < parts) fills.push_back(svg.substr(fill + 6, 7));
  }
  return fills;
}

TEST(PartitionOutput, SvgHasOnePathPerPartAndNeighboursDiffer) {
  const Partition partition = quadrants();
  const std::string svg = partition_svg(partition, 400);
  std::size_t paths = 0;
  const auto fills = svg_part_fills(svg, 4, &paths);
  EXPECT_EQ(paths, 4u + 2u);  // the parts, then all separators and the region boundary
  for (const auto& [a, b] : neighbour_pairs(partition)) EXPECT_NE(fills[a], fills[b]);
  EXPECT_NE(svg.find("width=\"400\""), std::string::npos);

  // 1024 parts, one per cell of a 32x32 grid: every neighbour pair differs.
  const Polygon2 region = testing::make_region({{{0, 0}, {32, 0}, {32, 32}, {0, 32}}});
  std::vector<std::int32_t> labels(1024);
  for (std::int32_t f = 0; f < 1024; ++f) labels[f] = f;
  const Partition many = build(make_tessellation(grid_faces(32, 32, {0, 0}, 1), region), labels, 1024, region);
  const auto many_fills = svg_part_fills(partition_svg(many), 1024, &paths);
  EXPECT_EQ(paths, 1024u + 2u);
  const auto pairs = neighbour_pairs(many);
  EXPECT_EQ(pairs.size(), 2u * 32u * 31u);
  for (const auto& [a, b] : pairs) EXPECT_NE(many_fills[a], many_fills[b]) << a << " " << b;
  EXPECT_LE(std::set<std::string>(many_fills.begin(), many_fills.end()).size(), 12u);
}

struct Decoded {
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  std::array<std::uint8_t, 3> at(std::uint32_t x, std::uint32_t y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

Decoded decode_png(const std::string& png) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  EXPECT_TRUE(png_image_begin_read_from_memory(&image, png.data(), png.size()));
  image.format = PNG_FORMAT_RGB;
  Decoded decoded{image.width, image.height, std::vector<std::uint8_t>(PNG_IMAGE_SIZE(image))};
  EXPECT_TRUE(png_image_finish_read(&image, nullptr, decoded.rgb.data(), 0, nullptr));
  return decoded;
}

TEST(PartitionOutput, PngHasTheRightSizeAndColours) {
  const Partition partition = quadrants();
  const std::string png = partition_png(partition, 300);
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  const auto be32 = [&](std::size_t at) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(png[at])) << 24 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(png[at + 1])) << 16 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(png[at + 2])) << 8 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(png[at + 3]));
  };
  EXPECT_EQ(be32(16), 300u);  // width
  EXPECT_EQ(be32(20), 300u);  // a square region: as high as wide

  // Quadrant centres (10 px margin, 280 px for the unit square): neighbours differ,
  // nothing is left white.
  const Decoded image = decode_png(png);
  ASSERT_EQ(image.width, 300u);
  ASSERT_EQ(image.height, 300u);
  const auto centre = [&](double x, double y) {
    return image.at(static_cast<std::uint32_t>(10 + 280 * x), static_cast<std::uint32_t>(290 - 280 * y));
  };
  const std::array<std::array<std::uint8_t, 3>, 4> colour{centre(0.25, 0.25), centre(0.75, 0.25), centre(0.25, 0.75),
                                                          centre(0.75, 0.75)};
  const std::array<std::uint8_t, 3> white{255, 255, 255};
  for (const auto& c : colour) EXPECT_NE(c, white);
  for (const auto& [a, b] : neighbour_pairs(partition)) EXPECT_NE(colour[a], colour[b]);

  // Square with hole [2,3]^2 in [0,5]^2: the hole is white, the parts are not.
  const Decoded holed = decode_png(partition_png(square_with_hole(), 520));
  ASSERT_EQ(holed.width, 520u);
  const auto point = [&](double x, double y) {
    return holed.at(static_cast<std::uint32_t>(10 + 100 * x), static_cast<std::uint32_t>(holed.height - 10 - 100 * y));
  };
  EXPECT_EQ(point(2.5, 2.5), white);
  EXPECT_NE(point(0.5, 0.5), white);
  EXPECT_NE(point(1.5, 2.5), white);
  EXPECT_NE(point(0.5, 0.5), point(1.5, 2.5));
}

TEST(PartitionOutput, MethodNamesRoundTrip) {
  for (const auto method : {PartitionMethod::CvtGp, PartitionMethod::Cvt, PartitionMethod::Metis, PartitionMethod::Madd,
                            PartitionMethod::Exact})
    EXPECT_EQ(parse_method(method_name(method)), method);
  EXPECT_STREQ(method_name(PartitionMethod::CvtGp), "cvtgp");
  EXPECT_STREQ(method_name(PartitionMethod::Exact), "exact");
}

TEST(PartitionOutput, ParseMethodListsTheValidNames) {
  try {
    parse_method("kway");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("kway"), std::string::npos) << message;
    EXPECT_NE(message.find("cvtgp, cvt, metis, madd, exact"), std::string::npos) << message;
  }
  EXPECT_THROW(parse_method("CVTGP"), InputError);
  EXPECT_THROW(parse_method(""), InputError);
}

}  // namespace
}  // namespace structmesh::partition2d
