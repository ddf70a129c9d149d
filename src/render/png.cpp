// A small raster back end: even-odd scanline polygon fill, Bresenham lines, and
// PNG encoding with libpng. Written by hand because no Debian library rasterizes
// flat polygon arrays headlessly without a display or a large graphics stack.
#include "structmesh/error.hpp"
#include "structmesh/render.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>

namespace structmesh {

Image Image::fit(const BoundingBox2& box, int width_px, int margin_px) {
  Image image;
  const Vec2 size = box.empty() ? Vec2(1, 1) : Vec2((box.max - box.min).cwiseMax(Vec2(1e-300, 1e-300)));
  const int inner_width = std::max(1, width_px - 2 * margin_px);
  image.scale = inner_width / size.x();
  // Very tall regions: cap the height at 4x the width and shrink the scale instead.
  const double inner_height = std::min(size.y() * image.scale, 4.0 * inner_width);
  image.scale = std::min(image.scale, inner_height / size.y());
  image.width = width_px;
  image.height = static_cast<int>(std::ceil(inner_height)) + 2 * margin_px;
  image.origin = (box.empty() ? Vec2(0, 0) : box.min) - Vec2(margin_px, margin_px) / image.scale;
  image.rgb.assign(static_cast<std::size_t>(image.width) * image.height * 3, 255);
  return image;
}

void Image::set(int x, int y, const std::array<std::uint8_t, 3>& color) {
  if (x < 0 || y < 0 || x >= width || y >= height) return;
  std::uint8_t* pixel = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
  pixel[0] = color[0];
  pixel[1] = color[1];
  pixel[2] = color[2];
}

void fill_rings(Image& image, const Polygon2& polygon, const std::array<std::uint8_t, 3>& color) {
  // Bucket edges by their first scanline, then sweep rows keeping the active edges:
  // O(edges + pixels) instead of testing every edge on every row.
  struct Edge {
    double x_at_top, slope;  // x at the first sampled row, dx per row
    int first_row, last_row;
  };
  std::vector<std::vector<Edge>> starting(image.height);
  for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
    const auto ring = polygon.ring(r);
    for (std::size_t i = 0; i < ring.size(); ++i) {
      Vec2 a = image.to_pixel(ring[i]), b = image.to_pixel(ring[(i + 1) % ring.size()]);
      if (a.y() == b.y()) continue;
      if (a.y() > b.y()) std::swap(a, b);
      // Sample at pixel centres y + 0.5 within [a.y, b.y).
      const int first = std::max(0, static_cast<int>(std::ceil(a.y() - 0.5)));
      const int last = std::min(image.height - 1, static_cast<int>(std::ceil(b.y() - 0.5)) - 1);
      if (first > last) continue;
      const double slope = (b.x() - a.x()) / (b.y() - a.y());
      starting[first].push_back({a.x() + (first + 0.5 - a.y()) * slope, slope, first, last});
    }
  }
  std::vector<Edge> active;
  std::vector<double> crossings;
  for (int y = 0; y < image.height; ++y) {
    active.erase(std::remove_if(active.begin(), active.end(), [y](const Edge& e) { return e.last_row < y; }),
                 active.end());
    active.insert(active.end(), starting[y].begin(), starting[y].end());
    crossings.clear();
    for (const Edge& e : active) crossings.push_back(e.x_at_top + (y - e.first_row) * e.slope);
    std::sort(crossings.begin(), crossings.end());
    for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) {
      const int x0 = std::max(0, static_cast<int>(std::ceil(crossings[k] - 0.5)));
      const int x1 = std::min(image.width - 1, static_cast<int>(std::ceil(crossings[k + 1] - 0.5)) - 1);
      for (int x = x0; x <= x1; ++x) image.set(x, y, color);
    }
  }
}

void draw_line(Image& image, const Vec2& a, const Vec2& b, const std::array<std::uint8_t, 3>& color) {
  const Vec2 pa = image.to_pixel(a), pb = image.to_pixel(b);
  // Lines reaching far outside the picture are skipped rather than walked pixel by
  // pixel (and before the conversion to int, which would overflow).
  const double limit = 4.0 * (image.width + image.height);
  if (!(pa.cwiseAbs().maxCoeff() <= limit && pb.cwiseAbs().maxCoeff() <= limit)) return;
  int x0 = static_cast<int>(std::floor(pa.x())), y0 = static_cast<int>(std::floor(pa.y()));
  const int x1 = static_cast<int>(std::floor(pb.x())), y1 = static_cast<int>(std::floor(pb.y()));
  const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
  const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  int error = dx + dy;
  while (true) {
    image.set(x0, y0, color);
    if (x0 == x1 && y0 == y1) break;
    const int e2 = 2 * error;
    if (e2 >= dy) {
      error += dy;
      x0 += sx;
    }
    if (e2 <= dx) {
      error += dx;
      y0 += sy;
    }
  }
}

void draw_rings(Image& image, const Polygon2& polygon, const std::array<std::uint8_t, 3>& color) {
  for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
    const auto ring = polygon.ring(r);
    for (std::size_t i = 0; i < ring.size(); ++i) draw_line(image, ring[i], ring[(i + 1) % ring.size()], color);
  }
}

namespace {

void append_png_data(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  out->append(reinterpret_cast<const char*>(data), length);
}

}  // namespace

std::string encode_png(const Image& image) {
  std::string out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (png == nullptr) throw Error("libpng: cannot create a write struct");
  png_infop info = png_create_info_struct(png);
  if (info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw Error("libpng: encoding failed");
  }
  png_set_write_fn(png, &out, append_png_data, nullptr);
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y)
    png_write_row(png, const_cast<png_bytep>(&image.rgb[static_cast<std::size_t>(y) * image.width * 3]));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

std::string region_png(const std::vector<Polygon2>& input, int width_px) {
  // Lon/lat regions are drawn in an equirectangular view at their mean latitude
  // (x scaled by cos(latitude)), so shapes look as they do on a map.
  std::vector<Polygon2> polygons = input;
  BoundingBox2 box;
  for (const Polygon2& p : polygons)
    for (const Vec2& q : p.points) box.extend(q);
  for (Polygon2& p : polygons) {
    if (p.coordinates != Polygon2::Coordinates::LonLat || box.empty()) continue;
    const double cos_lat = std::cos(0.5 * (box.min.y() + box.max.y()) * M_PI / 180.0);
    for (Vec2& q : p.points) q.x() *= cos_lat;
  }
  box = BoundingBox2{};
  for (const Polygon2& p : polygons)
    for (const Vec2& q : p.points) box.extend(q);
  Image image = Image::fit(box, width_px);
  for (const Polygon2& p : polygons) fill_rings(image, p, {158, 202, 225});
  for (const Polygon2& p : polygons) draw_rings(image, p, {8, 48, 107});
  return encode_png(image);
}

}  // namespace structmesh
