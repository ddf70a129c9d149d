// remove_narrow_water(): closes the water a mesh of the chosen element size cannot
// hold (channels, passes and inlets much narrower than an element) and drops islands
// smaller than an element, before partitioning (§3.3 meshes at a uniform size).
//
// Coastlines at 10 m "resolution" carry marsh creeks and passes a tenth of an element
// wide. With boundary samples an element apart on both banks, no quad fits across
// such a channel without folding, and paving fails there (§3.3.1 keeps boundary points
// fixed). Coastal ocean modellers filter the coastline to the mesh resolution for the
// same reason; this is the filter, on the constrained Delaunay triangulation of the
// region without Steiner points:
//   - a pinch chord is a triangulation edge inside the water, shorter than the channel
//     width, whose endpoints lie on different rings or far apart along their ring
//     (more than three chord lengths): it spans a channel, not a bend of one bank;
//   - pinch chords are walls; the triangles they cut into pieces smaller than half an
//     element's area (channel slivers, the pieces of a narrow creek) are closed;
//   - a vertex where the water left over meets itself at a point is opened by closing
//     the smaller fans around it, so the result is a manifold region;
//   - of the remaining water only the largest edge-connected piece is kept (water cut
//     off behind a closed pass, e.g. a lagoon, is reported with its area).
// Every kept vertex is an input vertex, so the result follows the input coastline
// exactly except across closed channels. Hand-written because no Debian library
// filters a polygon by local width: CGAL's offsets (straight skeleton) would also
// move every coast by the width, which the solver of §3.3.2 does not want.
#include "structmesh/partition2d.hpp"
#include "structmesh/triangulate.hpp"

#include "structmesh/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <tuple>
#include <vector>

namespace structmesh {

namespace {

double triangle_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return 0.5 * ((b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x()));
}

// Neighbour of every triangle across each of its edges (edge e runs from corner e to
// corner e + 1), kInvalidIndex on the boundary; built by sorting the directed edges.
std::vector<std::array<Index, 3>> triangle_neighbours(const std::vector<std::array<Index, 3>>& triangles) {
  struct HalfEdge {
    Index low, high, triangle;
    std::uint8_t edge;
  };
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(3 * triangles.size());
  for (Index t = 0; t < triangles.size(); ++t)
    for (std::uint8_t e = 0; e < 3; ++e) {
      const Index a = triangles[t][e], b = triangles[t][(e + 1) % 3];
      half_edges.push_back({std::min(a, b), std::max(a, b), t, e});
    }
  std::sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return std::tie(x.low, x.high, x.triangle) < std::tie(y.low, y.high, y.triangle);
  });
  std::vector<std::array<Index, 3>> neighbours(triangles.size(), {kInvalidIndex, kInvalidIndex, kInvalidIndex});
  for (std::size_t i = 0; i + 1 < half_edges.size(); ++i) {
    const HalfEdge& x = half_edges[i];
    const HalfEdge& y = half_edges[i + 1];
    if (x.low != y.low || x.high != y.high) continue;
    neighbours[x.triangle][x.edge] = y.triangle;
    neighbours[y.triangle][y.edge] = x.triangle;
    ++i;
  }
  return neighbours;
}

// Union-find over triangles, path halving.
constexpr int kMaxRounds = 8;

Index find_root(std::vector<Index>& parent, Index t) {
  while (parent[t] != t) {
    parent[t] = parent[parent[t]];
    t = parent[t];
  }
  return t;
}

// One pass of the filter on `polygon`: its water rings (indices into polygon.points,
// water on the left, outer ring first) and the pinch chords left with water on both
// sides (gaps at a point, e.g. an island's tip next to the shore).
struct FilterPass {
  std::vector<std::vector<Index>> rings;
  std::vector<std::array<Index, 2>> gaps;
};

FilterPass close_narrow_water(const Polygon2& polygon, double channel_width, NarrowWaterReport& report) {
  const RegionTriangulation triangulation = triangulate_region(polygon);
  const auto& P = triangulation.points;
  const auto& T = triangulation.triangles;
  const auto neighbours = triangle_neighbours(T);

  // Position of every vertex along its ring, for the "far apart along the ring" test.
  std::vector<Index> ring_of(polygon.points.size());
  std::vector<double> arc(polygon.points.size()), ring_length(polygon.ring_count());
  for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
    double s = 0;
    const Index begin = polygon.ring_offsets[r], end = polygon.ring_offsets[r + 1];
    for (Index i = begin; i < end; ++i) {
      ring_of[i] = static_cast<Index>(r);
      arc[i] = s;
      s += (P[i + 1 == end ? begin : i + 1] - P[i]).norm();
    }
    ring_length[r] = s;
  }
  // Are a and b more than three times `distance` apart along the boundary (on different
  // rings: always)?
  const auto far_along = [&](Index a, Index b, double distance) {
    if (ring_of[a] != ring_of[b]) return true;
    const double along = std::abs(arc[a] - arc[b]);
    return std::min(along, ring_length[ring_of[a]] - along) > 3 * distance;
  };
  const auto pinch_chord = [&](Index a, Index b) {
    const double length = (P[a] - P[b]).norm();
    return length < channel_width && far_along(a, b, length);
  };

  // Pieces of water between pinch chords; small ones are closed.
  std::vector<Index> parent(T.size());
  std::iota(parent.begin(), parent.end(), Index{0});
  std::vector<std::uint8_t> wall(3 * T.size(), 0);
  std::size_t walls = 0;
  for (Index t = 0; t < T.size(); ++t)
    for (int e = 0; e < 3; ++e) {
      const Index n = neighbours[t][e];
      if (n == kInvalidIndex) continue;
      if (pinch_chord(T[t][e], T[t][(e + 1) % 3])) {
        wall[3 * t + e] = 1;
        ++walls;
      } else if (n > t) {
        parent[find_root(parent, t)] = find_root(parent, n);
      }
    }
  report.pinch_chords = std::max(report.pinch_chords, walls / 2);  // the first round has the most
  std::vector<double> piece_area(T.size(), 0.0);
  std::vector<double> tri_area(T.size());
  for (Index t = 0; t < T.size(); ++t) {
    tri_area[t] = triangle_area(P[T[t][0]], P[T[t][1]], P[T[t][2]]);
    piece_area[find_root(parent, t)] += tri_area[t];
  }
  // A piece smaller than half of a (1.5 w)^2 square is a sliver of a channel.
  const double small_piece = 0.5 * 2.25 * channel_width * channel_width;
  std::vector<std::uint8_t> water(T.size(), 1);
  if (walls > 0)
    for (Index t = 0; t < T.size(); ++t)
      if (piece_area[find_root(parent, t)] < small_piece) {
        water[t] = 0;
        ++report.closed_triangles;
        report.closed_area += tri_area[t];
      }
  // A spike of water: a triangle on a boundary edge whose third vertex lies within the
  // width of that edge but far from it along the boundary (a creek whose banks are one
  // long segment and a few short ones; no chord is short there, only the altitude).
  for (Index t = 0; t < T.size(); ++t) {
    if (!water[t]) continue;
    for (int e = 0; e < 3; ++e) {
      if (neighbours[t][e] != kInvalidIndex) continue;
      const Index a = T[t][e], b = T[t][(e + 1) % 3], c = T[t][(e + 2) % 3];
      const Vec2 ab = P[b] - P[a];
      const double along_ab = (P[c] - P[a]).dot(ab);
      if (!(along_ab > 0 && along_ab < ab.squaredNorm())) continue;  // c projects outside the edge
      const double height = 2 * std::abs(tri_area[t]) / ab.norm();
      if (!(height < channel_width) || !far_along(c, a, height) || !far_along(c, b, height)) continue;
      water[t] = 0;
      ++report.closed_triangles;
      report.closed_area += tri_area[t];
      break;
    }
  }

  // Open every vertex where the water meets itself at a point: keep the fan of largest
  // area around it, close the others; closing can pinch a neighbour, so repeat.
  std::vector<Index> first_triangle(P.size() + 1, 0), vertex_triangles(3 * T.size());
  for (const auto& tri : T)
    for (const Index v : tri) ++first_triangle[v + 1];
  std::partial_sum(first_triangle.begin(), first_triangle.end(), first_triangle.begin());
  {
    std::vector<Index> fill(first_triangle.begin(), first_triangle.end() - 1);
    for (Index t = 0; t < T.size(); ++t)
      for (const Index v : T[t]) vertex_triangles[fill[v]++] = t;
  }
  std::vector<Index> queue(P.size());
  std::iota(queue.begin(), queue.end(), Index{0});
  std::vector<std::uint8_t> queued(P.size(), 1);
  std::vector<Index> fan_of;
  std::vector<double> fan_area;
  std::vector<std::size_t> stack;
  while (!queue.empty()) {
    const Index v = queue.back();
    queue.pop_back();
    queued[v] = 0;
    const std::span<const Index> around(vertex_triangles.data() + first_triangle[v],
                                        first_triangle[v + 1] - first_triangle[v]);
    fan_of.assign(around.size(), kInvalidIndex);
    fan_area.clear();
    Index fans = 0;
    for (std::size_t i = 0; i < around.size(); ++i) {
      if (!water[around[i]] || fan_of[i] != kInvalidIndex) continue;
      // Flood the fan through water neighbours that also touch v.
      stack.assign(1, i);
      fan_of[i] = fans;
      fan_area.push_back(0);
      while (!stack.empty()) {
        const std::size_t j = stack.back();
        stack.pop_back();
        const Index t = around[j];
        fan_area[fans] += tri_area[t];
        for (const Index n : neighbours[t]) {
          if (n == kInvalidIndex || !water[n]) continue;
          const auto it = std::find(around.begin(), around.end(), n);
          if (it == around.end()) continue;
          const auto k = static_cast<std::size_t>(it - around.begin());
          if (fan_of[k] != kInvalidIndex) continue;
          fan_of[k] = fans;
          stack.push_back(k);
        }
      }
      ++fans;
    }
    if (fans < 2) continue;
    const auto largest = static_cast<Index>(std::max_element(fan_area.begin(), fan_area.end()) - fan_area.begin());
    ++report.pinch_vertices;
    for (std::size_t i = 0; i < around.size(); ++i) {
      if (fan_of[i] == kInvalidIndex || fan_of[i] == largest) continue;
      const Index t = around[i];
      water[t] = 0;
      ++report.closed_triangles;
      report.closed_area += tri_area[t];
      for (const Index w : T[t])
        if (!queued[w]) {
          queued[w] = 1;
          queue.push_back(w);
        }
    }
  }

  // Keep the largest edge-connected piece of water.
  std::iota(parent.begin(), parent.end(), Index{0});
  for (Index t = 0; t < T.size(); ++t)
    if (water[t])
      for (const Index n : neighbours[t])
        if (n != kInvalidIndex && n > t && water[n]) parent[find_root(parent, t)] = find_root(parent, n);
  std::fill(piece_area.begin(), piece_area.end(), 0.0);
  for (Index t = 0; t < T.size(); ++t)
    if (water[t]) piece_area[find_root(parent, t)] += tri_area[t];
  const auto main_piece =
      static_cast<Index>(std::max_element(piece_area.begin(), piece_area.end()) - piece_area.begin());
  if (!(piece_area[main_piece] > 0)) throw InputError("remove_narrow_water: no water is wider than the channel width");
  for (Index t = 0; t < T.size(); ++t) {
    if (!water[t]) continue;
    const Index root = find_root(parent, t);
    if (root == main_piece) continue;
    if (root == t) ++report.pieces_dropped;
    water[t] = 0;
    report.dropped_area += tri_area[t];
  }

  FilterPass pass;
  // Boundary of the kept water: every triangle edge whose far side is not kept, with
  // the water on its left (triangles are counter-clockwise). No vertex is pinched, so
  // each vertex starts at most one boundary edge and the edges chain into rings.
  std::vector<Index> next_of(P.size(), kInvalidIndex);
  for (Index t = 0; t < T.size(); ++t) {
    if (!water[t]) continue;
    for (int e = 0; e < 3; ++e) {
      const Index n = neighbours[t][e];
      const Index a = T[t][e], b = T[t][(e + 1) % 3];
      if (n != kInvalidIndex && water[n]) {
        if (n > t && pinch_chord(a, b)) pass.gaps.push_back({a, b});
        continue;
      }
      if (next_of[a] != kInvalidIndex) throw Error("remove_narrow_water: the kept water is pinched at a vertex");
      next_of[a] = b;
    }
  }
  std::vector<std::uint8_t> used(P.size(), 0);
  for (Index start = 0; start < P.size(); ++start) {
    if (next_of[start] == kInvalidIndex || used[start]) continue;
    std::vector<Index> ring;
    for (Index v = start; !used[v]; v = next_of[v]) {
      used[v] = 1;
      ring.push_back(v);
      if (next_of[v] == kInvalidIndex) throw Error("remove_narrow_water: an open boundary chain");
    }
    pass.rings.push_back(std::move(ring));
  }
  // The outer ring (the only counter-clockwise one, so the largest signed area) first.
  std::vector<double> ring_area(pass.rings.size());
  std::vector<Vec2> points;
  for (std::size_t r = 0; r < pass.rings.size(); ++r) {
    points.clear();
    for (const Index v : pass.rings[r]) points.push_back(P[v]);
    ring_area[r] = signed_area(points);
  }
  const auto outer = std::max_element(ring_area.begin(), ring_area.end()) - ring_area.begin();
  std::rotate(pass.rings.begin(), pass.rings.begin() + outer, pass.rings.begin() + outer + 1);
  return pass;
}

bool point_in_triangle(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  const double d1 = triangle_area(a, b, p), d2 = triangle_area(b, c, p), d3 = triangle_area(c, a, p);
  const bool some_negative = std::min({d1, d2, d3}) < 0;
  const bool some_positive = std::max({d1, d2, d3}) > 0;
  return !(some_negative && some_positive);
}

// Removes the tip vertices at gaps: an endpoint of a gap chord where its ring turns
// towards the land (the water around it spans more than 180°) is dropped when no other
// vertex lies in the triangle it cuts off, so the land gives way by that triangle and
// the gap widens. At most one vertex per ring neighbourhood per round. Returns the
// number removed.
std::size_t remove_gap_tips(const std::vector<Vec2>& points, std::vector<std::vector<Index>>& rings,
                            const std::vector<std::array<Index, 2>>& gaps, NarrowWaterReport& report) {
  if (gaps.empty()) return 0;
  // Ring and position of every vertex in use, and a uniform grid of them.
  std::vector<Index> ring_of(points.size(), kInvalidIndex), position(points.size(), 0);
  BoundingBox2 box;
  std::size_t count = 0;
  for (Index r = 0; r < rings.size(); ++r)
    for (Index i = 0; i < rings[r].size(); ++i) {
      ring_of[rings[r][i]] = r;
      position[rings[r][i]] = i;
      box.extend(points[rings[r][i]]);
      ++count;
    }
  const double extent = std::max(box.max.x() - box.min.x(), box.max.y() - box.min.y());
  const auto cells = static_cast<std::int64_t>(std::clamp(std::sqrt(static_cast<double>(count)), 1.0, 4096.0));
  const double cell = extent > 0 ? extent / static_cast<double>(cells) * (1 + 1e-9) : 1.0;
  const auto cell_of = [&](double x, double y) {
    return std::pair<std::int64_t, std::int64_t>{
        std::clamp(static_cast<std::int64_t>((x - box.min.x()) / cell), std::int64_t{0}, cells - 1),
        std::clamp(static_cast<std::int64_t>((y - box.min.y()) / cell), std::int64_t{0}, cells - 1)};
  };
  std::vector<std::uint32_t> first(static_cast<std::size_t>(cells * cells) + 1, 0), members(count);
  for (const auto& ring : rings)
    for (const Index v : ring) {
      const auto [x, y] = cell_of(points[v].x(), points[v].y());
      ++first[static_cast<std::size_t>(y * cells + x) + 1];
    }
  std::partial_sum(first.begin(), first.end(), first.begin());
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (const auto& ring : rings)
      for (const Index v : ring) {
        const auto [x, y] = cell_of(points[v].x(), points[v].y());
        members[fill[static_cast<std::size_t>(y * cells + x)]++] = v;
      }
  }
  std::vector<std::uint8_t> removed(points.size(), 0), touched(points.size(), 0);
  std::size_t tips = 0;
  for (const auto& gap : gaps)
    for (const Index v : gap) {
      if (ring_of[v] == kInvalidIndex || touched[v]) continue;
      auto& ring = rings[ring_of[v]];
      if (ring.size() <= 3) continue;
      const Index i = position[v];
      const Index prev = ring[(i + ring.size() - 1) % ring.size()], next = ring[(i + 1) % ring.size()];
      if (touched[prev] || touched[next]) continue;
      const double turn = triangle_area(points[prev], points[v], points[next]);
      if (!(turn < 0)) continue;  // water on the left: a right turn is a tip of land
      const Vec2 &a = points[prev], &b = points[v], &c = points[next];
      const auto lo = cell_of(std::min({a.x(), b.x(), c.x()}), std::min({a.y(), b.y(), c.y()}));
      const auto hi = cell_of(std::max({a.x(), b.x(), c.x()}), std::max({a.y(), b.y(), c.y()}));
      bool blocked = false;
      for (std::int64_t y = lo.second; y <= hi.second && !blocked; ++y)
        for (std::int64_t x = lo.first; x <= hi.first && !blocked; ++x) {
          const std::size_t k = static_cast<std::size_t>(y * cells + x);
          for (std::uint32_t m = first[k]; m < first[k + 1] && !blocked; ++m) {
            const Index w = members[m];
            blocked = w != prev && w != v && w != next && !removed[w] && point_in_triangle(points[w], a, b, c);
          }
        }
      if (blocked) continue;
      removed[v] = 1;
      touched[v] = touched[prev] = touched[next] = 1;
      ++tips;
      report.tip_area += -turn;
    }
  if (tips == 0) return 0;
  for (auto& ring : rings) std::erase_if(ring, [&](Index v) { return removed[v] != 0; });
  report.tips_removed += tips;
  return tips;
}

}  // namespace

NarrowWaterResult remove_narrow_water(const Polygon2& region, double channel_width, double min_island_area) {
  NarrowWaterResult result;
  NarrowWaterReport& report = result.report;
  report.channel_width = channel_width;
  report.min_island_area = min_island_area;
  report.area_before = std::abs(area(region));

  // Islands below the area threshold go first: they would only add tiny rings.
  std::vector<std::vector<Index>> rings;
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const auto ring = region.ring(r);
    const double ring_area = std::abs(signed_area(ring));
    if (r > 0 && ring_area < min_island_area) {
      ++report.islands_dropped;
      report.island_area += ring_area;
      continue;
    }
    rings.emplace_back(region.ring_offsets[r + 1] - region.ring_offsets[r]);
    std::iota(rings.back().begin(), rings.back().end(), region.ring_offsets[r]);
  }
  bool changed = report.islands_dropped > 0;
  if (channel_width > 0) {
    // Close the narrow water and widen the gaps at tips, again while either changes
    // something (closing a spike can expose the next one; each tip widens a gap by one
    // input vertex), for a few rounds.
    for (int round = 0; round < kMaxRounds; ++round) {
      const Polygon2 polygon = select_rings(region, rings);
      std::vector<Index> to_input;
      for (const auto& ring : rings) to_input.insert(to_input.end(), ring.begin(), ring.end());
      FilterPass pass = close_narrow_water(polygon, channel_width, report);
      std::size_t total = 0;
      for (auto& ring : pass.rings) {
        total += ring.size();
        for (Index& v : ring) v = to_input[v];
      }
      for (auto& gap : pass.gaps)
        for (Index& v : gap) v = to_input[v];
      const bool closed = total != polygon.points.size() || pass.rings.size() != rings.size();
      changed = changed || closed;
      rings = std::move(pass.rings);
      const std::size_t tips = remove_gap_tips(region.points, rings, pass.gaps, report);
      changed = changed || tips > 0;
      if (!closed && tips == 0) break;
    }
  }
  report.changed = changed;
  if (!changed) {
    result.region = region;
    result.rings.clear();
    for (std::size_t r = 0; r < region.ring_count(); ++r) {
      std::vector<Index> ring(region.ring_offsets[r + 1] - region.ring_offsets[r]);
      std::iota(ring.begin(), ring.end(), region.ring_offsets[r]);
      result.rings.push_back(std::move(ring));
    }
  } else {
    // Every ring starts at its smallest input index: deterministic and close to the input order.
    for (auto& ring : rings) std::rotate(ring.begin(), std::min_element(ring.begin(), ring.end()), ring.end());
    result.rings = std::move(rings);
    result.region = select_rings(region, result.rings);
  }
  report.area_after = std::abs(area(result.region));
  return result;
}

Polygon2 select_rings(const Polygon2& region, const std::vector<std::vector<Index>>& rings) {
  Polygon2 out;
  out.coordinates = region.coordinates;
  for (const auto& ring : rings) {
    std::vector<Vec2> pts;
    pts.reserve(ring.size());
    for (const Index v : ring) pts.push_back(region.points[v]);
    out.add_ring(pts);
  }
  return out;
}

}  // namespace structmesh
