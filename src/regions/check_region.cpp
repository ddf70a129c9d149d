// check_region(): is a set of polygons a valid region to mesh?
//
// Problem kinds: "empty" (no polygons), "empty-polygon" (no rings), "non-finite",
// "duplicate-point" (consecutive repeat, also last == first), "short-ring" (fewer
// than 3 distinct points), "self-intersection" (segments that cross or touch,
// within a ring or between any two rings, including a ring folding back on
// itself), "hole-outside" (a hole not inside its outer ring), "nested-hole" (a
// hole inside another hole of the same polygon) and "polygons-overlap" (one
// polygon inside another's interior; counted in RegionReport::overlapping_polygons).
//
// All geometric decisions use exact orientation predicates, so collinear runs and
// touching rings are judged exactly. Candidate segment pairs come from a recursive
// uniform grid (each level about one cell per segment, a cell splits while it holds
// many segments), so the cost is about linear in the number of segments for
// boundary-like inputs, never all pairs.
#include "mesh/planar_geometry.hpp"
#include "structmesh/check.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>

namespace structmesh {

namespace {

using detail::orient2d;

struct RingInfo {
  std::uint32_t polygon = 0, ring = 0;  // ring index within its polygon (0 = outer)
  std::span<const Vec2> points;
  std::vector<std::uint32_t> kept;  // vertex indices without consecutive repeats
  bool usable = false;              // enough distinct finite points to have segments
  bool intersected = false;         // takes part in a self-intersection
};

struct Segment {
  Vec2 a, b;
  std::uint32_t ring;  // index into the RingInfo list
  std::uint32_t k;     // from kept[k] to kept[k + 1] (cyclically)
};

std::string format_point(const Vec2& p) {
  char buffer[64];
  char* end = buffer;
  *end++ = '(';
  end = std::to_chars(end, buffer + 30, p.x()).ptr;
  *end++ = ',';
  *end++ = ' ';
  end = std::to_chars(end, buffer + 62, p.y()).ptr;
  *end++ = ')';
  return std::string(buffer, end);
}

std::string ring_name(const RingInfo& ring) {
  return "polygon " + std::to_string(ring.polygon) + " ring " + std::to_string(ring.ring) +
         (ring.ring == 0 ? " (outer)" : " (hole)");
}

class Problems {
 public:
  Problems(RegionReport& report, std::size_t cap) : report_(report), cap_(cap) {}
  void add(const std::string& kind, const std::string& message, std::int64_t element) {
    if (counts_[kind]++ < cap_) report_.problems.push_back({kind, message, 0, element});
  }
  bool any() const { return !counts_.empty(); }

 private:
  RegionReport& report_;
  std::size_t cap_;
  std::map<std::string, std::size_t> counts_;
};

// Candidate pairs of segments whose padded grid cells meet, tested exactly.
class PairFinder {
 public:
  PairFinder(const std::vector<Segment>& segments, const std::vector<RingInfo>& rings)
      : segments_(segments), rings_(rings) {}

  std::vector<std::uint64_t> run() {
    if (segments_.size() < 2) return {};
    Box box;
    double magnitude = 0;
    for (const Segment& s : segments_) {
      for (const Vec2& p : {s.a, s.b}) {
        box.x0 = std::min(box.x0, p.x());
        box.y0 = std::min(box.y0, p.y());
        box.x1 = std::max(box.x1, p.x());
        box.y1 = std::max(box.y1, p.y());
        magnitude = std::max({magnitude, std::abs(p.x()), std::abs(p.y())});
      }
    }
    // Cells are padded by far more than the rounding error of the cell arithmetic
    // and of interpolating along a segment, so a contact point is always in a cell
    // both segments were put in.
    pad_ = 256 * std::numeric_limits<double>::epsilon() * std::max(magnitude, std::numeric_limits<double>::min());
    box.x0 -= pad_;
    box.y0 -= pad_;
    box.x1 += pad_;
    box.y1 += pad_;
    std::vector<std::uint32_t> ids(segments_.size());
    for (std::uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
    split(ids, box, 0);
    std::sort(found_.begin(), found_.end());
    found_.erase(std::unique(found_.begin(), found_.end()), found_.end());
    return std::move(found_);
  }

 private:
  struct Box {
    double x0 = std::numeric_limits<double>::infinity(), y0 = std::numeric_limits<double>::infinity();
    double x1 = -std::numeric_limits<double>::infinity(), y1 = -std::numeric_limits<double>::infinity();
  };
  static constexpr std::size_t kLeafSize = 24;
  static constexpr int kMaxDepth = 40;
  static constexpr std::size_t kMaxCellsPerAxis = 1 << 12;

  // Cell index along an axis, clamped in floating point so no out-of-range value is cast.
  static std::size_t cell(double value, double origin, double size, std::size_t count) {
    const double t = (value - origin) / size;
    if (!(t > 0)) return 0;
    if (t >= static_cast<double>(count - 1)) return count - 1;
    return static_cast<std::size_t>(t);
  }

  bool adjacent(const Segment& s, const Segment& t) const {
    if (s.ring != t.ring) return false;
    const std::size_t n = rings_[s.ring].kept.size();
    return (s.k + 1) % n == t.k || (t.k + 1) % n == s.k;
  }

  void test(std::uint32_t i, std::uint32_t j) {
    const Segment& s = segments_[i];
    const Segment& t = segments_[j];
    if (std::max(s.a.x(), s.b.x()) < std::min(t.a.x(), t.b.x()) ||
        std::max(t.a.x(), t.b.x()) < std::min(s.a.x(), s.b.x()) ||
        std::max(s.a.y(), s.b.y()) < std::min(t.a.y(), t.b.y()) ||
        std::max(t.a.y(), t.b.y()) < std::min(s.a.y(), s.b.y()) || adjacent(s, t))
      return;
    if (detail::segment_contact(s.a, s.b, t.a, t.b) != detail::SegmentContact::None)
      found_.push_back(std::uint64_t{std::min(i, j)} << 32 | std::max(i, j));
  }

  // Calls emit(column, row) for every cell of the grid that the segment passes
  // within `pad_` of. Walks the segment's major axis so that interpolation
  // errors are never magnified by a steep slope.
  template <typename Emit>
  void cells_of(const Segment& s, const Box& box, std::size_t nx, std::size_t ny, double sx, double sy,
                Emit&& emit) const {
    const bool x_major = std::abs(s.b.x() - s.a.x()) >= std::abs(s.b.y() - s.a.y());
    // u: the major axis, v: the minor one.
    auto u = [x_major](const Vec2& p) { return x_major ? p.x() : p.y(); };
    auto v = [x_major](const Vec2& p) { return x_major ? p.y() : p.x(); };
    Vec2 a = s.a, b = s.b;
    if (u(a) > u(b)) std::swap(a, b);
    const double u0 = x_major ? box.x0 : box.y0, u1 = x_major ? box.x1 : box.y1;
    const double v0 = x_major ? box.y0 : box.x0, v1 = x_major ? box.y1 : box.x1;
    const double su = x_major ? sx : sy, sv = x_major ? sy : sx;
    const std::size_t nu = x_major ? nx : ny, nv = x_major ? ny : nx;
    const double ua = std::max(u(a), u0), ub = std::min(u(b), u1);
    if (ua > ub) return;
    const double v_low = std::max(std::min(v(a), v(b)), v0), v_high = std::min(std::max(v(a), v(b)), v1);
    const double slope = (v(b) - v(a)) / (u(b) - u(a));  // |slope| <= 1; u(b) > u(a) for a proper segment
    auto v_at = [&](double w) { return w == u(a) ? v(a) : w == u(b) ? v(b) : v(a) + (w - u(a)) * slope; };
    const std::size_t first = cell(ua, u0, su, nu), last = cell(ub, u0, su, nu);
    for (std::size_t c = first; c <= last; ++c) {
      const double w0 = std::max(ua, u0 + static_cast<double>(c) * su - pad_);
      const double w1 = std::min(ub, u0 + static_cast<double>(c + 1) * su + pad_);
      if (w0 > w1) continue;
      const double p = v_at(w0), q = v_at(w1);
      const double lo = std::max(std::min(p, q) - pad_, v_low), hi = std::min(std::max(p, q) + pad_, v_high);
      if (lo > hi) continue;
      for (std::size_t r = cell(lo, v0, sv, nv); r <= cell(hi, v0, sv, nv); ++r) x_major ? emit(c, r) : emit(r, c);
    }
  }

  void split(std::span<const std::uint32_t> ids, const Box& box, int depth) {
    const std::size_t m = ids.size();
    const double width = box.x1 - box.x0, height = box.y1 - box.y0;
    if (m <= kLeafSize || depth >= kMaxDepth || !(width > 64 * pad_ || height > 64 * pad_) || !std::isfinite(width) ||
        !std::isfinite(height)) {
      for (std::size_t i = 0; i < m; ++i)
        for (std::size_t j = i + 1; j < m; ++j) test(ids[i], ids[j]);
      return;
    }
    // About one cell per segment, shaped like the box.
    const double target = static_cast<double>(m);
    double nx_real = 1, ny_real = 1;
    if (width > 64 * pad_ && height > 64 * pad_) {
      nx_real = std::sqrt(target * width / height);
      ny_real = target / std::max(nx_real, 1.0);
    } else if (width > 64 * pad_) {
      nx_real = target;
    } else {
      ny_real = target;
    }
    const double max_axis = static_cast<double>(kMaxCellsPerAxis);
    const auto nx = static_cast<std::size_t>(std::clamp(std::round(nx_real), 1.0, max_axis));
    const auto ny = static_cast<std::size_t>(std::clamp(std::round(ny_real), 1.0, max_axis));
    const double sx = width / static_cast<double>(nx), sy = height / static_cast<double>(ny);

    // Bucket the segments by cell: one walk records (cell, segment), a counting sort groups them.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> entries;
    entries.reserve(2 * ids.size());
    for (const std::uint32_t id : ids) {
      cells_of(segments_[id], box, nx, ny, sx, sy,
               [&](std::size_t c, std::size_t r) { entries.emplace_back(static_cast<std::uint32_t>(r * nx + c), id); });
    }
    std::vector<std::uint32_t> offsets(nx * ny + 1, 0);
    for (const auto& entry : entries) ++offsets[entry.first + 1];
    for (std::size_t k = 0; k < nx * ny; ++k) offsets[k + 1] += offsets[k];
    std::vector<std::uint32_t> items(entries.size());
    for (const auto& [k, id] : entries) items[offsets[k]++] = id;  // offsets[k] ends as the start of k + 1
    entries = {};
    for (std::size_t r = 0; r < ny; ++r) {
      for (std::size_t c = 0; c < nx; ++c) {
        const std::size_t k = r * nx + c;
        const std::uint32_t begin = k == 0 ? 0 : offsets[k - 1], end = offsets[k];
        if (end - begin < 2) continue;
        Box cell_box;
        cell_box.x0 = c == 0 ? box.x0 : box.x0 + static_cast<double>(c) * sx - pad_;
        cell_box.x1 = c + 1 == nx ? box.x1 : box.x0 + static_cast<double>(c + 1) * sx + pad_;
        cell_box.y0 = r == 0 ? box.y0 : box.y0 + static_cast<double>(r) * sy - pad_;
        cell_box.y1 = r + 1 == ny ? box.y1 : box.y0 + static_cast<double>(r + 1) * sy + pad_;
        split(std::span<const std::uint32_t>(items.data() + begin, end - begin), cell_box, depth + 1);
      }
    }
  }

  const std::vector<Segment>& segments_;
  const std::vector<RingInfo>& rings_;
  std::vector<std::uint64_t> found_;  // (smaller id << 32) | larger id
  double pad_ = 0;
};

// A point where two segments known to meet do so, for messages.
Vec2 contact_point(const Segment& s, const Segment& t) {
  for (const Vec2& p : {t.a, t.b})
    if (orient2d(s.a, s.b, p) == 0) return p;
  for (const Vec2& p : {s.a, s.b})
    if (orient2d(t.a, t.b, p) == 0) return p;
  const Vec2 d = s.b - s.a, e = t.b - t.a;
  const double denominator = d.x() * e.y() - d.y() * e.x();
  const double along = ((t.a.x() - s.a.x()) * e.y() - (t.a.y() - s.a.y()) * e.x()) / denominator;
  return s.a + along * d;
}

}  // namespace

RegionReport check_region(const std::vector<Polygon2>& polygons, const CheckOptions& options) {
  RegionReport report;
  Problems problems(report, options.max_problems_per_kind);
  report.polygons = polygons.size();
  if (polygons.empty()) problems.add("empty", "the region has no polygons", -1);

  // Rings: drop consecutive repeats, find the ones too small to be rings.
  std::vector<RingInfo> rings;
  std::vector<std::uint32_t> first_ring_of(polygons.size() + 1, 0);
  for (std::uint32_t p = 0; p < polygons.size(); ++p) {
    const Polygon2& polygon = polygons[p];
    first_ring_of[p] = static_cast<std::uint32_t>(rings.size());
    report.rings += polygon.ring_count();
    report.holes += polygon.hole_count();
    report.vertices += polygon.points.size();
    report.area += area(polygon);
    if (polygon.ring_count() == 0) problems.add("empty-polygon", "polygon " + std::to_string(p) + " has no rings", -1);
    for (std::uint32_t r = 0; r < polygon.ring_count(); ++r) {
      RingInfo& info = rings.emplace_back();
      info.polygon = p;
      info.ring = r;
      info.points = polygon.ring(r);
      const auto& pts = info.points;
      bool finite = true;
      for (std::size_t i = 0; i < pts.size() && finite; ++i) {
        if (!pts[i].allFinite()) {
          finite = false;
          problems.add("non-finite", ring_name(info) + ": vertex " + std::to_string(i) + " is not finite", r);
        }
      }
      if (!finite) continue;
      for (std::uint32_t i = 0; i < pts.size(); ++i) {
        if (!info.kept.empty() && pts[i] == pts[info.kept.back()]) {
          ++report.duplicate_points;
          problems.add("duplicate-point",
                       ring_name(info) + ": vertex " + std::to_string(i) + " repeats vertex " +
                           std::to_string(info.kept.back()) + " at " + format_point(pts[i]),
                       r);
        } else {
          info.kept.push_back(i);
        }
      }
      while (info.kept.size() > 1 && pts[info.kept.back()] == pts[info.kept.front()]) {
        ++report.duplicate_points;
        problems.add("duplicate-point",
                     ring_name(info) + ": last vertex " + std::to_string(info.kept.back()) + " repeats the first at " +
                         format_point(pts[info.kept.back()]) + " (rings are closed implicitly)",
                     r);
        info.kept.pop_back();
      }
      if (!detail::has_three_distinct_points(pts)) {
        ++report.short_rings;
        problems.add(
            "short-ring",
            ring_name(info) + " has fewer than 3 distinct points (" + std::to_string(pts.size()) + " vertices)", r);
        continue;
      }
      info.usable = true;
    }
  }
  first_ring_of[polygons.size()] = static_cast<std::uint32_t>(rings.size());

  // A ring that doubles back at a vertex: its two segments there overlap.
  std::vector<Segment> segments;
  for (std::uint32_t g = 0; g < rings.size(); ++g) {
    RingInfo& info = rings[g];
    if (!info.usable) continue;
    const std::size_t n = info.kept.size();
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2& previous = info.points[info.kept[(k + n - 1) % n]];
      const Vec2& here = info.points[info.kept[k]];
      const Vec2& next = info.points[info.kept[(k + 1) % n]];
      segments.push_back({here, next, g, static_cast<std::uint32_t>(k)});
      if (orient2d(previous, here, next) != 0) continue;
      const bool same_side = previous.x() != here.x() ? (previous.x() < here.x()) == (next.x() < here.x())
                                                      : (previous.y() < here.y()) == (next.y() < here.y());
      if (!same_side) continue;
      ++report.self_intersections;
      info.intersected = true;
      problems.add("self-intersection",
                   ring_name(info) + ": the ring folds back on itself at vertex " + std::to_string(info.kept[k]) + " " +
                       format_point(here) + " (its two segments there overlap)",
                   info.ring);
    }
  }

  // Crossing and touching segment pairs.
  for (const std::uint64_t pair : PairFinder(segments, rings).run()) {
    const Segment& s = segments[pair >> 32];
    const Segment& t = segments[pair & 0xffffffffu];
    RingInfo& rs = rings[s.ring];
    RingInfo& rt = rings[t.ring];
    const bool cross = detail::segment_contact(s.a, s.b, t.a, t.b) == detail::SegmentContact::Cross;
    if (options.shared_boundaries && !cross && rs.polygon != rt.polygon) continue;
    rs.intersected = rt.intersected = true;
    ++report.self_intersections;
    auto describe = [](const RingInfo& ring, const Segment& segment) {
      return ring_name(ring) + " segment " + std::to_string(ring.kept[segment.k]) + "-" +
             std::to_string(ring.kept[(segment.k + 1) % ring.kept.size()]);
    };
    problems.add("self-intersection",
                 describe(rs, s) + (cross ? " crosses " : " touches ") + describe(rt, t) + " at " +
                     format_point(contact_point(s, t)),
                 rs.ring);
  }

  // Containment, judged at one vertex per ring (exact for rings that meet no
  // other ring; rings in an intersection are already reported and skipped).
  std::vector<std::span<const Vec2>> spans(rings.size());
  for (std::size_t g = 0; g < rings.size(); ++g)
    if (rings[g].usable) spans[g] = rings[g].points;
  const detail::RingLocator locator(spans);
  for (std::uint32_t g = 0; g < rings.size(); ++g) {
    const RingInfo& info = rings[g];
    if (!info.usable || info.intersected) continue;
    const Vec2& probe = info.points[info.kept[0]];
    const std::vector<std::uint32_t> around = locator.containing(probe, g);
    auto inside = [&around](std::uint32_t ring) { return std::binary_search(around.begin(), around.end(), ring); };
    const std::uint32_t own_outer = first_ring_of[info.polygon];
    if (info.ring > 0) {
      if (rings[own_outer].usable && !inside(own_outer)) {
        ++report.holes_outside;
        problems.add("hole-outside",
                     ring_name(info) + " is not inside the outer ring of its polygon (vertex " +
                         std::to_string(info.kept[0]) + " at " + format_point(probe) + " is outside)",
                     info.ring);
      }
      for (std::uint32_t h = own_outer + 1; h < first_ring_of[info.polygon + 1]; ++h) {
        if (h == g || !inside(h)) continue;
        ++report.nested_holes;
        problems.add("nested-hole", ring_name(info) + " lies inside " + ring_name(rings[h]), info.ring);
      }
      continue;
    }
    // An outer ring in another polygon's interior (inside its outer ring, in none of its holes).
    if (options.shared_boundaries) continue;
    for (std::uint32_t q = 0; q < polygons.size(); ++q) {
      if (q == info.polygon || first_ring_of[q] == first_ring_of[q + 1] || !inside(first_ring_of[q])) continue;
      bool in_hole = false;
      for (std::uint32_t h = first_ring_of[q] + 1; h < first_ring_of[q + 1] && !in_hole; ++h) in_hole = inside(h);
      if (in_hole) continue;
      ++report.overlapping_polygons;
      problems.add("polygons-overlap",
                   "polygon " + std::to_string(info.polygon) + " lies inside polygon " + std::to_string(q), 0);
    }
  }

  report.valid = !problems.any();
  return report;
}

}  // namespace structmesh
