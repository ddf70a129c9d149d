// Files of a partition (design/partition2d.md §3.4): GeoJSON with part and
// separator features, and SVG/PNG pictures with the parts coloured so that
// neighbours differ; plus the method names of the CLI.
#include "structmesh/error.hpp"
#include "structmesh/partition2d.hpp"
#include "structmesh/render.hpp"

#include "render/svg_number.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <set>
#include <utility>

namespace structmesh {

namespace {

using detail::append_hundredths;
using detail::pixels;

constexpr std::array<const char*, 5> kMethodNames{"cvtgp", "cvt", "metis", "madd", "exact"};

// ---------------------------------------------------------------------------------
// GeoJSON
// ---------------------------------------------------------------------------------

// Shortest representation that reads back to the same double (as write_geojson), so
// a vertex shared by two parts is written as the same characters in both.
void append_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void append_position(std::string& out, const Vec2& p) {
  out += '[';
  append_number(out, p.x());
  out += ',';
  append_number(out, p.y());
  out += ']';
}

// ---------------------------------------------------------------------------------
// Pictures
// ---------------------------------------------------------------------------------

// Light fills (ColorBrewer Set3) under dark separators.
constexpr std::array<std::array<std::uint8_t, 3>, 12> kPalette{{{141, 211, 199},
                                                                {255, 255, 179},
                                                                {190, 186, 218},
                                                                {251, 128, 114},
                                                                {128, 177, 211},
                                                                {253, 180, 98},
                                                                {179, 222, 105},
                                                                {252, 205, 229},
                                                                {217, 217, 217},
                                                                {188, 128, 189},
                                                                {204, 235, 197},
                                                                {255, 237, 111}}};
constexpr std::array<std::uint8_t, 3> kSeparatorColor{40, 40, 40};
constexpr std::array<std::uint8_t, 3> kBoundaryColor{8, 48, 107};

// Parts sharing a separator curve, as sorted, deduplicated neighbour lists.
std::vector<std::vector<Index>> part_adjacency(const Partition& partition) {
  std::vector<std::vector<Index>> neighbours(partition.parts.size());
  for (const PartitionCurve& curve : partition.curves) {
    if (curve.kind != PartitionCurve::Kind::Separator || curve.left_part == curve.right_part) continue;
    neighbours[curve.left_part].push_back(static_cast<Index>(curve.right_part));
    neighbours[curve.right_part].push_back(static_cast<Index>(curve.left_part));
  }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return neighbours;
}

// Greedy colouring in smallest-last order: each part has at most 5 neighbours
// coloured before it in a planar adjacency graph, so 6 colours always suffice and
// the 12-colour palette never runs out. Among the free colours the least used is
// taken, which spreads the palette evenly.
std::vector<int> part_colors(const Partition& partition) {
  const auto neighbours = part_adjacency(partition);
  const std::size_t k = neighbours.size();
  std::vector<std::size_t> remaining_degree(k);
  std::set<std::pair<std::size_t, Index>> queue;
  for (Index p = 0; p < k; ++p) {
    remaining_degree[p] = neighbours[p].size();
    queue.insert({remaining_degree[p], p});
  }
  std::vector<Index> order;
  std::vector<std::uint8_t> removed(k, 0);
  while (!queue.empty()) {
    const Index p = queue.begin()->second;
    queue.erase(queue.begin());
    removed[p] = 1;
    order.push_back(p);
    for (const Index q : neighbours[p]) {
      if (removed[q]) continue;
      queue.erase({remaining_degree[q], q});
      queue.insert({--remaining_degree[q], q});
    }
  }
  std::vector<int> color(k, -1);
  std::array<std::size_t, kPalette.size()> used{};
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    std::array<bool, kPalette.size()> taken{};
    for (const Index q : neighbours[*it])
      if (color[q] >= 0) taken[color[q]] = true;
    int best = -1;
    for (int c = 0; c < static_cast<int>(kPalette.size()); ++c)
      if (!taken[c] && (best < 0 || used[c] < used[best])) best = c;
    color[*it] = best;
    ++used[best];
  }
  return color;
}

// Lon/lat partitions are drawn with longitude scaled by cos(middle latitude), as
// region_svg and region_png do, so shapes look as they do on a map.
struct View {
  BoundingBox2 box;
  double x_stretch = 1;
  Vec2 operator()(const Vec2& p) const { return {p.x() * x_stretch, p.y()}; }
};

View make_view(const Partition& partition) {
  View view;
  const bool lon_lat = !partition.parts.empty() && partition.parts.front().coordinates == Polygon2::Coordinates::LonLat;
  BoundingBox2 input_box;
  for (const Vec2& p : partition.vertices) input_box.extend(p);
  if (input_box.empty()) input_box.extend(Vec2::Zero());
  if (lon_lat)
    view.x_stretch = std::max(0.01, std::cos(0.5 * (input_box.min.y() + input_box.max.y()) * std::numbers::pi / 180));
  for (const Vec2& p : partition.vertices) view.box.extend(view(p));
  if (view.box.empty()) view.box.extend(Vec2::Zero());
  return view;
}

std::string hex_color(const std::array<std::uint8_t, 3>& rgb) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out = "#";
  for (const std::uint8_t channel : rgb) {
    out += kDigits[channel >> 4];
    out += kDigits[channel & 15];
  }
  return out;
}

// SVG path data of one polyline in pixel hundredths; points that round onto the
// previous one are dropped, so 10^6 vertices at picture scale stay a small file.
class PathWriter {
 public:
  PathWriter(const View& view, double margin, double scale) : view_(view), margin_(margin), scale_(scale) {}

  void polyline(std::string& out, const std::vector<Vec2>& points, bool closed) {
    px_.clear();
    for (const Vec2& point : points) {
      const Vec2 p = view_(point);
      const double x = margin_ + (p.x() - view_.box.min.x()) * scale_;
      const double y = margin_ + (view_.box.max.y() - p.y()) * scale_;  // y down in SVG: north up
      const std::array<std::int64_t, 2> q{std::llround(x * 100), std::llround(y * 100)};
      if (px_.empty() || q != px_.back()) px_.push_back(q);
    }
    if (closed)
      while (px_.size() > 1 && px_.back() == px_.front()) px_.pop_back();
    if (px_.size() < 2) return;  // nothing to see at this scale
    for (std::size_t i = 0; i < px_.size(); ++i) {
      out += i == 0 ? "M" : (i == 1 ? "L" : " ");
      append_hundredths(out, px_[i][0]);
      out += ' ';
      append_hundredths(out, px_[i][1]);
    }
    if (closed) out += 'Z';
  }

 private:
  const View& view_;
  double margin_, scale_;
  std::vector<std::array<std::int64_t, 2>> px_;
};

std::vector<Vec2> curve_points(const Partition& partition, const PartitionCurve& curve) {
  std::vector<Vec2> points;
  points.reserve(curve.vertices.size());
  for (const Index v : curve.vertices) points.push_back(partition.vertices[v]);
  return points;
}

}  // namespace

const char* method_name(PartitionMethod method) { return kMethodNames[static_cast<std::size_t>(method)]; }

PartitionMethod parse_method(const std::string& name) {
  for (std::size_t m = 0; m < kMethodNames.size(); ++m)
    if (name == kMethodNames[m]) return static_cast<PartitionMethod>(m);
  std::string valid;
  for (const char* known : kMethodNames) valid += (valid.empty() ? "" : ", ") + std::string(known);
  throw InputError("unknown partition method '" + name + "' (valid: " + valid + ")");
}

std::string write_partition_geojson(const Partition& partition) {
  for (std::size_t v = 0; v < partition.vertices.size(); ++v)
    if (!partition.vertices[v].allFinite())
      throw Error("cannot write GeoJSON: partition vertex " + std::to_string(v) + " is not finite");
  // The marker the region reader understands (io.hpp): planar coordinates within
  // [-180,180]x[-90,90] would otherwise be read as lon/lat.
  const bool planar = partition.parts.empty() || partition.parts.front().coordinates == Polygon2::Coordinates::Planar;
  std::size_t positions = 0;
  for (const Polygon2& polygon : partition.parts) positions += polygon.points.size() + polygon.ring_count();
  for (const PartitionCurve& curve : partition.curves) positions += curve.vertices.size();
  std::string out;
  out.reserve(64 + 48 * positions + 128 * (partition.parts.size() + partition.curves.size()));
  out += "{\"type\":\"FeatureCollection\",\"structmesh:coordinates\":";
  out += planar ? "\"planar\"" : "\"lonlat\"";
  out += ",\"features\":[";
  bool first = true;
  const auto begin_feature = [&]() {
    out += first ? "\n" : ",\n";
    first = false;
  };
  for (std::size_t p = 0; p < partition.parts.size(); ++p) {
    const Polygon2& polygon = partition.parts[p];
    begin_feature();
    out += "{\"type\":\"Feature\",\"properties\":{\"part\":" + std::to_string(p) + ",\"area\":";
    append_number(out, partition.part_areas[p]);
    out += ",\"kind\":\"part\"},\"geometry\":{\"type\":\"Polygon\",\"coordinates\":[";
    // Rings are already outer counter-clockwise, holes clockwise (RFC 7946); the
    // first position is repeated last.
    for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
      if (r > 0) out += ",\n";
      const auto ring = polygon.ring(r);
      out += '[';
      for (std::size_t i = 0; i <= ring.size(); ++i) {
        if (i > 0) out += ',';
        append_position(out, ring[i % ring.size()]);
      }
      out += ']';
    }
    out += "]}}";
  }
  for (const PartitionCurve& curve : partition.curves) {
    if (curve.kind != PartitionCurve::Kind::Separator) continue;
    begin_feature();
    out += "{\"type\":\"Feature\",\"properties\":{\"kind\":\"separator\",\"left\":" + std::to_string(curve.left_part) +
           ",\"right\":" + std::to_string(curve.right_part) +
           "},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[";
    for (std::size_t i = 0; i < curve.vertices.size(); ++i) {
      if (i > 0) out += ',';
      append_position(out, partition.vertices[curve.vertices[i]]);
    }
    out += "]}}";
  }
  out += "\n]}\n";
  return out;
}

std::string partition_svg(const Partition& partition, double width_px) {
  if (!(width_px > 0 && width_px <= 1e6)) width_px = 1200;
  const View view = make_view(partition);
  const double world_width = view.box.max.x() - view.box.min.x();
  const double world_height = view.box.max.y() - view.box.min.y();
  const double margin = std::max(4.0, 0.02 * width_px);
  const double extent = world_width > 0 ? world_width : (world_height > 0 ? world_height : 1.0);
  const double scale = (width_px - 2 * margin) / extent;
  const double height_px = std::ceil(world_height * scale + 2 * margin);
  PathWriter writer(view, margin, scale);

  std::string out;
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + pixels(width_px) + "\" height=\"" + pixels(height_px) +
         "\" viewBox=\"0 0 " + pixels(width_px) + " " + pixels(height_px) + "\">\n";
  out += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  // One filled path per part; holes stay white by the even-odd rule, and a part
  // enclosed by another is drawn over it.
  const std::vector<int> color = part_colors(partition);
  std::vector<Vec2> ring;
  for (std::size_t p = 0; p < partition.parts.size(); ++p) {
    const Polygon2& polygon = partition.parts[p];
    out += "<path fill-rule=\"evenodd\" stroke=\"none\" fill=\"" + hex_color(kPalette[color[p]]) + "\" d=\"";
    for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
      ring.assign(polygon.ring(r).begin(), polygon.ring(r).end());
      writer.polyline(out, ring, true);
    }
    out += "\"/>\n";
  }
  // Separators, then the region boundary, each one path of open polylines.
  for (const auto kind : {PartitionCurve::Kind::Separator, PartitionCurve::Kind::Boundary}) {
    const bool separators = kind == PartitionCurve::Kind::Separator;
    out += "<path fill=\"none\" stroke=\"" + hex_color(separators ? kSeparatorColor : kBoundaryColor) +
           "\" stroke-width=\"" + (separators ? std::string("1") : pixels(std::max(1.0, width_px / 800))) +
           "\" stroke-linejoin=\"round\" d=\"";
    for (const PartitionCurve& curve : partition.curves)
      if (curve.kind == kind) writer.polyline(out, curve_points(partition, curve), false);
    out += "\"/>\n";
  }
  out += "</svg>\n";
  return out;
}

std::string partition_png(const Partition& partition, int width_px) {
  if (width_px <= 0 || width_px > 100000) width_px = 1200;
  const View view = make_view(partition);
  Image image = Image::fit(view.box, width_px);
  const std::vector<int> color = part_colors(partition);
  Polygon2 stretched;
  for (std::size_t p = 0; p < partition.parts.size(); ++p) {
    stretched = partition.parts[p];
    for (Vec2& q : stretched.points) q = view(q);
    fill_rings(image, stretched, kPalette[color[p]]);
  }
  for (const auto kind : {PartitionCurve::Kind::Separator, PartitionCurve::Kind::Boundary})
    for (const PartitionCurve& curve : partition.curves) {
      if (curve.kind != kind) continue;
      const auto& line_color = kind == PartitionCurve::Kind::Separator ? kSeparatorColor : kBoundaryColor;
      for (std::size_t i = 0; i + 1 < curve.vertices.size(); ++i)
        draw_line(image, view(partition.vertices[curve.vertices[i]]), view(partition.vertices[curve.vertices[i + 1]]),
                  line_color);
    }
  return encode_png(image);
}

}  // namespace structmesh
