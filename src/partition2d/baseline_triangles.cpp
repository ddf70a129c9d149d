// The METIS and MADD-style baselines' tessellation (design/partition2d.md §2.9), and
// the boundary ring of every region-boundary half-edge of any tessellation.
#include "partition2d/partition_internal.hpp"

#include "structmesh/error.hpp"
#include "structmesh/triangulate.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace structmesh::partition2d {

namespace {

// Twins by sorting half-edges on their unordered vertex pair.
void match_twins(Tessellation& tessellation) {
  const std::size_t half_edge_count = tessellation.face_vertices.size();
  struct Key {
    Index low, high, half_edge;
  };
  std::vector<Key> keys(half_edge_count);
  for (Index f = 0; f < tessellation.face_count(); ++f) {
    for (Index h = tessellation.face_offsets[f]; h < tessellation.face_offsets[f + 1]; ++h) {
      const Index a = tessellation.face_vertices[h], b = tessellation.face_vertices[tessellation.next(h, f)];
      keys[h] = {std::min(a, b), std::max(a, b), h};
    }
  }
  std::sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) {
    return x.low != y.low ? x.low < y.low : x.high != y.high ? x.high < y.high : x.half_edge < y.half_edge;
  });
  tessellation.twin.assign(half_edge_count, kInvalidIndex);
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    if (keys[i].low == keys[i + 1].low && keys[i].high == keys[i + 1].high) {
      tessellation.twin[keys[i].half_edge] = keys[i + 1].half_edge;
      tessellation.twin[keys[i + 1].half_edge] = keys[i].half_edge;
      ++i;
    }
  }
}

double smallest_angle_corner(const std::array<Vec2, 3>& p, int& corner) {
  double best = 10;
  for (int k = 0; k < 3; ++k) {
    const Vec2 u = p[(k + 1) % 3] - p[k], v = p[(k + 2) % 3] - p[k];
    const double angle = std::atan2(std::abs(u.x() * v.y() - u.y() * v.x()), u.dot(v));
    if (angle < best) best = angle, corner = k;
  }
  return best;
}

Index find_root(std::vector<Index>& parent, Index x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

Tessellation triangle_tessellation(const Polygon2& metric_region, const Frame& frame, std::size_t target_triangles,
                                   bool madd) {
  TriangulateOptions options;
  options.target_triangles = target_triangles;
  options.bound_size_above_floor = true;
  RegionTriangulation cdt = triangulate_region(metric_region, options);

  Tessellation tessellation;
  tessellation.vertices.resize(cdt.points.size());
  tessellation.input_vertex.resize(cdt.points.size());
  for (std::size_t i = 0; i < cdt.points.size(); ++i) {
    tessellation.vertices[i] = frame.to_normalised(cdt.points[i]);
    tessellation.input_vertex[i] = i < metric_region.points.size() ? static_cast<std::int64_t>(i) : -1;
  }
  const std::size_t triangles = cdt.triangles.size();
  tessellation.face_offsets.resize(triangles + 1);
  tessellation.face_vertices.resize(3 * triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    tessellation.face_offsets[t + 1] = static_cast<Index>(3 * (t + 1));
    std::copy(cdt.triangles[t].begin(), cdt.triangles[t].end(), tessellation.face_vertices.begin() + 3 * t);
  }
  tessellation.face_cell.resize(triangles);
  std::iota(tessellation.face_cell.begin(), tessellation.face_cell.end(), Index{0});
  match_twins(tessellation);
  if (madd) {
    // MADD-style merging (§3.1.1, as the dissertation describes it; not
    // Linardakis-Chrisochoides' medial-axis algorithm): sliver-ish triangles are
    // glued to the neighbour across their shortest edge, which is the edge
    // opposite the small angle.
    constexpr double kSmallAngle = 30.0 * 3.14159265358979323846 / 180.0;
    constexpr Index kMaxGroup = 4;
    std::vector<double> smallest(triangles);
    std::vector<int> corner(triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
      std::array<Vec2, 3> p;
      for (int k = 0; k < 3; ++k) p[k] = tessellation.vertices[cdt.triangles[t][k]];
      smallest[t] = smallest_angle_corner(p, corner[t]);
    }
    std::vector<Index> order(triangles);
    std::iota(order.begin(), order.end(), Index{0});
    std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return smallest[a] < smallest[b]; });
    std::vector<Index> parent(triangles), size(triangles, 1);
    std::iota(parent.begin(), parent.end(), Index{0});
    for (const Index t : order) {
      if (smallest[t] >= kSmallAngle) break;
      if (size[find_root(parent, t)] > 1) continue;  // already merged
      // The edge opposite corner c is half-edge (c + 1) % 3 of the face.
      const Index half_edge = 3 * t + static_cast<Index>((corner[t] + 1) % 3);
      const Index twin = tessellation.twin[half_edge];
      if (twin == kInvalidIndex) continue;  // region boundary: nothing to merge with
      const Index a = find_root(parent, t), b = find_root(parent, twin / 3);
      if (a == b || size[a] + size[b] > kMaxGroup) continue;
      parent[a] = b;
      size[b] += size[a];
    }
    // Groups numbered by their first triangle (deterministic).
    std::vector<Index> group(triangles, kInvalidIndex);
    Index groups = 0;
    for (std::size_t t = 0; t < triangles; ++t) {
      const Index root = find_root(parent, static_cast<Index>(t));
      if (group[root] == kInvalidIndex) group[root] = groups++;
      tessellation.face_cell[t] = group[root];
    }
    tessellation.cell_count = groups;
  } else {
    tessellation.cell_count = triangles;
  }
  assign_boundary_rings(tessellation, metric_region);
  return tessellation;
}

void assign_boundary_rings(Tessellation& tessellation, const Polygon2& region) {
  const std::size_t half_edge_count = tessellation.face_vertices.size();
  tessellation.boundary_ring.assign(half_edge_count, -1);
  const auto ring_of = [&](Index vertex) -> std::int32_t {
    const std::int64_t input = tessellation.input_vertex[vertex];
    if (input < 0) return -1;
    const auto it = std::upper_bound(region.ring_offsets.begin(), region.ring_offsets.end(), static_cast<Index>(input));
    return static_cast<std::int32_t>(it - region.ring_offsets.begin()) - 1;
  };
  // Each boundary vertex has exactly one outgoing boundary half-edge (rings
  // neither touch nor cross), so the boundary can be walked forwards.
  std::vector<Index> outgoing(tessellation.vertices.size(), kInvalidIndex);
  std::vector<Index> head(half_edge_count, kInvalidIndex);
  std::vector<Index> unknown;
  for (Index f = 0; f < tessellation.face_count(); ++f) {
    for (Index h = tessellation.face_offsets[f]; h < tessellation.face_offsets[f + 1]; ++h) {
      if (tessellation.twin[h] != kInvalidIndex) continue;
      const Index a = tessellation.face_vertices[h];
      head[h] = tessellation.face_vertices[tessellation.next(h, f)];
      outgoing[a] = h;
      std::int32_t ring = ring_of(a);
      if (ring < 0) ring = ring_of(head[h]);
      tessellation.boundary_ring[h] = ring;
      if (ring < 0) unknown.push_back(h);
    }
  }
  for (const Index start : unknown) {
    Index h = start;
    std::size_t steps = 0;
    while (tessellation.boundary_ring[h] < 0) {
      h = outgoing[head[h]];
      if (h == kInvalidIndex || ++steps > half_edge_count) {
        throw Error("assign_boundary_rings: a boundary loop without input vertices");
      }
    }
    tessellation.boundary_ring[start] = tessellation.boundary_ring[h];
  }
}

}  // namespace structmesh::partition2d
