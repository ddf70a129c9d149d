// region_svg(): regions as an SVG picture, north up.
//
// Coordinates are written in pixels rounded to 0.01 px, and vertices that round
// onto the previous one are dropped, so a 10^5-vertex coastline stays a compact
// file that browsers draw quickly. Lon/lat regions are drawn with longitude
// scaled by cos(middle latitude), so shapes look as they do on a map.
#include "structmesh/render.hpp"

#include "render/svg_number.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace structmesh {

namespace {

using detail::append_hundredths;
using detail::pixels;

std::string escape_xml(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const char* entity = c == '&'    ? "&amp;"
                         : c == '<'  ? "&lt;"
                         : c == '>'  ? "&gt;"
                         : c == '"'  ? "&quot;"
                         : c == '\'' ? "&apos;"
                                     : nullptr;
    if (entity != nullptr) {
      out += entity;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

std::string region_svg(const std::vector<Polygon2>& polygons, const SvgOptions& options) {
  const double width_px = options.width_px > 0 && options.width_px <= 1e6 ? options.width_px : 1200;
  BoundingBox2 box;
  bool all_lon_lat = !polygons.empty();
  for (const Polygon2& polygon : polygons) {
    for (const Vec2& p : polygon.points)
      if (p.allFinite()) box.extend(p);
    all_lon_lat = all_lon_lat && polygon.coordinates == Polygon2::Coordinates::LonLat;
  }
  if (box.empty()) box.extend(Vec2::Zero());

  const double x_stretch =
      all_lon_lat ? std::max(0.01, std::cos(0.5 * (box.min.y() + box.max.y()) * std::numbers::pi / 180)) : 1.0;
  const double world_width = (box.max.x() - box.min.x()) * x_stretch;
  const double world_height = box.max.y() - box.min.y();
  const double margin = std::max(4.0, 0.02 * width_px);
  const double extent = world_width > 0 ? world_width : (world_height > 0 ? world_height : 1.0);
  const double scale = (width_px - 2 * margin) / extent;
  const double font_size = std::max(12.0, width_px / 50);
  const double title_height = options.title.empty() ? 0.0 : 1.6 * font_size;
  const double height_px = std::ceil(world_height * scale + 2 * margin + title_height);
  const double stroke_width = std::max(0.5, width_px / 1000);

  std::string out;
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + pixels(width_px) + "\" height=\"" + pixels(height_px) +
         "\" viewBox=\"0 0 " + pixels(width_px) + " " + pixels(height_px) + "\">\n";
  if (!options.title.empty()) out += "<title>" + escape_xml(options.title) + "</title>\n";
  out += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  const std::string style = "fill=\"" + escape_xml(options.fill) + "\" stroke=\"" + escape_xml(options.stroke) +
                            "\" stroke-width=\"" + pixels(stroke_width) + "\" stroke-linejoin=\"round\"";

  std::vector<std::array<std::int64_t, 2>> ring_px;
  for (const Polygon2& polygon : polygons) {
    out += "<path fill-rule=\"evenodd\" " + style + " d=\"";
    for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
      ring_px.clear();
      for (const Vec2& p : polygon.ring(r)) {
        if (!p.allFinite()) continue;
        const double x = margin + (p.x() - box.min.x()) * x_stretch * scale;
        const double y = title_height + margin + (box.max.y() - p.y()) * scale;  // y down in SVG: north up
        const std::array<std::int64_t, 2> q{std::llround(x * 100), std::llround(y * 100)};
        if (ring_px.empty() || q != ring_px.back()) ring_px.push_back(q);
      }
      while (ring_px.size() > 1 && ring_px.back() == ring_px.front()) ring_px.pop_back();
      if (ring_px.size() < 2) continue;  // nothing to see at this scale
      for (std::size_t i = 0; i < ring_px.size(); ++i) {
        out += i == 0 ? "M" : (i == 1 ? "L" : " ");
        append_hundredths(out, ring_px[i][0]);
        out += ' ';
        append_hundredths(out, ring_px[i][1]);
      }
      out += 'Z';
    }
    out += "\"/>\n";
  }
  if (!options.title.empty()) {
    out += "<text x=\"" + pixels(margin) + "\" y=\"" + pixels(1.2 * font_size) +
           "\" font-family=\"sans-serif\" font-size=\"" + pixels(font_size) + "\">" + escape_xml(options.title) +
           "</text>\n";
  }
  out += "</svg>\n";
  return out;
}

}  // namespace structmesh
