// Quad mesh pictures: colours at known places, view cropping, sub-pixel quads,
// no gaps between bands, the same bytes for any thread count, a valid PNG, and
// the --view parser's errors.
#include "structmesh/error.hpp"
#include "structmesh/render.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

namespace structmesh {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

// An nx x ny grid of counter-clockwise quads over [0, width] x [0, height], row by row.
QuadMesh grid(int nx, int ny, double width, double height) {
  QuadMesh mesh;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) mesh.points.emplace_back(width * i / nx, height * j / ny, 0);
  const auto id = [&](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) mesh.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return mesh;
}

Rgb pixel_at(const Image& image, const Vec2& world) {
  const Vec2 p = image.to_pixel(world);
  const std::size_t i = (static_cast<std::size_t>(p.y()) * image.width + static_cast<std::size_t>(p.x())) * 3;
  return {image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]};
}

std::size_t count_color(const Image& image, const Rgb& color) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < image.rgb.size(); i += 3)
    n += image.rgb[i] == color[0] && image.rgb[i + 1] == color[1] && image.rgb[i + 2] == color[2];
  return n;
}

void expect_color_near(const Rgb& actual, const Rgb& expected) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(actual[k], expected[k], 1) << "channel " << k;
}

TEST(QuadPng, GridQuadCentresTakeTheirValuesColours) {
  const QuadMesh mesh = grid(2, 2, 2, 2);
  // Quads 0..3: (0,0), (1,0), (0,1), (1,1). Viridis at 0, 0.2, 0.5 and 1; -0.5 is inverted.
  const std::vector<double> values{0.0, 0.2, 0.5, 1.0};
  QuadPictureOptions options;
  options.width_px = 220;  // 100 px per unit
  options.mark_inverted = false;
  const Image image = quad_mesh_image(mesh, values, options);
  EXPECT_EQ(image.width, 220);
  expect_color_near(pixel_at(image, {0.5, 0.5}), {68, 1, 84});
  expect_color_near(pixel_at(image, {1.5, 0.5}), {65, 68, 135});
  expect_color_near(pixel_at(image, {0.5, 1.5}), {33, 145, 140});
  expect_color_near(pixel_at(image, {1.5, 1.5}), {253, 231, 37});
  // The margin stays white.
  EXPECT_EQ(pixel_at(image, {-0.05, 1.0}), (Rgb{255, 255, 255}));

  const std::vector<double> marked{-0.5, 0.0, std::nan(""), 1.0};
  options.mark_inverted = true;
  const Image flagged = quad_mesh_image(mesh, marked, options);
  EXPECT_EQ(pixel_at(flagged, {0.5, 0.5}), pixel_at(flagged, {1.5, 0.5}));  // <= 0: both inverted
  EXPECT_NE(pixel_at(flagged, {0.5, 0.5}), pixel_at(image, {0.5, 0.5}));    // ... not the map's low end
  EXPECT_EQ(pixel_at(flagged, {0.5, 1.5}), (Rgb{190, 190, 190}));           // NaN: grey
}

TEST(QuadPng, EdgesAreDrawnOnlyForLargeQuads) {
  const QuadMesh mesh = grid(2, 2, 2, 2);
  const std::vector<double> values(4, 1.0);
  QuadPictureOptions options;
  options.width_px = 220;
  options.legend = false;
  const Image large = quad_mesh_image(mesh, values, options);
  EXPECT_NE(pixel_at(large, {1.0, 0.5}), (Rgb{253, 231, 37}));  // the middle edge
  EXPECT_EQ(pixel_at(large, {0.5, 0.5}), (Rgb{253, 231, 37}));
  // 200 x 200 quads in 200 px: no edges, every map pixel takes the fill colour.
  const QuadMesh fine = grid(200, 200, 2, 2);
  const std::vector<double> fine_values(fine.quads.size(), 1.0);
  const Image small = quad_mesh_image(fine, fine_values, options);
  EXPECT_EQ(count_color(small, {253, 231, 37}), 200u * 200u);
}

TEST(QuadPng, ViewWindowCrops) {
  const QuadMesh mesh = grid(2, 2, 2, 2);
  const std::vector<double> values{0.0, 0.2, 0.5, 1.0};
  QuadPictureOptions options;
  options.width_px = 220;
  options.mark_inverted = false;
  options.legend = false;
  options.edges = false;
  options.view = parse_view("0,0,1,1");  // quad 0 only, 200 px per unit
  const Image image = quad_mesh_image(mesh, values, options);
  EXPECT_EQ(count_color(image, {68, 1, 84}), 200u * 200u);
  expect_color_near(pixel_at(image, {0.5, 0.5}), {68, 1, 84});
  EXPECT_EQ(count_color(image, {65, 68, 135}), 0u);   // quad 1: outside (shares an edge)
  EXPECT_EQ(count_color(image, {33, 145, 140}), 0u);  // quad 2
  EXPECT_EQ(count_color(image, {253, 231, 37}), 0u);  // quad 3: shares only a corner
  // Zooming into the middle of a quad: the whole window takes its colour.
  options.view = parse_view("1.2,1.2,1.4,1.3");
  const Image zoomed = quad_mesh_image(mesh, values, options);
  EXPECT_EQ(count_color(zoomed, {253, 231, 37}), static_cast<std::size_t>(200 * 100));
}

TEST(QuadPng, EmptyViewShowsTheWholeMesh) {
  QuadMesh mesh = grid(3, 2, 3, 2);
  for (Vec3& p : mesh.points) p += Vec3(10, -5, 0);
  const std::vector<double> values{0.1, 0.3, 0.5, 0.7, 0.9, 1.0};
  QuadPictureOptions options;
  options.width_px = 300;
  const Image whole = quad_mesh_image(mesh, values, options);
  options.view.extend({10, -5});
  options.view.extend({13, -3});
  const Image windowed = quad_mesh_image(mesh, values, options);
  EXPECT_EQ(whole.width, windowed.width);
  EXPECT_EQ(whole.height, windowed.height);
  EXPECT_EQ(whole.rgb, windowed.rgb);
}

TEST(QuadPng, SubPixelQuadPaintsThePixelUnderItsCentre) {
  QuadMesh mesh = grid(1, 1, 0.001, 0.001);
  for (Vec3& p : mesh.points) p += Vec3(3.3, 4.4, 0);
  mesh.points.emplace_back(0, 0, 0);  // unused points widen the picture to [0, 10]^2
  mesh.points.emplace_back(10, 10, 0);
  QuadPictureOptions options;
  options.width_px = 120;  // 10 px per unit: the quad is 0.01 px wide
  options.legend = false;
  const std::vector<double> values{1.0};
  const Image image = quad_mesh_image(mesh, values, options);
  EXPECT_EQ(count_color(image, {253, 231, 37}), 1u);
  EXPECT_EQ(pixel_at(image, {3.3005, 4.4005}), (Rgb{253, 231, 37}));
}

TEST(QuadPng, ConcaveQuadLeavesItsNotchEmpty) {
  // An arrow-head (dart): the reflex corner at (2, 1) leaves the notch around (2, 0.5) empty.
  QuadMesh mesh;
  mesh.points = {{0, 0, 0}, {2, 1, 0}, {4, 0, 0}, {2, 4, 0}};
  mesh.quads = {{0, 1, 2, 3}};
  const std::vector<double> values{1.0};
  QuadPictureOptions options;
  options.width_px = 420;
  options.legend = false;
  options.edges = false;
  const Image image = quad_mesh_image(mesh, values, options);
  EXPECT_EQ(pixel_at(image, {2, 0.5}), (Rgb{255, 255, 255}));
  EXPECT_EQ(pixel_at(image, {2, 2}), (Rgb{253, 231, 37}));
  const double area_px = 6.0 * 100 * 100;  // shoelace area 6, 100 px per unit
  EXPECT_NEAR(static_cast<double>(count_color(image, {253, 231, 37})), area_px, 0.01 * area_px);
}

TEST(QuadPng, SameBytesForAnyThreadCount) {
  // Sheared, sub-pixel and large quads across many bands, with edges and a zoom.
  QuadMesh mesh = grid(700, 500, 7, 5);
  for (Vec3& p : mesh.points) p.x() += 0.3 * std::sin(2 * p.y()) + 0.02 * std::cos(37 * p.x() * p.y());
  std::vector<double> values(mesh.quads.size());
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = std::fmod(i * 0.618034, 1.2) - 0.1;
  for (const std::string& view : {std::string(), std::string("2,1,2.6,1.3")}) {
    QuadPictureOptions options;
    options.width_px = 640;
    options.title = "Scaled Jacobian: sheared grid (350k quads)";
    if (!view.empty()) options.view = parse_view(view);
    std::string one, two;
    {
      tbb::global_control control(tbb::global_control::max_allowed_parallelism, 1);
      one = quad_mesh_png(mesh, values, options);
    }
    {
      tbb::global_control control(tbb::global_control::max_allowed_parallelism, 2);
      two = quad_mesh_png(mesh, values, options);
    }
    EXPECT_EQ(one, two) << "view " << view;
  }
}

TEST(QuadPng, EncodesAPngWithTheSignature) {
  const QuadMesh mesh = grid(4, 3, 4, 3);
  const std::vector<double> values(mesh.quads.size(), 0.75);
  QuadPictureOptions options;
  options.title = "Key, h = 0.02";
  const std::string png = quad_mesh_png(mesh, values, options);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

TEST(QuadPng, RejectsBadInput) {
  const QuadMesh mesh = grid(2, 2, 2, 2);
  const std::vector<double> three(3, 1.0), four(4, 1.0);
  EXPECT_THROW(quad_mesh_image(mesh, three), InputError);
  QuadPictureOptions options;
  options.value_min = 1;
  options.value_max = 1;
  EXPECT_THROW(quad_mesh_image(mesh, four, options), InputError);
  options = {};
  options.width_px = 4;
  EXPECT_THROW(quad_mesh_image(mesh, four, options), InputError);
}

TEST(ParseView, ReadsFourNumbers) {
  const BoundingBox2 box = parse_view(" 0, -1.5 ,2e1,+3");
  EXPECT_EQ(box.min, Vec2(0, -1.5));
  EXPECT_EQ(box.max, Vec2(20, 3));
}

TEST(ParseView, RejectsMalformedText) {
  for (const char* text : {"", "1,2,3", "0,0,1,1,2", "a,b,c,d", "0,0,1,1x", "0,,1,1", "nan,0,1,1", "0,0,inf,1",
                           "1,0,0,1", "0,1,1,1", "0;0;1;1"})
    EXPECT_THROW(parse_view(text), InputError) << text;
}

}  // namespace
}  // namespace structmesh
