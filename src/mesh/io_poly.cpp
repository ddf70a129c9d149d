// Triangle's .poly planar straight line graph as a region.
//
// Reading: the segments must form closed loops (every used vertex ends exactly
// two segments). Loops become rings by nesting depth: a loop inside an even
// number of other loops is an outer ring, one inside an odd number is a hole of
// the innermost loop around it. Triangle's hole points are parsed but not needed
// for that (a Polygon2 has no internal boundaries, so every odd-depth loop is a
// hole). Vertex numbering starts at 0 or 1, as the first vertex says. Optional
// header fields (dimension, attribute and marker counts) default as in Triangle.
// Leading comment "# structmesh:coordinates lonlat" marks lon/lat data; a .poly
// is otherwise planar.
#include "mesh/planar_geometry.hpp"
#include "mesh/text_scanner.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

namespace structmesh {

namespace {

constexpr std::string_view kLonLatMarker = "structmesh:coordinates lonlat";

std::int64_t int_field(detail::TextScanner& in, const char* what) {
  const std::string_view token = in.token_on_line();
  if (token.empty()) in.fail(std::string("line ends before the ") + what);
  return in.parse_integer(token, what);
}

double real_field(detail::TextScanner& in, const char* what) {
  const std::string_view token = in.token_on_line();
  if (token.empty()) in.fail(std::string("line ends before the ") + what);
  return in.parse_real(token, what);
}

// An optional trailing integer field: `fallback` when the line has no more tokens.
std::int64_t optional_int_field(detail::TextScanner& in, const char* what, std::int64_t fallback) {
  const std::string_view token = in.token_on_line();
  return token.empty() ? fallback : in.parse_integer(token, what);
}

// Moves to the next record; fails with `what` if the file ends first.
std::uint32_t next_record(detail::TextScanner& in, const std::string& what) {
  if (in.at_end()) in.fail("file ends before " + what);
  return in.line();
}

bool has_lon_lat_marker(std::string_view data) {
  // Only the leading comment block counts, so the marker cannot hide in the data.
  std::size_t pos = 0;
  while (pos < data.size()) {
    const std::size_t end = std::min(data.find('\n', pos), data.size());
    const std::string_view line = data.substr(pos, end - pos);
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first != std::string_view::npos && line[first] != '#') return false;
    if (line.find(kLonLatMarker) != std::string_view::npos) return true;
    pos = end + 1;
  }
  return false;
}

struct Segment {
  std::uint32_t a, b, line;
};

void append_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

// A point strictly inside `hole` and outside every ring in `islands` (outer rings
// of other polygons that may sit in the hole), for Triangle's hole list. It is the
// middle of the widest free stretch of a horizontal line halfway across the largest
// gap between the hole's vertex heights, so it is far from vertices and edges.
Vec2 point_in_hole(std::span<const Vec2> hole, const std::vector<std::span<const Vec2>>& islands) {
  std::vector<double> heights(hole.size());
  for (std::size_t i = 0; i < hole.size(); ++i) heights[i] = hole[i].y();
  std::sort(heights.begin(), heights.end());
  heights.erase(std::unique(heights.begin(), heights.end()), heights.end());
  Vec2 fallback = Vec2::Zero();
  for (const Vec2& p : hole) fallback += p / static_cast<double>(hole.size());
  if (heights.size() < 2) return fallback;

  // Candidate lines: the midpoints of the largest gaps (a few, in case one is blocked by islands).
  std::vector<std::pair<double, double>> gaps;  // (-gap, y)
  for (std::size_t i = 0; i + 1 < heights.size(); ++i)
    gaps.emplace_back(-(heights[i + 1] - heights[i]), 0.5 * heights[i] + 0.5 * heights[i + 1]);
  const std::size_t tries = std::min<std::size_t>(gaps.size(), 8);
  std::partial_sort(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(tries), gaps.end());

  // Near the top of the double range the arithmetic can overflow; any finite point then.
  if (!fallback.allFinite()) fallback = hole[0];
  Vec2 best = fallback;
  double best_width = -1;
  std::vector<std::pair<double, bool>> crossings;  // (x, crosses the hole itself)
  for (std::size_t t = 0; t < tries; ++t) {
    const double y = gaps[t].second;
    crossings.clear();
    auto add_crossings = [&](std::span<const Vec2> ring, bool is_hole) {
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Vec2& a = ring[i];
        const Vec2& b = ring[(i + 1) % ring.size()];
        if ((a.y() > y) == (b.y() > y)) continue;
        crossings.emplace_back(a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y()), is_hole);
      }
    };
    add_crossings(hole, true);
    for (const auto& island : islands) add_crossings(island, false);
    std::sort(crossings.begin(), crossings.end());
    bool in_hole = false, in_island = false;
    for (std::size_t i = 0; i + 1 < crossings.size(); ++i) {
      (crossings[i].second ? in_hole : in_island) ^= true;
      const double width = crossings[i + 1].first - crossings[i].first;
      if (in_hole && !in_island && width > best_width) {
        best_width = width;
        best = Vec2(0.5 * crossings[i].first + 0.5 * crossings[i + 1].first, y);
      }
    }
  }
  return best.allFinite() ? best : fallback;
}

}  // namespace

std::vector<Polygon2> read_poly(std::string_view data, const std::string& source_name) {
  detail::TextScanner in(data, source_name);
  in.set_comment_char('#');

  // Vertices: "<count> [<dimension> [<attributes> [<boundary markers>]]]".
  next_record(in, "the vertex header");
  const std::int64_t vertex_count = int_field(in, "vertex count");
  const std::int64_t dimension = optional_int_field(in, "dimension", 2);
  const std::int64_t attribute_count = optional_int_field(in, "attribute count", 0);
  const std::int64_t vertex_markers = optional_int_field(in, "boundary marker count", 0);
  if (vertex_count == 0) in.fail("vertex count 0: the vertices are in a separate .node file, which is not supported");
  if (vertex_count < 0 || vertex_count > 0xfffffffeLL) in.fail("bad vertex count " + std::to_string(vertex_count));
  if (dimension != 2) in.fail("dimension must be 2, found " + std::to_string(dimension));
  if (attribute_count < 0) in.fail("negative attribute count");
  if (vertex_markers != 0 && vertex_markers != 1) in.fail("boundary marker count must be 0 or 1");
  in.skip_line();

  // Never trust a count for memory: each record needs at least a few bytes.
  const auto n = static_cast<std::size_t>(vertex_count);
  std::vector<Vec2> points;
  points.reserve(std::min(n, data.size() / 4));
  std::int64_t base = 0;
  for (std::size_t i = 0; i < n; ++i) {
    next_record(in, "vertex " + std::to_string(i) + " of " + std::to_string(n));
    const std::int64_t number = int_field(in, "vertex number");
    if (i == 0) {
      if (number != 0 && number != 1) in.fail("vertices must be numbered from 0 or 1, found " + std::to_string(number));
      base = number;
    } else if (number != base + static_cast<std::int64_t>(i)) {
      in.fail("vertex numbered " + std::to_string(number) + ", expected " +
              std::to_string(base + static_cast<std::int64_t>(i)));
    }
    const double x = real_field(in, "x coordinate");
    const double y = real_field(in, "y coordinate");
    for (std::int64_t k = 0; k < attribute_count; ++k) real_field(in, "vertex attribute");
    if (vertex_markers == 1) int_field(in, "vertex boundary marker");
    points.emplace_back(x, y);
    in.skip_line();
  }

  // Segments: "<count> [<boundary markers>]", then "<number> <a> <b> [<marker>]".
  next_record(in, "the segment header");
  const std::int64_t segment_count = int_field(in, "segment count");
  const std::int64_t segment_markers = optional_int_field(in, "segment boundary marker count", 0);
  if (segment_count <= 0 || segment_count > 0xfffffffeLL)
    in.fail("segment count must be positive, found " + std::to_string(segment_count));
  if (segment_markers != 0 && segment_markers != 1) in.fail("segment boundary marker count must be 0 or 1");
  in.skip_line();
  const auto m = static_cast<std::size_t>(segment_count);
  std::vector<Segment> segments;
  segments.reserve(std::min(m, data.size() / 4));
  const std::string range = std::to_string(base) + ".." + std::to_string(base + vertex_count - 1);
  for (std::size_t s = 0; s < m; ++s) {
    const std::uint32_t line = next_record(in, "segment " + std::to_string(s) + " of " + std::to_string(m));
    int_field(in, "segment number");
    std::array<std::uint32_t, 2> ends{};
    for (auto& end : ends) {
      const std::int64_t v = int_field(in, "segment endpoint");
      if (v < base || v - base >= vertex_count)
        in.fail("segment " + std::to_string(s) + " refers to vertex " + std::to_string(v) + ", but the vertices are " +
                range);
      end = static_cast<std::uint32_t>(v - base);
    }
    if (ends[0] == ends[1])
      in.fail("segment " + std::to_string(s) + " joins vertex " + std::to_string(ends[0] + base) + " to itself");
    if (segment_markers == 1) int_field(in, "segment boundary marker");
    segments.push_back({ends[0], ends[1], line});
    in.skip_line();
  }

  // Holes ("<count>", then "<number> <x> <y>") and regional attributes: both optional here.
  for (const char* section : {"hole", "regional attribute"}) {
    if (in.at_end()) break;
    const std::int64_t count = int_field(in, (std::string(section) + " count").c_str());
    if (count < 0) in.fail(std::string("negative ") + section + " count");
    in.skip_line();
    for (std::int64_t k = 0; k < count; ++k) {
      next_record(in, std::string(section) + " " + std::to_string(k) + " of " + std::to_string(count));
      int_field(in, (std::string(section) + " number").c_str());
      real_field(in, "x coordinate");
      real_field(in, "y coordinate");
      in.skip_line();
    }
  }

  // Every used vertex must end exactly two segments, or the segments are not closed loops.
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::array<std::uint32_t, 2>> incident(n, {kNone, kNone});
  for (std::uint32_t s = 0; s < segments.size(); ++s) {
    for (const std::uint32_t v : {segments[s].a, segments[s].b}) {
      auto& slots = incident[v];
      if (slots[1] != kNone)
        throw InputError(located_message(
            source_name, segments[s].line,
            "vertex " + std::to_string(v + base) + " ends more than two segments; rings must be simple closed loops"));
      slots[slots[0] == kNone ? 0 : 1] = s;
    }
  }
  for (std::uint32_t v = 0; v < n; ++v) {
    if (incident[v][0] != kNone && incident[v][1] == kNone) {
      const Segment& s = segments[incident[v][0]];
      throw InputError(located_message(source_name, s.line,
                                       "dangling segment " + std::to_string(s.a + base) + "-" +
                                           std::to_string(s.b + base) + ": vertex " + std::to_string(v + base) +
                                           " ends no other segment, so the loop is not closed"));
    }
  }

  // Walk the loops, following the file's segment direction where it is consistent.
  Polygon2 loops;
  std::vector<bool> visited(n, false);
  std::vector<Vec2> ring;
  for (std::uint32_t start = 0; start < n; ++start) {
    if (visited[start] || incident[start][0] == kNone) continue;
    std::uint32_t s = segments[incident[start][0]].a == start || segments[incident[start][1]].a != start
                          ? incident[start][0]
                          : incident[start][1];
    ring.clear();
    std::uint32_t v = start;
    while (true) {
      visited[v] = true;
      ring.push_back(points[v]);
      const std::uint32_t w = segments[s].a == v ? segments[s].b : segments[s].a;
      if (w == start) break;
      s = incident[w][0] == s ? incident[w][1] : incident[w][0];
      v = w;
    }
    if (!detail::has_three_distinct_points(ring))
      throw InputError(located_message(
          source_name, segments[incident[start][0]].line,
          "the loop through vertex " + std::to_string(start + base) + " has fewer than 3 distinct points"));
    loops.add_ring(ring);
  }

  // Nesting depth of each loop = number of loops around its first vertex.
  std::vector<std::span<const Vec2>> spans;
  for (std::size_t r = 0; r < loops.ring_count(); ++r) spans.push_back(loops.ring(r));
  const detail::RingLocator locator(spans);
  std::vector<std::vector<std::uint32_t>> around(spans.size());
  for (std::uint32_t r = 0; r < spans.size(); ++r) around[r] = locator.containing(spans[r][0], r);

  std::vector<Polygon2> polygons;
  std::vector<std::uint32_t> polygon_of(spans.size(), kNone);
  std::vector<std::uint32_t> parent(spans.size(), kNone);
  for (std::uint32_t r = 0; r < spans.size(); ++r) {
    if (around[r].size() % 2 == 1) {
      // A hole of the deepest even-depth loop around it (crossing loops may leave none).
      std::size_t best_depth = 0;
      for (const std::uint32_t q : around[r]) {
        const std::size_t depth = around[q].size();
        if (depth % 2 == 0 && (parent[r] == kNone || depth > best_depth)) {
          parent[r] = q;
          best_depth = depth;
        }
      }
    }
    if (parent[r] == kNone) {
      polygon_of[r] = static_cast<std::uint32_t>(polygons.size());
      polygons.emplace_back().add_ring(spans[r]);
    }
  }
  for (std::uint32_t r = 0; r < spans.size(); ++r)
    if (parent[r] != kNone) polygons[polygon_of[parent[r]]].add_ring(spans[r]);

  const auto coordinates = has_lon_lat_marker(data) ? Polygon2::Coordinates::LonLat : Polygon2::Coordinates::Planar;
  for (Polygon2& polygon : polygons) {
    polygon.coordinates = coordinates;
    detail::normalize_orientation(polygon);
  }
  return polygons;
}

std::string write_poly(const std::vector<Polygon2>& polygons) {
  std::size_t vertex_count = 0, ring_count = 0;
  bool all_lon_lat = !polygons.empty();
  for (std::size_t p = 0; p < polygons.size(); ++p) {
    const Polygon2& polygon = polygons[p];
    for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
      if (polygon.ring(r).size() < 3)
        throw InputError("cannot write .poly: polygon " + std::to_string(p) + " ring " + std::to_string(r) +
                         " has fewer than 3 points");
    }
    for (std::size_t v = 0; v < polygon.points.size(); ++v)
      if (!polygon.points[v].allFinite())
        throw InputError("cannot write .poly: polygon " + std::to_string(p) + " point " + std::to_string(v) +
                         " is not finite");
    vertex_count += polygon.points.size();
    ring_count += polygon.ring_count();
    all_lon_lat = all_lon_lat && polygon.coordinates == Polygon2::Coordinates::LonLat;
  }

  std::string out;
  out.reserve(128 + 64 * vertex_count);
  out += "# structmesh region: " + std::to_string(polygons.size()) + " polygon(s), " + std::to_string(ring_count) +
         " ring(s); boundary marker = ring number\n";
  if (all_lon_lat) out += "# " + std::string(kLonLatMarker) + "\n";
  out += std::to_string(vertex_count) + " 2 0 1\n";
  std::size_t id = 1, ring_id = 1;
  for (const Polygon2& polygon : polygons) {
    for (std::size_t r = 0; r < polygon.ring_count(); ++r, ++ring_id) {
      for (const Vec2& p : polygon.ring(r)) {
        out += std::to_string(id++);
        out += ' ';
        append_number(out, p.x());
        out += ' ';
        append_number(out, p.y());
        out += ' ';
        out += std::to_string(ring_id);
        out += '\n';
      }
    }
  }
  out += std::to_string(vertex_count) + " 1\n";
  id = 1;
  ring_id = 1;
  std::size_t first = 1;
  for (const Polygon2& polygon : polygons) {
    for (std::size_t r = 0; r < polygon.ring_count(); ++r, ++ring_id) {
      const std::size_t size = polygon.ring(r).size();
      for (std::size_t i = 0; i < size; ++i, ++id) {
        const std::size_t next = i + 1 == size ? first : id + 1;
        out += std::to_string(id) + ' ' + std::to_string(id) + ' ' + std::to_string(next) + ' ' +
               std::to_string(ring_id) + '\n';
      }
      first += size;
    }
  }

  // Hole points; islands are outer rings of other polygons whose box lies inside the hole's box.
  std::vector<BoundingBox2> boxes;
  for (const Polygon2& polygon : polygons)
    boxes.push_back(polygon.ring_count() > 0 ? bounding_box(polygon.ring(0)) : BoundingBox2{});
  std::vector<Vec2> hole_points;
  std::vector<std::span<const Vec2>> islands;
  for (std::size_t p = 0; p < polygons.size(); ++p) {
    for (std::size_t r = 1; r < polygons[p].ring_count(); ++r) {
      const auto hole = polygons[p].ring(r);
      const BoundingBox2 box = bounding_box(hole);
      islands.clear();
      for (std::size_t q = 0; q < polygons.size(); ++q) {
        if (q == p || boxes[q].empty()) continue;
        if (box.min.x() <= boxes[q].min.x() && boxes[q].max.x() <= box.max.x() && box.min.y() <= boxes[q].min.y() &&
            boxes[q].max.y() <= box.max.y())
          islands.push_back(polygons[q].ring(0));
      }
      hole_points.push_back(point_in_hole(hole, islands));
    }
  }
  out += std::to_string(hole_points.size()) + "\n";
  for (std::size_t h = 0; h < hole_points.size(); ++h) {
    out += std::to_string(h + 1);
    out += ' ';
    append_number(out, hole_points[h].x());
    out += ' ';
    append_number(out, hole_points[h].y());
    out += '\n';
  }
  return out;
}

}  // namespace structmesh
