// GeoJSON regions (RFC 7946): Polygon, MultiPolygon, Feature, FeatureCollection
// and GeometryCollection of those.
//
// Reading: each ring's repeated closing position is dropped (Polygon2 rings are
// implicitly closed); a ring whose last position differs from its first is an
// InputError naming the feature, polygon and ring.
// Rings are reoriented to the Polygon2 convention (outer CCW, holes CW).
// Coordinates: a "structmesh:coordinates" member ("planar" or "lonlat") on the
// root object or on a Feature decides; otherwise a legacy "crs" member naming
// anything but CRS84/EPSG:4326 means planar; otherwise the data is lon/lat when
// every position lies within [-180,180]x[-90,90].
#include "mesh/planar_geometry.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>

namespace structmesh {

namespace {

using nlohmann::json;

constexpr int kMaxCollectionDepth = 16;  // nested GeometryCollections; bounds recursion on hostile input
constexpr const char* kCoordinatesMember = "structmesh:coordinates";

using Flag = std::optional<Polygon2::Coordinates>;

class GeoJsonReader {
 public:
  explicit GeoJsonReader(const std::string& source) : source_(source) {}

  std::vector<Polygon2> read(const json& root) {
    if (!root.is_object()) fail("", "top level is not a JSON object");
    const Flag root_flag = coordinates_flag(root, "");
    const std::string type = type_of(root, "");
    if (type == "FeatureCollection") {
      const json* features = member(root, "features");
      if (features == nullptr || !features->is_array()) fail("", "FeatureCollection has no \"features\" array");
      for (std::size_t f = 0; f < features->size(); ++f) read_feature((*features)[f], "feature " + std::to_string(f));
    } else if (type == "Feature") {
      read_feature(root, "feature 0");
    } else {
      read_geometry(root, "", 0, std::nullopt);
    }
    if (polygons_.empty()) fail("", "holds no polygons");

    // Without markers: lon/lat when every position is in range and no projected "crs" is named.
    bool looks_lon_lat = !has_planar_crs(root);
    for (std::size_t p = 0; p < polygons_.size() && looks_lon_lat; ++p)
      for (const Vec2& q : polygons_[p].points)
        if (std::abs(q.x()) > 180 || std::abs(q.y()) > 90) looks_lon_lat = false;
    const auto automatic = looks_lon_lat ? Polygon2::Coordinates::LonLat : Polygon2::Coordinates::Planar;
    for (std::size_t p = 0; p < polygons_.size(); ++p) {
      polygons_[p].coordinates = flags_[p].value_or(root_flag.value_or(automatic));
      detail::normalize_orientation(polygons_[p]);
    }
    return std::move(polygons_);
  }

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(located_message(source_, 0, where.empty() ? what : where + ": " + what));
  }

  static std::string join(const std::string& where, const std::string& part) {
    return where.empty() ? part : where + ", " + part;
  }

  static const json* member(const json& object, const char* name) {
    const auto it = object.find(name);
    return it == object.end() ? nullptr : &*it;
  }

  std::string type_of(const json& object, const std::string& where) const {
    const json* type = member(object, "type");
    if (type == nullptr || !type->is_string()) fail(where, "object has no \"type\" string");
    const std::string& name = type->get_ref<const std::string&>();
    return name.size() <= 40 ? name : name.substr(0, 40) + "...";
  }

  Flag coordinates_flag(const json& object, const std::string& where) const {
    const json* value = member(object, kCoordinatesMember);
    if (value == nullptr) return std::nullopt;
    if (value->is_string() && *value == "planar") return Polygon2::Coordinates::Planar;
    if (value->is_string() && *value == "lonlat") return Polygon2::Coordinates::LonLat;
    fail(where, std::string("\"") + kCoordinatesMember + "\" must be \"planar\" or \"lonlat\"");
  }

  // The 2008 GeoJSON "crs" member: anything but plain WGS84 lon/lat means projected data.
  static bool has_planar_crs(const json& root) {
    const json* crs = member(root, "crs");
    if (crs == nullptr || crs->is_null()) return false;
    const std::string text = crs->dump();
    return text.find("CRS84") == std::string::npos && text.find("4326") == std::string::npos;
  }

  void read_feature(const json& feature, const std::string& where) {
    if (!feature.is_object()) fail(where, "is not a JSON object");
    if (type_of(feature, where) != "Feature")
      fail(where, "expected a Feature, found '" + type_of(feature, where) + "'");
    // The separator polylines of a structmesh partition file (write_partition_geojson)
    // describe the parts' shared boundaries; the parts themselves are the region.
    const json* properties = member(feature, "properties");
    if (properties != nullptr && properties->is_object()) {
      const json* kind = member(*properties, "kind");
      if (kind != nullptr && kind->is_string() && *kind == "separator") return;
    }
    const json* geometry = member(feature, "geometry");
    if (geometry == nullptr || geometry->is_null()) fail(where, "has no geometry");
    read_geometry(*geometry, where, 0, coordinates_flag(feature, where));
  }

  void read_geometry(const json& geometry, const std::string& where, int depth, Flag flag) {
    if (!geometry.is_object()) fail(where, "geometry is not a JSON object");
    const std::string type = type_of(geometry, where);
    if (type == "GeometryCollection") {
      if (depth >= kMaxCollectionDepth) fail(where, "GeometryCollections nested too deeply");
      const json* members = member(geometry, "geometries");
      if (members == nullptr || !members->is_array()) fail(where, "GeometryCollection has no \"geometries\" array");
      for (std::size_t g = 0; g < members->size(); ++g)
        read_geometry((*members)[g], join(where, "geometry " + std::to_string(g)), depth + 1, flag);
      return;
    }
    if (type != "Polygon" && type != "MultiPolygon")
      fail(where, "geometry type '" + type + "' is not polygonal (expected Polygon or MultiPolygon)");
    const json* coordinates = member(geometry, "coordinates");
    if (coordinates == nullptr || !coordinates->is_array()) fail(where, type + " has no \"coordinates\" array");
    if (type == "Polygon") {
      read_polygon(*coordinates, where, flag);
    } else {
      for (std::size_t p = 0; p < coordinates->size(); ++p)
        read_polygon((*coordinates)[p], join(where, "polygon " + std::to_string(p)), flag);
    }
  }

  void read_polygon(const json& rings, const std::string& where, Flag flag) {
    if (!rings.is_array()) fail(where, "polygon is not an array of rings");
    if (rings.empty()) fail(where, "polygon has no rings");
    Polygon2 polygon;
    std::vector<Vec2> points;
    for (std::size_t r = 0; r < rings.size(); ++r) {
      const std::string ring_where = join(where, "ring " + std::to_string(r));
      read_ring(rings[r], ring_where, points);
      polygon.add_ring(points);
    }
    polygons_.push_back(std::move(polygon));
    flags_.push_back(flag);
  }

  void read_ring(const json& ring, const std::string& where, std::vector<Vec2>& points) const {
    if (!ring.is_array()) fail(where, "ring is not an array of positions");
    points.clear();
    points.reserve(ring.size());
    for (std::size_t v = 0; v < ring.size(); ++v) {
      const json& position = ring[v];
      if (!position.is_array() || position.size() < 2)
        fail(join(where, "vertex " + std::to_string(v)), "position is not an array of at least 2 numbers");
      Vec2 p;
      for (int axis = 0; axis < 2; ++axis) {
        const json& value = position[static_cast<std::size_t>(axis)];
        if (!value.is_number())
          fail(join(where, "vertex " + std::to_string(v)),
               std::string("coordinate is ") + value.type_name() + ", not a number");
        p[axis] = value.get<double>();
        if (!std::isfinite(p[axis])) fail(join(where, "vertex " + std::to_string(v)), "coordinate is not finite");
      }
      points.push_back(p);
    }
    if (!detail::has_three_distinct_points(points)) fail(where, "ring has fewer than 3 distinct points");
    // RFC 7946 §3.1.6: a linear ring's last position repeats its first. An open
    // ring is rejected rather than closed silently: its closing edge might cut
    // through the region, and `structmesh check` must be able to say so.
    if (points.size() < 2 || points.front() != points.back())
      fail(where, "ring is not closed: its last position must repeat the first (RFC 7946)");
    points.pop_back();
  }

  const std::string& source_;
  std::vector<Polygon2> polygons_;
  std::vector<Flag> flags_;  // per polygon: the Feature's marker, if any
};

void append_number(std::string& out, double value) {
  // JSON has no infinity (an area can overflow even when every coordinate is finite).
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  // Shortest representation that reads back to the same double.
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void append_ring(std::string& out, std::span<const Vec2> ring, bool counter_clockwise) {
  if (ring.empty()) {
    out += "[]";
    return;
  }
  // RFC 7946 orientation whatever the input's; the first point stays first, and is repeated last.
  const bool reverse = ring.size() >= 3 && (signed_area(ring) < 0) == counter_clockwise;
  out += '[';
  for (std::size_t i = 0; i <= ring.size(); ++i) {
    const std::size_t k = i == 0 || i == ring.size() || !reverse ? i % ring.size() : ring.size() - i;
    if (i > 0) out += ',';
    out += '[';
    append_number(out, ring[k].x());
    out += ',';
    append_number(out, ring[k].y());
    out += ']';
  }
  out += ']';
}

}  // namespace

std::vector<Polygon2> read_geojson(std::string_view data, const std::string& source_name) {
  json root;
  try {
    root = json::parse(data.begin(), data.end());
  } catch (const json::parse_error& e) {
    // nlohmann reports the byte offset; turn it into the line and column people look for.
    const std::size_t byte = std::min<std::size_t>(e.byte, data.size());
    const std::string_view before = data.substr(0, byte == 0 ? 0 : byte - 1);
    const auto line = 1 + std::count(before.begin(), before.end(), '\n');
    const std::size_t line_start = before.rfind('\n');
    const std::size_t column = line_start == std::string_view::npos ? byte : byte - 1 - line_start;
    std::string detail = e.what();
    const std::size_t colon = detail.find(": ", detail.find("parse error"));
    if (colon != std::string::npos) detail = detail.substr(colon + 2);
    throw InputError(located_message(
        source_name, static_cast<std::uint64_t>(line),
        "invalid JSON at byte " + std::to_string(byte) + " (column " + std::to_string(column) + "): " + detail));
  } catch (const json::exception& e) {
    // Such as "number overflow parsing '1e999'", without nlohmann's "[json.exception...] " tag.
    const std::string what = e.what();
    const std::size_t tag_end = what.find("] ");
    throw InputError(located_message(
        source_name, 0, "invalid JSON: " + (tag_end == std::string::npos ? what : what.substr(tag_end + 2))));
  }
  try {
    return GeoJsonReader(source_name).read(root);
  } catch (const json::exception& e) {
    // The reader checks types before every access; this is a safety net for the fuzzers.
    throw InputError(located_message(source_name, 0, std::string("unexpected GeoJSON structure: ") + e.what()));
  }
}

std::string write_geojson(const std::vector<Polygon2>& polygons) {
  std::size_t planar = 0, lon_lat_out_of_range = 0;
  for (std::size_t p = 0; p < polygons.size(); ++p) {
    const Polygon2& polygon = polygons[p];
    for (std::size_t v = 0; v < polygon.points.size(); ++v)
      if (!polygon.points[v].allFinite())
        throw InputError("cannot write GeoJSON: polygon " + std::to_string(p) + " point " + std::to_string(v) +
                         " is not finite");
    if (polygon.coordinates == Polygon2::Coordinates::Planar) {
      ++planar;
    } else {
      for (const Vec2& p : polygon.points)
        if (std::abs(p.x()) > 180 || std::abs(p.y()) > 90) {
          ++lon_lat_out_of_range;
          break;
        }
    }
  }
  // A marker only where the reader's automatic rule would get it wrong, so that
  // ordinary lon/lat data stays plain RFC 7946.
  const bool all_planar = !polygons.empty() && planar == polygons.size();
  const bool per_feature = !all_planar && (planar > 0 || lon_lat_out_of_range > 0);

  std::size_t points = 0;
  for (const Polygon2& polygon : polygons) points += polygon.points.size() + polygon.ring_count();
  std::string out;
  out.reserve(64 + 48 * points + 128 * polygons.size());
  out += "{\"type\":\"FeatureCollection\",";
  if (all_planar) out += "\"structmesh:coordinates\":\"planar\",";
  out += "\"features\":[";
  for (std::size_t p = 0; p < polygons.size(); ++p) {
    const Polygon2& polygon = polygons[p];
    out += p == 0 ? "\n" : ",\n";
    out += "{\"type\":\"Feature\",";
    if (per_feature) {
      out += polygon.coordinates == Polygon2::Coordinates::Planar ? "\"structmesh:coordinates\":\"planar\","
                                                                  : "\"structmesh:coordinates\":\"lonlat\",";
    }
    out += "\"properties\":{\"part\":" + std::to_string(p) + ",\"area\":";
    append_number(out, area(polygon));
    out += "},\"geometry\":{\"type\":\"Polygon\",\"coordinates\":[";
    for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
      if (r > 0) out += ",\n";
      append_ring(out, polygon.ring(r), r == 0);
    }
    out += "]}}";
  }
  out += "\n]}\n";
  return out;
}

}  // namespace structmesh
