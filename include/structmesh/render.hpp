// Pictures of regions and meshes for people to look at.
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <cstdint>
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

}  // namespace structmesh
