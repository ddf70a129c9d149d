// Pictures of regions and meshes for people to look at.
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace structmesh {

struct SvgOptions {
  double width_px = 1200;          // picture width; height follows the aspect ratio
  std::string fill = "#9ecae1";    // region fill
  std::string stroke = "#08306b";  // boundary stroke
  std::string title;               // optional caption
};

/// An SVG of planar regions: each polygon filled (holes cut out with the even-odd
/// rule), rings outlined. Suitable for 10^5+ vertices (one path per polygon).
std::string region_svg(const std::vector<Polygon2>& polygons, const SvgOptions& options = {});

}  // namespace structmesh

namespace structmesh {

/// An 8-bit RGB raster with a world-to-pixel mapping (north up). Our own
/// rasterizer: pictures of millions of elements must render in seconds, and a
/// scanline fill over flat arrays does that without a graphics stack.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // row-major, 3 bytes per pixel
  // world -> pixel: px = (x - origin.x) * scale, py = height - (y - origin.y) * scale
  Vec2 origin{0, 0};
  double scale = 1;

  /// A white image that fits `box` into width_px, with a margin of `margin_px`.
  static Image fit(const BoundingBox2& box, int width_px, int margin_px = 10);
  Vec2 to_pixel(const Vec2& p) const { return {(p.x() - origin.x()) * scale, height - (p.y() - origin.y()) * scale}; }
  void set(int x, int y, const std::array<std::uint8_t, 3>& color);
};

/// Fills the rings with the even-odd rule (holes stay unfilled).
void fill_rings(Image& image, const Polygon2& polygon, const std::array<std::uint8_t, 3>& color);
/// Draws a 1-pixel line between two world points.
void draw_line(Image& image, const Vec2& a, const Vec2& b, const std::array<std::uint8_t, 3>& color);
/// Draws every ring's outline.
void draw_rings(Image& image, const Polygon2& polygon, const std::array<std::uint8_t, 3>& color);
/// Encodes the image as PNG (libpng).
std::string encode_png(const Image& image);

/// A PNG picture of regions: filled, outlined, holes visible.
std::string region_png(const std::vector<Polygon2>& polygons, int width_px = 1200);

struct QuadPictureOptions {
  int width_px = 1600;  // picture width; height follows the view's aspect ratio (at most 4x the width)
  BoundingBox2 view;    // empty = the whole mesh; else only this window (zoom)
  /// Colour map range: viridis from value_min (dark violet) to value_max (yellow),
  /// values outside are clamped. value_min < value_max.
  double value_min = 0, value_max = 1;
  /// Values <= 0 in a distinct red ("inverted": a scaled Jacobian <= 0); turn off for
  /// values where <= 0 means nothing special. NaN values are drawn light grey.
  bool mark_inverted = true;
  bool edges = true;   // draw the edges of quads at least ~5 px wide (sqrt of pixel area >= 5)
  bool legend = true;  // a colour bar with ticks and labels below the picture
  std::string title;   // optional caption above the picture (ASCII; lower case drawn as upper case)
};

/// A picture of a planar quad mesh (x, y of its points) with quad i filled in the
/// colour of cell_values[i]. Every pixel whose centre lies in a quad takes its
/// colour (later quads win on shared pixels); a quad that covers no pixel centre
/// paints the pixel under its centre, so sub-pixel quads stay visible. Only quads
/// in the view are drawn. The bytes do not depend on the thread count.
/// InputError unless cell_values has one value per quad, value_min < value_max and
/// 16 <= width_px <= 65536.
Image quad_mesh_image(const QuadMesh& mesh, std::span<const double> cell_values,
                      const QuadPictureOptions& options = {});
/// quad_mesh_image encoded as PNG.
std::string quad_mesh_png(const QuadMesh& mesh, std::span<const double> cell_values,
                          const QuadPictureOptions& options = {});
/// Parses "--view x0,y0,x1,y1" (the window's lower-left and upper-right corners)
/// into a box; InputError on malformed text, non-finite numbers or x0 >= x1, y0 >= y1.
BoundingBox2 parse_view(const std::string& text);

/// A picture of a labelled triangle surface: orthographic view from `azimuth_deg`
/// (around +z, from +x) and `elevation_deg` (above the xy plane), flat shading, a
/// z-buffer, faces coloured by label (label_color(); negative labels grey), and
/// `markers` (e.g. guards, which lie inside the solid) drawn on top as dots.
struct SurfacePictureOptions {
  int width_px = 1200;
  double azimuth_deg = 35, elevation_deg = 25;
  /// When not empty: one colour per face, used instead of the labels' colours.
  std::vector<std::array<std::uint8_t, 3>> face_colors;
};
/// The viridis colour map at t in [0, 1] (clamped), as quad_mesh_image() uses it.
std::array<std::uint8_t, 3> viridis_color(double t);
/// A colour per non-negative label, neighbouring labels clearly different; grey for < 0.
std::array<std::uint8_t, 3> label_color(std::int32_t label);
Image surface_image(const TriMesh& surface, std::span<const std::int32_t> face_labels, std::span<const Vec3> markers,
                    const SurfacePictureOptions& options = {});
std::string surface_png(const TriMesh& surface, std::span<const std::int32_t> face_labels,
                        std::span<const Vec3> markers, const SurfacePictureOptions& options = {});

}  // namespace structmesh
