// sample_partition(): consistent boundary samples for every part (§3.3.1).
//
// Each curve of the partition (a separator between two parts, or a piece of the
// region boundary) is sampled once, by arc length, and both parts use those
// samples, so the part meshes share their boundary vertices by construction.
// Paving needs an even number of boundary points per part [80]. The dissertation
// doubles every separator sample; we instead round each curve to the nearest
// segment count and then fix the parity of the odd parts with a T-join on a
// spanning tree of the part adjacency (the outside of the region is the root and
// absorbs any parity), which changes the fewest curves by one segment each and keeps
// the spacing close to the requested size.
#include "mesh/planar_geometry.hpp"
#include "quad2d/interval_assignment.hpp"
#include "quad2d/paving.hpp"

#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <queue>
#include <string>

namespace structmesh {

namespace {

// Region boundary vertices that turn by more than this are kept as samples, so the
// Key's teeth and other sharp features survive resampling.
constexpr double kCornerTurn = 25.0 * std::numbers::pi / 180.0;
// Region boundary samples closer than this many sizes across water (not at a shared
// end) count as crossing (crossing_segments).
constexpr double kSampleClearance = 0.25;
// A boundary vertex whose sides meet at less than this over a narrow base is the tip
// of a needle (thinning removes it).
constexpr double kNeedleAngle = 30.0 * std::numbers::pi / 180.0;
// Interior angles that make a part four-sided: its four smallest below 150°, every
// other break at least 100° (the side bends there) and none above 225° (reflex).
// mapped_mesh() refuses the parts where this was too optimistic; they are paved.
constexpr double kCornerAngle = 150.0 * std::numbers::pi / 180.0;
constexpr double kSideAngleMin = 100.0 * std::numbers::pi / 180.0;
constexpr double kSideAngleMax = 1.25 * std::numbers::pi;
// Polar blocks for parts with 3..8 corners (more: the centre sees too much).
constexpr std::size_t kMaxPolarCorners = 8;
// Interval assignment rewards (a matching grid: 2, no singular point): polar blocks
// have one singular point; the three-block alternative of a four-sided part is
// worth less than changing its sides' counts a little to make the grid match.
constexpr double kPolarReward = 1.5;
constexpr double kAlternativePolarReward = 0.75;
constexpr double kUnmatchableRatio = 1.6;  // a bit below 1.33 / 0.75
// Parts of up to this many expected quads: their polar blocks can be polished
// together (polish_quads() takes up to 20k free points).
constexpr double kSmallPartQuads = 15000;

// A curve as pieces between kept vertices: piece i runs from polyline vertex
// breaks[i] to breaks[i+1] and gets segments[i] segments.
struct CurvePlan {
  std::vector<Vec2> polyline;
  std::vector<std::size_t> breaks;
  std::vector<Index> break_vertices;  // partition vertex at each break
  bool smoothed = false;
  /// Samples are the polyline's own vertices (a region boundary piece whose
  /// resampling would cross something), each polyline edge split evenly into
  /// edge_segments[i] segments (about its length / size, one more on the longest
  /// when the count's parity has to stay).
  bool exact = false;
  /// Position in the curve's input vertices of each polyline vertex (a region
  /// boundary thinned by thinned_vertices holds only some of them; exact then means
  /// those).
  std::vector<std::size_t> source;
  std::vector<Index> edge_segments;  // exact plans: per polyline edge
  std::vector<double> lengths;
  std::vector<Index> segments;
  bool closed = false;
};

double turning_angle(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 u = b - a, v = c - b;
  return std::abs(std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v)));
}

double polyline_length(std::span<const Vec2> points, std::size_t from, std::size_t to) {
  double length = 0;
  for (std::size_t i = from; i < to; ++i) length += (points[i + 1] - points[i]).norm();
  return length;
}

// Point at arc length s along polyline[from..to].
Vec2 point_at(std::span<const Vec2> points, std::size_t from, std::size_t to, double s) {
  for (std::size_t i = from; i < to; ++i) {
    const double length = (points[i + 1] - points[i]).norm();
    if (s <= length || i + 1 == to) {
      const double t = length > 0 ? std::clamp(s / length, 0.0, 1.0) : 0.0;
      return points[i] + t * (points[i + 1] - points[i]);
    }
    s -= length;
  }
  return points[to];
}

// A separator follows CVT cell edges: a staircase whose steps are as large as a
// cell. Part meshes want smooth sides (paving rows follow them; a structured grid
// folds at a reflex step), so the separator is resampled to m = 8..64 even points
// and smoothed with 2m Laplacian sweeps (ends fixed), which flattens steps up to
// about a fifth of its length. sample_partition() reverts a separator to its cell
// edges if the smoothed one would cross another curve.
std::vector<Vec2> smoothed_separator(const std::vector<Vec2>& polyline, double size) {
  const double length = polyline_length(polyline, 0, polyline.size() - 1);
  const std::size_t m = static_cast<std::size_t>(std::clamp(std::round(length / size), 8.0, 64.0));
  std::vector<Vec2> points(m + 1), next(m + 1);
  for (std::size_t i = 0; i <= m; ++i)
    points[i] = point_at(polyline, 0, polyline.size() - 1, length * static_cast<double>(i) / static_cast<double>(m));
  points.front() = polyline.front();
  points.back() = polyline.back();
  for (std::size_t sweep = 0; sweep < 2 * m; ++sweep) {
    next = points;
    for (std::size_t i = 1; i < m; ++i) next[i] = 0.5 * points[i] + 0.25 * (points[i - 1] + points[i + 1]);
    points.swap(next);
  }
  return points;
}

// A region boundary finer than the element size (a natural coastline: inlets and
// spits of a few hundred metres meshed at a kilometre and more) is thinned before it
// is sampled: walking along it, a vertex is kept when it is at least half a size
// from the last kept one, or when it is a corner of the boundary at the mesh's scale
// (turns by more than kCornerTurn between edges of at least half a size, like the
// Key's teeth). Sampling every input vertex there, or cutting the raw polyline by arc
// length, gives part boundaries of needle-like spikes between points a mesher cannot
// move: measured on the Gulf of Mexico at 1M quads, 59 of 512 parts could not be
// paved without an inverted quad. Kept vertices are input vertices, so the region
// is reproduced within half a size; where the thinned boundary would cross
// something, sample_partition keeps every input vertex along that stretch
// (follow_input).
// Visvalingam-Whyatt simplification (1993), measured at the element size: drops the
// vertex whose triangle with its two neighbours is least significant while that
// triangle is smaller than (size/4)^2 or thinner than size/8 (its height over its
// longest side): a heap with lazy deletion, O(n log n). Unlike a distance tolerance
// it also removes long needle-like spits and inlets, which no quad of that size can
// follow, while keeping broad features.
std::vector<std::size_t> visvalingam(const Partition& partition, const PartitionCurve& curve, double size,
                                     const std::vector<std::uint8_t>& protect, bool needles_only) {
  const std::size_t n = curve.vertices.size();
  std::vector<std::size_t> all(n);
  std::iota(all.begin(), all.end(), std::size_t{0});
  if (n < 4) return all;
  const auto at = [&](std::size_t i) -> const Vec2& { return partition.metric_vertices[curve.vertices[i]]; };
  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t i = 0; i < n; ++i) prev[i] = i - 1, next[i] = i + 1;
  const double area_limit = 0.0625 * size * size, thin_limit = 0.125 * size;
  // Significance below 1: the vertex goes. A needle (the tip of a spit or inlet:
  // its sides meet at less than 30 degrees over a base narrower than size/4) always.
  const auto significance = [&](std::size_t i) {
    const Vec2 u = at(prev[i]) - at(i), v = at(next[i]) - at(i);
    const double cross = u.x() * v.y() - u.y() * v.x();
    const bool needle =
        std::abs(std::atan2(cross, u.dot(v))) < kNeedleAngle && (at(next[i]) - at(prev[i])).norm() < 0.25 * size;
    if (needle) return 0.0;
    if (needles_only) return std::numeric_limits<double>::infinity();
    const double area = 0.5 * std::abs(cross);
    const double longest = std::max({u.norm(), v.norm(), (at(next[i]) - at(prev[i])).norm()});
    const double height = longest > 0 ? 2 * area / longest : 0.0;
    return std::min(area / area_limit, height / thin_limit);
  };
  std::vector<double> key(n, std::numeric_limits<double>::infinity());
  // Only finite significances enter the heap (needles_only: only needles).
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap;
  for (std::size_t i = 1; i + 1 < n; ++i)
    if (!protect[i] && std::isfinite(key[i] = significance(i))) heap.emplace(key[i], i);
  std::vector<std::uint8_t> removed(n, 0);
  std::size_t left = n;
  while (!heap.empty() && left > 4) {
    const auto [value, i] = heap.top();
    heap.pop();
    if (removed[i] || value != key[i]) continue;  // stale entry
    if (value >= 1) break;
    removed[i] = 1;
    --left;
    next[prev[i]] = next[i];
    prev[next[i]] = prev[i];
    for (const std::size_t j : {prev[i], next[i]})
      if (j != 0 && j + 1 != n && !protect[j] && std::isfinite(key[j] = significance(j))) heap.emplace(key[j], j);
  }
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i)
    if (!removed[i]) kept.push_back(i);
  return kept;
}

// The positions (into curve.vertices) kept by thinning; `protect` marks positions
// that must stay (stretches where the thinned curve crossed something).
std::vector<std::size_t> thinned_vertices(const Partition& partition, const PartitionCurve& curve, double size,
                                          const std::vector<std::uint8_t>& protect) {
  const std::vector<std::size_t> all = visvalingam(partition, curve, size, protect, false);
  const auto at = [&](std::size_t i) -> const Vec2& { return partition.metric_vertices[curve.vertices[all[i]]]; };
  const std::size_t last = all.size() - 1;
  const double reach = 0.5 * size;
  std::vector<std::size_t> kept{all.front()};
  std::size_t previous = 0;
  std::vector<std::uint8_t> forced(all.size(), 0);
  for (std::size_t i = 1; i < last; ++i) {
    forced[i] = protect[all[i]] || (turning_angle(at(i - 1), at(i), at(i + 1)) > kCornerTurn &&
                                    (at(i) - at(i - 1)).norm() >= reach && (at(i + 1) - at(i)).norm() >= reach);
    if (!forced[i] && (at(i) - at(previous)).norm() < reach) continue;
    kept.push_back(all[i]);
    previous = i;
  }
  // The end is a junction or the start of a closed curve: always kept; a kept vertex
  // too close before it goes unless it is a corner.
  if (kept.size() > 1 && previous != 0 && !forced[previous] && (at(last) - at(previous)).norm() < 0.5 * reach)
    kept.pop_back();
  kept.push_back(all.back());
  const bool closed = curve.vertices.front() == curve.vertices.back();
  if (closed && kept.size() < 5) {  // an island about the size of an element keeps its shape
    kept.resize(curve.vertices.size());
    std::iota(kept.begin(), kept.end(), std::size_t{0});
  }
  return kept;
}

CurvePlan plan_curve(const Partition& partition, const PartitionCurve& curve, double size, bool smooth,
                     const std::vector<std::uint8_t>* protect = nullptr) {
  CurvePlan plan;
  const bool boundary = curve.kind == PartitionCurve::Kind::Boundary;
  // Only a boundary finer than the elements is thinned (on average more than two
  // vertices per element edge); a designed shape like the Key keeps its vertices.
  double length = 0;
  for (std::size_t i = 1; i < curve.vertices.size(); ++i)
    length += (partition.metric_vertices[curve.vertices[i]] - partition.metric_vertices[curve.vertices[i - 1]]).norm();
  const bool fine = length < 0.5 * size * static_cast<double>(curve.vertices.size() - 1);
  const std::vector<std::uint8_t> none(boundary ? curve.vertices.size() : 0, 0);
  if (boundary && fine) {
    plan.source = thinned_vertices(partition, curve, size, protect ? *protect : none);
  } else if (boundary) {
    // A boundary as coarse as the elements keeps its vertices but its needles.
    plan.source = visvalingam(partition, curve, size, protect ? *protect : none, true);
  } else {
    plan.source.resize(curve.vertices.size());
    std::iota(plan.source.begin(), plan.source.end(), std::size_t{0});
  }
  std::vector<Index> vertices;
  for (const std::size_t i : plan.source) vertices.push_back(curve.vertices[i]);
  for (const Index v : vertices) plan.polyline.push_back(partition.metric_vertices[v]);
  const std::size_t last = plan.polyline.size() - 1;
  plan.closed = curve.vertices.front() == curve.vertices.back();
  plan.breaks.push_back(0);
  if (boundary) {
    for (std::size_t i = 1; i < last; ++i)
      if (turning_angle(plan.polyline[i - 1], plan.polyline[i], plan.polyline[i + 1]) > kCornerTurn)
        plan.breaks.push_back(i);
  }
  plan.breaks.push_back(last);
  for (const std::size_t b : plan.breaks) plan.break_vertices.push_back(vertices[b]);
  if (smooth && curve.kind == PartitionCurve::Kind::Separator && !plan.closed) {
    plan.polyline = smoothed_separator(plan.polyline, size);
    plan.breaks = {0, plan.polyline.size() - 1};
    plan.smoothed = true;
  }
  for (std::size_t i = 0; i + 1 < plan.breaks.size(); ++i) {
    const double length = polyline_length(plan.polyline, plan.breaks[i], plan.breaks[i + 1]);
    plan.lengths.push_back(length);
    plan.segments.push_back(static_cast<Index>(std::max(1.0, std::round(length / size))));
  }
  // A closed curve (an island inside one part) needs at least a triangle.
  if (plan.closed) {
    Index total = 0;
    for (const Index s : plan.segments) total += s;
    if (total < 3) plan.segments[0] += 3 - total;
  }
  return plan;
}

Index total_segments(const CurvePlan& plan) {
  Index total = 0;
  for (const Index s : plan.segments) total += s;
  return total;
}

// Changes the curve's segment count by one, in the direction that brings a piece
// closest to its ideal count (length / size) and never below the minimum.
void flip_parity(CurvePlan& plan, double size) {
  const Index minimum_total = plan.closed ? 3 : 1;
  std::size_t best = 0;
  int best_step = 0;
  double best_error = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < plan.segments.size(); ++i) {
    const double ideal = plan.lengths[i] / size;
    for (const int step : {+1, -1}) {
      const double count = static_cast<double>(plan.segments[i]) + step;
      if (count < 1 || total_segments(plan) + step < minimum_total) continue;
      const double error = std::abs(count - ideal) - std::abs(static_cast<double>(plan.segments[i]) - ideal);
      if (error < best_error) best_error = error, best = i, best_step = step;
    }
  }
  plan.segments[best] = static_cast<Index>(static_cast<int>(plan.segments[best]) + best_step);
}

// The sample positions of a plan, piece ends included.
// The samples of a plan in order, piece ends included; break_of[i] is the index of
// the break a sample sits on (into plan.break_vertices), or -1.
struct Samples {
  std::vector<Vec2> points;
  std::vector<std::int64_t> break_of;
};

Samples sample_positions(const CurvePlan& plan) {
  Samples out;
  if (plan.exact) {
    std::size_t next_break = 0;
    for (std::size_t i = 0; i < plan.polyline.size(); ++i) {
      const bool on_break = next_break < plan.breaks.size() && plan.breaks[next_break] == i;
      out.points.push_back(plan.polyline[i]);
      out.break_of.push_back(on_break ? static_cast<std::int64_t>(next_break++) : -1);
      if (i + 1 == plan.polyline.size()) break;
      const Index n = plan.edge_segments[i];
      for (Index j = 1; j < n; ++j) {
        const double t = static_cast<double>(j) / n;
        out.points.push_back((1 - t) * plan.polyline[i] + t * plan.polyline[i + 1]);
        out.break_of.push_back(-1);
      }
    }
    return out;
  }
  for (std::size_t piece = 0; piece < plan.segments.size(); ++piece) {
    const std::size_t from = plan.breaks[piece], to = plan.breaks[piece + 1];
    out.points.push_back(plan.polyline[from]);
    out.break_of.push_back(static_cast<std::int64_t>(piece));
    const Index n = plan.segments[piece];
    for (Index j = 1; j < n; ++j) {
      out.points.push_back(point_at(plan.polyline, from, to, plan.lengths[piece] * j / n));
      out.break_of.push_back(-1);
    }
  }
  out.points.push_back(plan.polyline.back());
  out.break_of.push_back(static_cast<std::int64_t>(plan.breaks.size() - 1));
  return out;
}

// Exact plans split only edges longer than this many sizes: splitting every edge above
// the size (at 1.5) lowered the Gulf's worst quad at 1M quads from 0.02-0.04 to 0.000
// (new samples beside sharp coast turns).
constexpr double kSplitEdgesLongerThan = 3.0;

// Turns a region boundary plan exact (its own vertices as samples), keeping the
// parity of its total count so that no part's boundary becomes odd.
void make_exact(CurvePlan& plan, Index before, double size) {
  // Input edges far longer than the size (the straight sides of a clipped region,
  // a coast digitised coarsely) are split evenly: as single edges they left paving a
  // boundary edge of up to 30 element sizes (Gulf of Mexico at 20M quads), which
  // folded quads that nothing could untangle.
  plan.exact = true;
  const std::size_t edges = plan.polyline.size() - 1;
  plan.edge_segments.assign(edges, 1);
  for (std::size_t i = 0; i < edges; ++i) {
    const double length = (plan.polyline[i + 1] - plan.polyline[i]).norm();
    if (length > kSplitEdgesLongerThan * size) plan.edge_segments[i] = static_cast<Index>(std::round(length / size));
  }
  Index after = 0;
  for (const Index n : plan.edge_segments) after += n;
  if ((after - before) % 2 != 0) {
    std::size_t longest = 0;  // by the length of its segments
    const auto segment_length = [&](std::size_t i) {
      return (plan.polyline[i + 1] - plan.polyline[i]).norm() / static_cast<double>(plan.edge_segments[i]);
    };
    for (std::size_t i = 1; i < edges; ++i)
      if (segment_length(i) > segment_length(longest)) longest = i;
    ++plan.edge_segments[longest];
  }
  std::vector<Index> counts;
  for (std::size_t piece = 0; piece + 1 < plan.breaks.size(); ++piece) {
    Index count = 0;
    for (std::size_t i = plan.breaks[piece]; i < plan.breaks[piece + 1]; ++i) count += plan.edge_segments[i];
    counts.push_back(count);
  }
  plan.segments = counts;
}

double orientation(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

// Segments ab and cd cross or touch, other than at a shared end point.
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  if (a == c || a == d || b == c || b == d) return false;
  const double o1 = orientation(a, b, c), o2 = orientation(a, b, d), o3 = orientation(c, d, a),
               o4 = orientation(c, d, b);
  return ((o1 <= 0 && o2 >= 0) || (o1 >= 0 && o2 <= 0)) && ((o3 <= 0 && o4 >= 0) || (o3 >= 0 && o4 <= 0)) &&
         !(o1 == 0 && o2 == 0);  // collinear overlaps of a degenerate pair are left to the meshers
}

using paving::closest_on_segment;

// Closest points (on ab, on cd) of two segments that do not meet.
std::pair<Vec2, Vec2> closest_points(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const std::array<std::pair<Vec2, Vec2>, 4> candidates{{{a, closest_on_segment(a, c, d)},
                                                         {b, closest_on_segment(b, c, d)},
                                                         {closest_on_segment(c, a, b), c},
                                                         {closest_on_segment(d, a, b), d}}};
  return *std::min_element(candidates.begin(), candidates.end(), [](const auto& x, const auto& y) {
    return (x.first - x.second).squaredNorm() < (y.first - y.second).squaredNorm();
  });
}

// The sample segments (curve, index) that meet another curve's, or their own curve's,
// away from shared ends, or (both on the region boundary) pass within `clearance` of
// each other across water while more than three times that distance apart along the
// boundary: thinning can bring the two banks of a channel together without a
// crossing, and no quad fits between samples that close. A uniform grid of cell = the
// longest segment.
std::vector<std::pair<std::size_t, std::size_t>> crossing_segments(const Partition& partition,
                                                                   const std::vector<CurvePlan>& plans,
                                                                   double clearance) {
  struct Segment {
    Vec2 a, b;
    std::size_t curve, index;
    double arc_a, arc_b;  // arc length of a and b along the curve's samples
  };
  std::vector<Segment> segments;
  std::vector<double> curve_length(plans.size());
  double longest = 0;
  BoundingBox2 box;
  for (std::size_t c = 0; c < plans.size(); ++c) {
    const std::vector<Vec2> points = sample_positions(plans[c]).points;
    double arc = 0;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
      const double length = (points[i + 1] - points[i]).norm();
      segments.push_back({points[i], points[i + 1], c, i, arc, arc + length});
      arc += length;
      longest = std::max(longest, length);
      box.extend(points[i]);
      box.extend(points[i + 1]);
    }
    curve_length[c] = arc;
  }
  // +1 where the water is on the left of a region boundary curve (its part's loop runs
  // it forwards), -1 where it is on the right.
  std::vector<double> water_left(plans.size(), 0.0);
  for (const auto& loops : partition.part_loops)
    for (const auto& loop : loops)
      for (const std::int64_t ref : loop) water_left[ref >= 0 ? ref : -ref - 1] = ref >= 0 ? 1.0 : -1.0;
  // Distance along the boundary between two segments: along their curve, or through
  // an end point the two curves share (a junction); infinite otherwise.
  const auto along = [&](const Segment& s, const Segment& t) {
    const double Ls = curve_length[s.curve], Lt = curve_length[t.curve];
    if (s.curve == t.curve) {
      const Segment& first = s.index < t.index ? s : t;
      const Segment& second = s.index < t.index ? t : s;
      const double inside = second.arc_a - first.arc_b;
      return plans[s.curve].closed ? std::min(inside, Ls - (second.arc_b - first.arc_a)) : inside;
    }
    const auto& ps = plans[s.curve].polyline;
    const auto& pt = plans[t.curve].polyline;
    double best = std::numeric_limits<double>::infinity();
    if (ps.front() == pt.front()) best = std::min(best, s.arc_a + t.arc_a);
    if (ps.front() == pt.back()) best = std::min(best, s.arc_a + Lt - t.arc_b);
    if (ps.back() == pt.front()) best = std::min(best, Ls - s.arc_b + t.arc_a);
    if (ps.back() == pt.back()) best = std::min(best, Ls - s.arc_b + Lt - t.arc_b);
    return best;
  };
  if (segments.empty() || !(longest > 0)) return {};
  // Cells of about the median segment length (at least the clearance): a cell as long
  // as the longest segment would put thousands of short coast segments in one cell and
  // test them pairwise. A segment is registered in every cell its box (grown by the
  // clearance) covers, at most 64 x 64 of them; a pair is tested in the lowest cell both
  // cover, so segments whose grown boxes are apart are never tested (a zero-length
  // segment on the line through a distant one no longer counts as meeting it).
  std::vector<double> lengths(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) lengths[i] = segments[i].arc_b - segments[i].arc_a;
  std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
  const double cell = std::max({lengths[lengths.size() / 2], clearance, longest / 64});
  const auto key = [&](double x, double y) {
    return std::pair<std::int64_t, std::int64_t>{static_cast<std::int64_t>(std::floor((x - box.min.x()) / cell)),
                                                 static_cast<std::int64_t>(std::floor((y - box.min.y()) / cell))};
  };
  std::vector<std::array<std::int64_t, 4>> cells_of(segments.size());  // x0, y0, x1, y1
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::size_t>> grid;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const auto lo = key(std::min(segments[s].a.x(), segments[s].b.x()) - clearance,
                        std::min(segments[s].a.y(), segments[s].b.y()) - clearance);
    const auto hi = key(std::max(segments[s].a.x(), segments[s].b.x()) + clearance,
                        std::max(segments[s].a.y(), segments[s].b.y()) + clearance);
    cells_of[s] = {lo.first, lo.second, hi.first, hi.second};
    for (std::int64_t x = lo.first; x <= hi.first; ++x)
      for (std::int64_t y = lo.second; y <= hi.second; ++y) grid[{x, y}].push_back(s);
  }
  std::vector<std::pair<std::size_t, std::size_t>> result;
  for (const auto& [cell_key, members] : grid)
    for (std::size_t i = 0; i < members.size(); ++i)
      for (std::size_t j = i + 1; j < members.size(); ++j) {
        const auto& ci = cells_of[members[i]];
        const auto& cj = cells_of[members[j]];
        if (cell_key.first != std::max(ci[0], cj[0]) || cell_key.second != std::max(ci[1], cj[1])) continue;
        const Segment& s = segments[members[i]];
        const Segment& t = segments[members[j]];
        if (s.curve == t.curve && (s.index + 1 == t.index || t.index + 1 == s.index)) continue;
        if (!segments_meet(s.a, s.b, t.a, t.b)) {
          const bool coast = partition.curves[s.curve].kind == PartitionCurve::Kind::Boundary &&
                             partition.curves[t.curve].kind == PartitionCurve::Kind::Boundary;
          if (!coast || s.a == t.a || s.a == t.b || s.b == t.a || s.b == t.b) continue;
          const auto [p, q] = closest_points(s.a, s.b, t.a, t.b);
          const double distance = (p - q).norm();
          if (!(distance < clearance) || !(along(s, t) > 3 * distance)) continue;
          // Thin land (an island, a spit) between them is no problem for a mesher.
          if (!(water_left[s.curve] * paving::cross(s.b - s.a, q - p) > 0 &&
                water_left[t.curve] * paving::cross(t.b - t.a, p - q) > 0))
            continue;
        }
        result.emplace_back(s.curve, s.index);
        result.emplace_back(t.curve, t.index);
      }
  std::sort(result.begin(), result.end());
  result.erase(std::unique(result.begin(), result.end()), result.end());
  return result;
}

// A separator whose samples cut a corner of its cell-edge polyline across something
// takes every polyline vertex as a break, with the same total count spread over the
// pieces by length (largest remainders; at least one each, parity kept when more
// are needed).
bool break_at_every_vertex(CurvePlan& plan, const std::vector<Index>& vertices) {
  const std::size_t pieces = plan.polyline.size() - 1;
  if (plan.breaks.size() == pieces + 1) return false;
  Index total = total_segments(plan);
  if (total < pieces) total = static_cast<Index>(pieces + (pieces - total) % 2);
  plan.breaks.resize(pieces + 1);
  std::iota(plan.breaks.begin(), plan.breaks.end(), std::size_t{0});
  plan.break_vertices = vertices;
  plan.lengths.clear();
  double length = 0;
  for (std::size_t i = 0; i < pieces; ++i) {
    plan.lengths.push_back((plan.polyline[i + 1] - plan.polyline[i]).norm());
    length += plan.lengths.back();
  }
  plan.segments.assign(pieces, 1);
  std::vector<double> share(pieces);
  for (std::size_t i = 0; i < pieces; ++i)
    share[i] = length > 0 ? plan.lengths[i] / length * static_cast<double>(total) : 1.0;
  for (Index left = total - static_cast<Index>(pieces); left > 0; --left) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < pieces; ++i)
      if (share[i] - plan.segments[i] > share[best] - plan.segments[best]) best = i;
    ++plan.segments[best];
  }
  return true;
}

// Rounding leaves some parts odd: a T-join on a BFS tree of the graph parts +
// outside (node `parts`), curves as edges; leaves first, an odd node flips the
// curve to its parent (the outside absorbs any parity).
void repair_parity(const Partition& partition, std::vector<CurvePlan>& plans, double size,
                   const std::vector<std::uint8_t>& avoid) {
  const std::size_t parts = partition.part_loops.size();
  const std::size_t curves = partition.curves.size();
  const auto part_parity = [&]() {
    std::vector<std::uint8_t> odd(parts, 0);
    for (std::size_t p = 0; p < parts; ++p)
      for (const auto& loop : partition.part_loops[p])
        for (const std::int64_t ref : loop) {
          const std::size_t c = ref >= 0 ? static_cast<std::size_t>(ref) : static_cast<std::size_t>(-ref - 1);
          odd[p] ^= static_cast<std::uint8_t>(total_segments(plans[c]) & 1U);
        }
    return odd;
  };
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> adjacent(parts + 1);  // (node, curve)
  for (std::size_t c = 0; c < curves; ++c) {
    const PartitionCurve& curve = partition.curves[c];
    const std::size_t a = curve.left_part >= 0 ? static_cast<std::size_t>(curve.left_part) : parts;
    const std::size_t b = curve.right_part >= 0 ? static_cast<std::size_t>(curve.right_part) : parts;
    if (a == b) continue;
    adjacent[a].emplace_back(b, c);
    adjacent[b].emplace_back(a, c);
  }
  // A spanning forest by 0-1 BFS: curves to avoid (those of structured parts) cost 1,
  // so the tree uses them only where nothing else connects. Nodes are finished in an
  // order where every parent precedes its children.
  constexpr std::size_t kFar = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> order, parent_curve(parts + 1, curves), parent(parts + 1, parts + 1),
      distance(parts + 1, kFar);
  std::vector<std::uint8_t> done(parts + 1, 0);
  std::deque<std::size_t> queue;
  for (std::size_t root_index = 0; root_index <= parts; ++root_index) {
    const std::size_t root = root_index == 0 ? parts : root_index - 1;
    if (distance[root] != kFar) continue;
    distance[root] = 0;
    queue.push_back(root);
    while (!queue.empty()) {
      const std::size_t node = queue.front();
      queue.pop_front();
      if (done[node]) continue;
      done[node] = 1;
      order.push_back(node);
      for (const auto& [next, curve] : adjacent[node]) {
        const std::size_t weight = avoid.empty() ? 0 : avoid[curve];
        if (done[next] || distance[node] + weight >= distance[next]) continue;
        distance[next] = distance[node] + weight;
        parent[next] = node;
        parent_curve[next] = curve;
        if (weight == 0)
          queue.push_front(next);
        else
          queue.push_back(next);
      }
    }
  }
  std::vector<std::uint8_t> odd = part_parity();
  odd.push_back(0);  // the outside has no constraint
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    const std::size_t node = *it;
    if (node == parts || !odd[node]) continue;
    if (parent[node] > parts)
      throw Error("sample_partition: part " + std::to_string(node) +
                  " has an odd boundary and no neighbour to share the parity with");
    flip_parity(plans[parent_curve[node]], size);
    odd[node] ^= 1U;
    if (parent[node] != parts) odd[parent[node]] ^= 1U;
  }
  const std::vector<std::uint8_t> check = part_parity();
  for (std::size_t p = 0; p < parts; ++p)
    if (check[p]) throw Error("sample_partition: part " + std::to_string(p) + " kept an odd boundary (internal)");
}

// Interior angle (left side) at the vertex where piece `a` of one curve ends and
// piece `b` starts, walking each piece forwards or backwards. The directions are
// chords of length min(size, half the piece), so a zigzag of the CVT separator
// right at the vertex does not decide the angle.
double interior_angle(const CurvePlan& a_plan, std::size_t a, bool a_forward, const CurvePlan& b_plan, std::size_t b,
                      bool b_forward, double size) {
  const auto along = [&](const CurvePlan& plan, std::size_t piece, bool forward, bool at_start) {
    const std::size_t from = plan.breaks[piece], to = plan.breaks[piece + 1];
    const double length = plan.lengths[piece];
    const double reach = std::min(size, 0.5 * length);
    // Arc-length position of the vertex and of the chord's other end, in forward terms.
    const bool vertex_is_from = forward == at_start;
    const double s_other = vertex_is_from ? reach : length - reach;
    const Vec2 vertex = vertex_is_from ? plan.polyline[from] : plan.polyline[to];
    const Vec2 other = point_at(plan.polyline, from, to, s_other);
    return std::pair<Vec2, Vec2>{vertex, other};
  };
  const auto [a_vertex, a_other] = along(a_plan, a, a_forward, false);
  const auto [b_vertex, b_other] = along(b_plan, b, b_forward, true);
  const Vec2 in = a_vertex - a_other, out = b_other - b_vertex;
  const double turn = std::atan2(in.x() * out.y() - in.y() * out.x(), in.dot(out));
  return std::numbers::pi - turn;
}

}  // namespace

SampledPartition sample_partition(const Partition& partition, double size, bool blocks) {
  if (!(size > 0) || !std::isfinite(size)) throw InputError("sample_partition: the element size must be positive");
  const std::size_t parts = partition.part_loops.size();
  const std::size_t curves = partition.curves.size();

  std::vector<CurvePlan> plans;
  plans.reserve(curves);
  for (const PartitionCurve& curve : partition.curves) {
    if (curve.vertices.size() < 2) throw Error("sample_partition: a partition curve has fewer than 2 vertices");
    plans.push_back(plan_curve(partition, curve, size, true));
  }

  // Edges: the pieces of the curves (region boundary curves split at corners), the
  // unknowns of the interval assignment; each part loop as a sequence of edges.
  std::vector<std::size_t> edge_offset(curves + 1, 0);
  for (std::size_t c = 0; c < curves; ++c) edge_offset[c + 1] = edge_offset[c] + plans[c].segments.size();
  const std::size_t edge_count = edge_offset[curves];
  struct LoopEdge {
    std::size_t curve, piece;
    bool forward;
  };
  std::vector<std::vector<std::vector<LoopEdge>>> loop_edges(parts);
  for (std::size_t p = 0; p < parts; ++p)
    for (const auto& loop_refs : partition.part_loops[p]) {
      std::vector<LoopEdge> loop;
      for (const std::int64_t ref : loop_refs) {
        const bool forward = ref >= 0;
        const std::size_t c = forward ? static_cast<std::size_t>(ref) : static_cast<std::size_t>(-ref - 1);
        const std::size_t pieces = plans[c].segments.size();
        for (std::size_t i = 0; i < pieces; ++i) loop.push_back({c, forward ? i : pieces - 1 - i, forward});
      }
      loop_edges[p].push_back(std::move(loop));
    }
  const auto edge_id = [&](const LoopEdge& e) { return static_cast<Index>(edge_offset[e.curve] + e.piece); };
  const auto edge_start = [](const std::vector<CurvePlan>& all, const LoopEdge& e) {
    const CurvePlan& plan = all[e.curve];
    return plan.polyline[plan.breaks[e.piece + (e.forward ? 0 : 1)]];
  };
  // The point at arc length s along the loop from the start of loop edge `first`.
  const auto side_point = [](const std::vector<CurvePlan>& all, const std::vector<LoopEdge>& loop, std::size_t first,
                             double s) {
    for (std::size_t k = first;; k = (k + 1) % loop.size()) {
      const CurvePlan& plan = all[loop[k].curve];
      const std::size_t from = plan.breaks[loop[k].piece], to = plan.breaks[loop[k].piece + 1];
      const double length = plan.lengths[loop[k].piece];
      if (s <= length || (k + 1) % loop.size() == first)
        return point_at(plan.polyline, from, to, loop[k].forward ? std::min(s, length) : length - std::min(s, length));
      s -= length;
    }
  };

  // Four-sided parts: one loop, exactly four corners (interior angle < 135°) and every
  // other break between 150° and 225°, where the part can be a structured grid.
  quad2d::IntervalProblem problem;
  problem.ideal.resize(edge_count);
  problem.minimum.assign(edge_count, 1);
  for (std::size_t c = 0; c < curves; ++c)
    for (std::size_t i = 0; i < plans[c].segments.size(); ++i) {
      problem.ideal[edge_offset[c] + i] = plans[c].lengths[i] / size;
      if (plans[c].closed && plans[c].segments.size() == 1) problem.minimum[edge_offset[c] + i] = 3;
    }
  problem.part_edges.resize(parts);
  std::vector<std::array<std::size_t, 4>> corner_edges;      // per four_sided entry: loop edge index of each corner
  std::vector<std::vector<std::size_t>> polar_corner_edges;  // per polar entry
  for (std::size_t p = 0; p < parts; ++p) {
    for (const auto& loop : loop_edges[p])
      for (const LoopEdge& e : loop) problem.part_edges[p].push_back(edge_id(e));
    if (!blocks || loop_edges[p].size() != 1 || loop_edges[p][0].size() < 3) continue;
    const std::vector<LoopEdge>& loop = loop_edges[p][0];
    // The four smallest interior angles are the corners when they are below 150°,
    // every other break is at least 100° (a side may bend) and none is reflex.
    std::vector<std::pair<double, std::size_t>> angles;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const LoopEdge& in = loop[(k + loop.size() - 1) % loop.size()];
      angles.emplace_back(interior_angle(plans[in.curve], in.piece, in.forward, plans[loop[k].curve], loop[k].piece,
                                         loop[k].forward, size),
                          k);
    }
    std::vector<std::pair<double, std::size_t>> sorted = angles;
    std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    // A part with a reflex break is paved, unless it is small enough for the polar
    // blocks' polish (the reflex break becomes a bend of a side; the polish must lift
    // every quad over the threshold, else the part is paved after all).
    const bool reflex = sorted.back().first > kSideAngleMax;
    const bool small = partition.part_areas[p] / (size * size) <= kSmallPartQuads;
    if (reflex && !small) continue;
    const bool four_sided = !reflex && sorted.size() >= 4 && sorted[3].first < kCornerAngle &&
                            (sorted.size() == 4 || sorted[4].first >= kSideAngleMin);
    // Polar blocks around a centre with the given corners (loop edge indices, in loop order).
    const auto add_polar = [&](std::vector<std::size_t> corners, double reward) {
      quad2d::IntervalProblem::Polar blocks;
      blocks.part = p;
      blocks.reward = reward;
      blocks.sides.resize(corners.size());
      // Chord lengths: from each side's arc-length midpoint to the mean of the corners.
      Vec2 centre = Vec2::Zero();
      for (const std::size_t k : corners) centre += edge_start(plans, loop[k]);
      centre /= static_cast<double>(corners.size());
      for (std::size_t i = 0; i < corners.size(); ++i) {
        double length = 0;
        for (std::size_t k = corners[i]; k != corners[(i + 1) % corners.size()]; k = (k + 1) % loop.size()) {
          blocks.sides[i].push_back(edge_id(loop[k]));
          length += plans[loop[k].curve].lengths[loop[k].piece];
        }
        blocks.chord_ideal.push_back((side_point(plans, loop, corners[i], 0.5 * length) - centre).norm() / size);
      }
      problem.polar.push_back(std::move(blocks));
      polar_corner_edges.push_back(std::move(corners));
    };
    if (!four_sided) {
      // Polar blocks: the corners are the breaks below 150°.
      std::vector<std::size_t> corners;
      for (std::size_t k = 0; k < angles.size(); ++k)
        if (angles[k].first < kCornerAngle) corners.push_back(k);
      if (corners.size() < 3 || corners.size() > kMaxPolarCorners) continue;
      add_polar(std::move(corners), reflex ? kAlternativePolarReward : kPolarReward);
      continue;
    }
    std::vector<std::size_t> corners;
    for (int i = 0; i < 4; ++i) corners.push_back(sorted[static_cast<std::size_t>(i)].second);
    std::sort(corners.begin(), corners.end());
    // The alternative of a four-sided part whose opposite sides cannot match (a
    // trapezoid, a part with one short side: lengths further apart than the counts'
    // range of 0.75..1.33 times the ideal allows): three polar blocks around a centre,
    // the most obtuse of the four corners taken as a bend of a side. One singular
    // point (valence 3) instead of the dozens paving leaves; the MILP picks at most
    // one of the two, and the block meshers' quality check still falls back to paving.
    // Parts whose grid can match get no alternative: candidates that then fail the
    // quality check would only constrain their neighbours' counts.
    std::array<double, 4> side_length{};
    for (int side = 0; side < 4; ++side)
      for (std::size_t k = corners[side]; k != corners[(side + 1) % 4]; k = (k + 1) % loop.size())
        side_length[side] += plans[loop[k].curve].lengths[loop[k].piece];
    const auto mismatch = [&](int a, int b) {
      return std::max(side_length[a], side_length[b]) > kUnmatchableRatio * std::min(side_length[a], side_length[b]);
    };
    if (mismatch(0, 2) || mismatch(1, 3)) {
      std::vector<std::size_t> polar_corners;
      for (int i = 0; i < 3; ++i) polar_corners.push_back(sorted[static_cast<std::size_t>(i)].second);
      std::sort(polar_corners.begin(), polar_corners.end());
      problem.exclusive.emplace_back(problem.four_sided.size(), problem.polar.size());
      add_polar(std::move(polar_corners), kAlternativePolarReward);
    }
    quad2d::IntervalProblem::FourSided four;
    four.part = p;
    for (int side = 0; side < 4; ++side)
      for (std::size_t k = corners[side]; k != corners[(side + 1) % 4]; k = (k + 1) % loop.size())
        four.sides[side].push_back(edge_id(loop[k]));
    problem.four_sided.push_back(std::move(four));
    corner_edges.push_back({corners[0], corners[1], corners[2], corners[3]});
  }
  // The MILP covers only the structured candidates' edges (its size follows them,
  // not the thousands of island edges of a coastline); the parity of every other
  // part is then repaired by the T-join, which avoids the candidates' curves where
  // the part graph allows, and every candidate is checked again in integers.
  quad2d::IntervalSolution assignment;
  std::vector<std::uint8_t> candidate_curve(curves, 0);
  if (!problem.four_sided.empty() || !problem.polar.empty()) {
    std::vector<Index> local(edge_count, kInvalidIndex);
    quad2d::IntervalProblem compact;
    const auto use = [&](Index e) {
      if (local[e] == kInvalidIndex) {
        local[e] = static_cast<Index>(compact.ideal.size());
        compact.ideal.push_back(problem.ideal[e]);
        compact.minimum.push_back(problem.minimum[e]);
      }
      return local[e];
    };
    const auto remap = [&](const std::vector<Index>& edges) {
      std::vector<Index> out;
      for (const Index e : edges) out.push_back(use(e));
      return out;
    };
    for (const auto& four : problem.four_sided) {
      compact.four_sided.push_back({four.part, {}});
      for (int side = 0; side < 4; ++side) compact.four_sided.back().sides[side] = remap(four.sides[side]);
      compact.part_edges.push_back(remap(problem.part_edges[four.part]));
      compact.part_ids.push_back(four.part);
    }
    for (const auto& blocks : problem.polar) {
      quad2d::IntervalProblem::Polar mapped{blocks.part, {}, blocks.chord_ideal};
      for (const auto& side : blocks.sides) mapped.sides.push_back(remap(side));
      compact.polar.push_back(std::move(mapped));
      compact.part_edges.push_back(remap(problem.part_edges[blocks.part]));
      compact.part_ids.push_back(blocks.part);
    }
    compact.exclusive = problem.exclusive;
    assignment = quad2d::solve_interval_assignment(compact);
    if (assignment.solved) {
      for (std::size_t c = 0; c < curves; ++c)
        for (std::size_t i = 0; i < plans[c].segments.size(); ++i) {
          const Index e = local[edge_offset[c] + i];
          if (e == kInvalidIndex) continue;
          plans[c].segments[i] = assignment.counts[e];
          candidate_curve[c] = 1;
        }
    }
  }
  repair_parity(partition, plans, size, candidate_curve);
  // Samples must not cross anything. A smoothed separator that does goes back to
  // its cell edges (its counts stay); a region boundary piece that does (its chords
  // cut across a strait or an island smaller than the size) takes its input
  // vertices as samples. Until nothing crosses and every hole is inside its part.
  // Input positions of each region boundary curve that its thinned samples must keep.
  std::vector<std::vector<std::uint8_t>> protect(curves);
  // follow_input(c, segments): the sample segments of curve c that cross something
  // (empty: the whole curve).
  const auto follow_input = [&](std::size_t c, const std::vector<std::size_t>& segments) {
    if (plans[c].smoothed) {
      const std::vector<Index> counts = plans[c].segments;
      plans[c] = plan_curve(partition, partition.curves[c], size, false);
      plans[c].segments = counts;
      return true;
    }
    if (partition.curves[c].kind != PartitionCurve::Kind::Boundary)
      return break_at_every_vertex(plans[c], partition.curves[c].vertices);
    const Index before = total_segments(plans[c]);
    if (!plans[c].exact) {  // first the (thinned) polyline's own vertices
      make_exact(plans[c], before, size);
      return true;
    }
    // Then every input vertex along each stretch that still crosses: from the
    // polyline vertex before the crossing segment to the one after it.
    const std::vector<std::size_t>& source = plans[c].source;
    std::vector<std::uint8_t>& mask = protect[c];
    mask.resize(partition.curves[c].vertices.size(), 0);
    bool added = false;
    const auto keep = [&](std::size_t from, std::size_t to) {
      for (std::size_t i = source[from]; i <= source[to]; ++i) {
        added = added || !mask[i];
        mask[i] = 1;
      }
    };
    if (segments.empty()) keep(0, source.size() - 1);
    // Sample segment -> polyline edge (an exact plan splits long edges).
    std::vector<std::size_t> edge_of;
    for (std::size_t i = 0; i < plans[c].edge_segments.size(); ++i)
      edge_of.insert(edge_of.end(), plans[c].edge_segments[i], i);
    for (const std::size_t segment : segments) {
      const std::size_t k = segment < edge_of.size() ? edge_of[segment] : segment;
      keep(k > 0 ? k - 1 : 0, std::min(k + 2, source.size() - 1));
    }
    if (!added) return false;
    plans[c] = plan_curve(partition, partition.curves[c], size, false, &mask);
    make_exact(plans[c], before, size);
    return true;
  };
  for (int round = 0; round < 32; ++round) {
    bool changed = false;
    const auto crossing = crossing_segments(partition, plans, kSampleClearance * size);  // sorted by curve
    for (std::size_t i = 0; i < crossing.size();) {
      const std::size_t c = crossing[i].first;
      std::vector<std::size_t> segments;
      for (; i < crossing.size() && crossing[i].first == c; ++i) segments.push_back(crossing[i].second);
      changed = follow_input(c, segments) || changed;
    }
    // An island thinned until its samples turn the other way round (a thin island
    // sampled by three points) follows its input.
    for (std::size_t c = 0; c < curves; ++c) {
      if (!plans[c].closed || partition.curves[c].kind != PartitionCurve::Kind::Boundary) continue;
      std::vector<Vec2> input;
      for (const Index v : partition.curves[c].vertices) input.push_back(partition.metric_vertices[v]);
      const double sampled = signed_area(sample_positions(plans[c]).points), wanted = signed_area(input);
      if (!(sampled * wanted > 0) || std::abs(sampled) < 0.25 * std::abs(wanted))
        changed = follow_input(c, {}) || changed;
    }
    // A hole whose samples fall outside its part's sampled outer loop (the coast's
    // chords passed on the inland side of an island): the outer loop's sample segment
    // nearest to the hole follows its input there (a smoothed separator goes back to
    // its cell edges); a curve where that changes nothing follows its input all along.
    for (std::size_t p = 0; p < parts && !changed; ++p) {
      const auto& loops = partition.part_loops[p];
      if (loops.size() < 2) continue;
      const auto curve_of = [](std::int64_t ref) {
        return ref >= 0 ? static_cast<std::size_t>(ref) : static_cast<std::size_t>(-ref - 1);
      };
      std::vector<std::vector<Vec2>> outer_curves;
      std::vector<Vec2> outer;
      for (const std::int64_t ref : loops[0]) {
        outer_curves.push_back(sample_positions(plans[curve_of(ref)]).points);
        std::vector<Vec2> points = outer_curves.back();
        if (ref < 0) std::reverse(points.begin(), points.end());
        outer.insert(outer.end(), points.begin(), points.end() - 1);
      }
      std::map<std::size_t, std::vector<std::size_t>> nearest;  // curve -> sample segments
      for (std::size_t l = 1; l < loops.size(); ++l) {
        const Vec2 hole = sample_positions(plans[curve_of(loops[l].front())]).points.front();
        if (detail::point_in_ring(outer, hole)) continue;
        double best = std::numeric_limits<double>::infinity();
        std::pair<std::size_t, std::size_t> at{0, 0};
        for (std::size_t r = 0; r < loops[0].size(); ++r)
          for (std::size_t i = 0; i + 1 < outer_curves[r].size(); ++i) {
            const double d = paving::point_segment_distance(hole, outer_curves[r][i], outer_curves[r][i + 1]);
            if (d < best) best = d, at = {curve_of(loops[0][r]), i};
          }
        nearest[at.first].push_back(at.second);
      }
      for (const auto& [c, segments] : nearest) {
        const bool moved = follow_input(c, segments);
        changed = moved || follow_input(c, {}) || changed;
      }
    }
    if (!changed) break;
  }

  if (assignment.solved) {
    // Re-check in the final counts (the parity repair or exact boundary samples may
    // have changed a candidate's curve).
    const auto count = [&](Index e) {
      const auto c =
          static_cast<std::size_t>(std::upper_bound(edge_offset.begin(), edge_offset.end(), e) - edge_offset.begin()) -
          1;
      return static_cast<std::uint64_t>(plans[c].segments[e - edge_offset[c]]);
    };
    const auto side_sum = [&](const std::vector<Index>& side) {
      std::uint64_t total = 0;
      for (const Index e : side) total += count(e);
      return total;
    };
    for (std::size_t f = 0; f < problem.four_sided.size(); ++f) {
      const auto& sides = problem.four_sided[f].sides;
      assignment.mapped[f] =
          assignment.mapped[f] && side_sum(sides[0]) == side_sum(sides[2]) && side_sum(sides[1]) == side_sum(sides[3]);
    }
    for (std::size_t q = 0; q < problem.polar.size(); ++q) {
      const auto& sides = problem.polar[q].sides;
      const std::vector<Index>& r = assignment.chord_segments[q];
      const std::size_t k = sides.size();
      for (std::size_t i = 0; i < k && assignment.polar[q]; ++i)
        assignment.polar[q] = side_sum(sides[i]) == r[(i + k - 1) % k] + r[(i + 1) % k];
    }
  }

  // A part whose four-sided grid and polar alternative both hold is a grid (no
  // singular point).
  if (assignment.solved)
    for (const auto& [f, q] : problem.exclusive)
      if (assignment.mapped[f]) assignment.polar[q] = 0;

  SampledPartition sampled;
  sampled.size = size;
  // Curve ends first, shared by every curve that ends there.
  std::vector<Index> point_of_vertex(partition.metric_vertices.size(), kInvalidIndex);
  const auto add_point = [&](const Vec2& p, bool boundary) {
    sampled.points.push_back(p);
    sampled.on_region_boundary.push_back(boundary ? 1 : 0);
    sampled.fixed.push_back(boundary ? 1 : 0);
    return static_cast<Index>(sampled.points.size() - 1);
  };
  const auto end_point = [&](Index vertex, bool boundary) {
    if (point_of_vertex[vertex] == kInvalidIndex)
      point_of_vertex[vertex] = add_point(partition.metric_vertices[vertex], boundary);
    else if (boundary)
      sampled.on_region_boundary[point_of_vertex[vertex]] = sampled.fixed[point_of_vertex[vertex]] = 1;
    return point_of_vertex[vertex];
  };
  // chains[c]: the curve's sample indices from its first to its last vertex.
  std::vector<std::vector<Index>> chains(curves);
  for (std::size_t c = 0; c < curves; ++c) {
    const PartitionCurve& curve = partition.curves[c];
    const CurvePlan& plan = plans[c];
    const bool boundary = curve.kind == PartitionCurve::Kind::Boundary;
    std::vector<Index>& chain = chains[c];
    const Samples samples = sample_positions(plan);
    for (std::size_t i = 0; i < samples.points.size(); ++i)
      chain.push_back(samples.break_of[i] >= 0
                          ? end_point(plan.break_vertices[static_cast<std::size_t>(samples.break_of[i])], boundary)
                          : add_point(samples.points[i], boundary));
  }

  sampled.part_loops.assign(parts, {});
  for (std::size_t p = 0; p < parts; ++p) {
    for (const auto& loop_refs : partition.part_loops[p]) {
      std::vector<Index> loop;
      for (const std::int64_t ref : loop_refs) {
        const bool forward = ref >= 0;
        const std::vector<Index>& chain = chains[forward ? ref : -ref - 1];
        // Each curve contributes its points but its last; the next curve starts there.
        if (forward)
          loop.insert(loop.end(), chain.begin(), chain.end() - 1);
        else
          loop.insert(loop.end(), chain.rbegin(), chain.rend() - 1);
      }
      sampled.part_loops[p].push_back(std::move(loop));
    }
  }
  // Corner positions of the parts that came out four-sided with matching sides.
  sampled.part_corners.assign(parts, {-1, -1, -1, -1});
  for (std::size_t f = 0; f < problem.four_sided.size() && assignment.solved; ++f) {
    if (!assignment.mapped[f]) continue;
    const std::size_t p = problem.four_sided[f].part;
    const std::vector<LoopEdge>& loop = loop_edges[p][0];
    std::vector<std::int64_t> start(loop.size() + 1, 0);  // loop position where each loop edge starts
    for (std::size_t k = 0; k < loop.size(); ++k)
      start[k + 1] = start[k] + plans[loop[k].curve].segments[loop[k].piece];
    for (int i = 0; i < 4; ++i) sampled.part_corners[p][i] = start[corner_edges[f][i]];
  }
  sampled.part_polar.assign(parts, {});
  for (std::size_t q = 0; q < problem.polar.size() && assignment.solved; ++q) {
    if (!assignment.polar[q]) continue;
    const std::size_t p = problem.polar[q].part;
    const std::vector<LoopEdge>& loop = loop_edges[p][0];
    std::vector<std::int64_t> start(loop.size() + 1, 0);
    for (std::size_t k = 0; k < loop.size(); ++k)
      start[k + 1] = start[k] + plans[loop[k].curve].segments[loop[k].piece];
    const std::int64_t n = start[loop.size()];
    const std::vector<Index>& r = assignment.chord_segments[q];
    const std::size_t k = r.size();
    PolarBlocks& blocks = sampled.part_polar[p];
    for (std::size_t i = 0; i < k; ++i) {
      const std::int64_t corner = start[polar_corner_edges[q][i]];
      blocks.corners.push_back(corner);
      blocks.splits.push_back((corner + r[(i + k - 1) % k]) % n);  // side i's first part has r_{i-1} segments
      blocks.chord_segments.push_back(r[i]);
    }
  }
  return sampled;
}

std::pair<Polygon2, std::vector<Index>> part_boundary(const SampledPartition& sampled, std::size_t part) {
  if (part >= sampled.part_loops.size()) throw InputError("part_boundary: no part " + std::to_string(part));
  Polygon2 polygon;
  std::vector<Index> map;
  for (const std::vector<Index>& loop : sampled.part_loops[part]) {
    std::vector<Vec2> ring;
    ring.reserve(loop.size());
    for (const Index i : loop) ring.push_back(sampled.points[i]);
    polygon.add_ring(ring);
    map.insert(map.end(), loop.begin(), loop.end());
  }
  return {std::move(polygon), std::move(map)};
}

}  // namespace structmesh
