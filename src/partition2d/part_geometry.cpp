// build_part_geometry(): from a part label per tessellation face to part polygons,
// curves and junctions (design/partition2d.md §3.1, §3.2).
//
// Everything is derived from the half-edges of the tessellation, so neighbouring
// parts share vertices by construction:
//   1. part-boundary half-edges: no twin (region boundary) or a twin in another part;
//   2. the undirected graph of those edges gives the junctions (degree != 2) and,
//      per vertex and for both sides at once, which vertices are kept;
//   3. face tracing per part chains the half-edges into rings (§3.1 step 3);
//   4. curves are the maximal chains of "canonical" half-edges (one per undirected
//      edge) between junctions, or closed loops starting at their smallest vertex;
//   5. each ring is written as signed curve references and as a Polygon2 ring.
#include "partition2d/partition_internal.hpp"

#include "structmesh/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

namespace structmesh::partition2d {

namespace {

// |cross| of the unit directions above which a degree-2 vertex is a turn and kept
// (§3.1): both neighbouring parts see the same decision because it is made per vertex.
constexpr double kTurnTolerance = 1e-9;

struct HalfEdges {
  std::vector<Index> face;    // face of each half-edge
  std::vector<Index> target;  // vertex each half-edge points to
};

HalfEdges half_edge_tables(const Tessellation& tessellation) {
  HalfEdges tables;
  const std::size_t count = tessellation.face_vertices.size();
  tables.face.resize(count);
  tables.target.resize(count);
  for (Index f = 0; f < tessellation.face_count(); ++f)
    for (Index h = tessellation.face_offsets[f]; h < tessellation.face_offsets[f + 1]; ++h) {
      tables.face[h] = f;
      tables.target[h] = tessellation.face_vertices[tessellation.next(h, f)];
    }
  return tables;
}

// Angle turned clockwise from direction `from` to direction `to`, in (0, 2π].
double clockwise_angle(const Vec2& from, const Vec2& to) {
  double angle = std::atan2(from.y(), from.x()) - std::atan2(to.y(), to.x());
  while (angle <= 0) angle += 2 * std::numbers::pi;
  while (angle > 2 * std::numbers::pi) angle -= 2 * std::numbers::pi;
  return angle;
}

}  // namespace

void build_part_geometry(const Tessellation& tessellation, std::span<const std::int32_t> face_part, std::size_t parts,
                         const Polygon2& region, const CoordinateMaps& maps, Partition& partition) {
  const std::size_t face_count = tessellation.face_count();
  const std::size_t half_edge_count = tessellation.face_vertices.size();
  const std::size_t vertex_count = tessellation.vertices.size();
  if (face_part.size() != face_count || tessellation.twin.size() != half_edge_count ||
      tessellation.input_vertex.size() != vertex_count)
    throw Error("part geometry: " + std::to_string(face_part.size()) + " face labels for " +
                std::to_string(face_count) + " faces, " + std::to_string(tessellation.twin.size()) + " twins for " +
                std::to_string(half_edge_count) + " half-edges, " + std::to_string(tessellation.input_vertex.size()) +
                " input indices for " + std::to_string(vertex_count) + " vertices");
  std::vector<std::size_t> faces_per_part(parts, 0);
  for (std::size_t f = 0; f < face_count; ++f) {
    if (face_part[f] < 0 || static_cast<std::size_t>(face_part[f]) >= parts)
      throw Error("part geometry: face " + std::to_string(f) + " has part " + std::to_string(face_part[f]) +
                  " outside [0, " + std::to_string(parts) + ")");
    ++faces_per_part[face_part[f]];
  }
  for (std::size_t p = 0; p < parts; ++p)
    if (faces_per_part[p] == 0) throw Error("part " + std::to_string(p) + " is empty");

  const HalfEdges tables = half_edge_tables(tessellation);
  const auto source = [&](Index h) { return tessellation.face_vertices[h]; };
  const auto part_of = [&](Index h) { return face_part[tables.face[h]]; };
  const auto on_region_boundary = [&](Index h) { return tessellation.twin[h] == kInvalidIndex; };

  // 1. Part-boundary half-edges; the canonical one of each undirected edge has the
  //    smaller part on its left (the only one on the region boundary), so every
  //    curve is oriented with its smaller part on the left.
  std::vector<std::uint8_t> boundary(half_edge_count, 0), canonical(half_edge_count, 0);
  for (Index h = 0; h < half_edge_count; ++h) {
    if (on_region_boundary(h)) {
      boundary[h] = canonical[h] = 1;
    } else if (part_of(tessellation.twin[h]) != part_of(h)) {
      boundary[h] = 1;
      canonical[h] = part_of(h) < part_of(tessellation.twin[h]);
    }
  }
  const auto canonical_of = [&](Index h) { return canonical[h] ? h : tessellation.twin[h]; };

  // 2. Degrees in the graph of part-boundary edges, and up to two neighbours per
  //    vertex for the turn test.
  std::vector<Index> degree(vertex_count, 0);
  std::vector<std::array<Index, 2>> neighbours(vertex_count, {kInvalidIndex, kInvalidIndex});
  const auto add_neighbour = [&](Index v, Index w) {
    if (degree[v] < 2) neighbours[v][degree[v]] = w;
    ++degree[v];
  };
  for (Index h = 0; h < half_edge_count; ++h)
    if (canonical[h]) {
      add_neighbour(source(h), tables.target[h]);
      add_neighbour(tables.target[h], source(h));
    }
  std::vector<std::uint8_t> junction(vertex_count, 0), keep(vertex_count, 0);
  for (Index v = 0; v < vertex_count; ++v) {
    if (degree[v] == 0) continue;
    junction[v] = degree[v] != 2;
    bool turn = false;
    if (degree[v] == 2) {
      const Vec2& p = tessellation.vertices[v];
      const Vec2 in = (p - tessellation.vertices[neighbours[v][0]]).normalized();
      const Vec2 out = (tessellation.vertices[neighbours[v][1]] - p).normalized();
      turn = std::abs(in.x() * out.y() - in.y() * out.x()) > kTurnTolerance || in.dot(out) < 0;
    }
    keep[v] = junction[v] || turn || tessellation.input_vertex[v] >= 0;
  }

  // 3. Face tracing: the successor of a boundary half-edge of part P is the first
  //    outgoing boundary half-edge of P clockwise from the reversed incoming one
  //    (§3.1 step 3); pieces of a part that touch only at a vertex become separate
  //    rings, while a part touching itself around a hole stays one ring.
  std::vector<Index> outgoing_offsets(vertex_count + 1, 0), outgoing;
  for (Index h = 0; h < half_edge_count; ++h)
    if (boundary[h]) ++outgoing_offsets[source(h) + 1];
  for (std::size_t v = 0; v < vertex_count; ++v) outgoing_offsets[v + 1] += outgoing_offsets[v];
  outgoing.resize(outgoing_offsets[vertex_count]);
  {
    std::vector<Index> fill(outgoing_offsets.begin(), outgoing_offsets.end() - 1);
    for (Index h = 0; h < half_edge_count; ++h)
      if (boundary[h]) outgoing[fill[source(h)]++] = h;
  }
  std::vector<Index> successor(half_edge_count, kInvalidIndex);
  for (Index h = 0; h < half_edge_count; ++h) {
    if (!boundary[h]) continue;
    const Index w = tables.target[h];
    const Vec2& at = tessellation.vertices[w];
    const Vec2 back = tessellation.vertices[source(h)] - at;
    double best_angle = 0;
    for (Index k = outgoing_offsets[w]; k < outgoing_offsets[w + 1]; ++k) {
      const Index candidate = outgoing[k];
      if (part_of(candidate) != part_of(h)) continue;
      const double angle = clockwise_angle(back, tessellation.vertices[tables.target[candidate]] - at);
      if (successor[h] == kInvalidIndex || angle < best_angle) {
        successor[h] = candidate;
        best_angle = angle;
      }
    }
    if (successor[h] == kInvalidIndex)
      throw Error("part geometry: the boundary of part " + std::to_string(part_of(h)) + " is open at vertex " +
                  std::to_string(w) + " (inconsistent twins)");
  }

  // 4. Curves as chains of canonical half-edges. At a vertex of degree 2 both edges
  //    separate the same two sides, so the successor of a canonical half-edge there
  //    is canonical too and the chain continues.
  std::vector<std::uint8_t> curve_end = junction;
  std::vector<Index> curve_offsets{0}, curve_half_edges;
  std::vector<Index> curve_of(half_edge_count, kInvalidIndex);
  const auto add_curve = [&](Index first) {
    const Index c = static_cast<Index>(curve_offsets.size() - 1);
    Index h = first;
    while (true) {
      curve_of[h] = c;
      curve_half_edges.push_back(h);
      if (curve_end[tables.target[h]]) break;
      h = successor[h];
    }
    curve_offsets.push_back(static_cast<Index>(curve_half_edges.size()));
  };
  for (Index h = 0; h < half_edge_count; ++h)
    if (canonical[h] && junction[source(h)] && curve_of[h] == kInvalidIndex) add_curve(h);
  // Closed loops without a junction start at their smallest kept vertex (the loop
  // start, not a junction). A closed polygon turns, so some vertex is kept.
  for (Index h = 0; h < half_edge_count; ++h) {
    if (!canonical[h] || curve_of[h] != kInvalidIndex) continue;
    Index start = kInvalidIndex;
    Index g = h;
    do {
      if (keep[source(g)] && (start == kInvalidIndex || source(g) < source(start))) start = g;
      g = successor[g];
    } while (g != h);
    if (start == kInvalidIndex) throw Error("part geometry: a closed boundary loop has no corner");
    curve_end[source(start)] = 1;
    add_curve(start);
  }

  // Compact vertex numbering in tessellation order.
  std::vector<Index> compact(vertex_count, kInvalidIndex);
  partition.vertices.clear();
  partition.metric_vertices.clear();
  partition.input_vertex.clear();
  partition.junction.clear();
  for (Index v = 0; v < vertex_count; ++v) {
    if (!keep[v]) continue;
    compact[v] = static_cast<Index>(partition.vertices.size());
    const Vec2 metric = maps.normalised_to_metric(tessellation.vertices[v]);
    const std::int64_t input = tessellation.input_vertex[v];
    // Input vertices bit-identical from the region (§2.0); only new ones are mapped back.
    partition.vertices.push_back(input >= 0 ? region.points[static_cast<std::size_t>(input)]
                                            : maps.metric_to_input(metric));
    partition.metric_vertices.push_back(metric);
    partition.input_vertex.push_back(input);
    partition.junction.push_back(junction[v]);
  }

  partition.curves.assign(curve_offsets.size() - 1, {});
  for (std::size_t c = 0; c + 1 < curve_offsets.size(); ++c) {
    PartitionCurve& curve = partition.curves[c];
    const Index first = curve_half_edges[curve_offsets[c]];
    curve.left_part = part_of(first);
    curve.kind = on_region_boundary(first) ? PartitionCurve::Kind::Boundary : PartitionCurve::Kind::Separator;
    curve.right_part = on_region_boundary(first) ? -1 : part_of(tessellation.twin[first]);
    curve.vertices.push_back(compact[source(first)]);
    for (Index k = curve_offsets[c]; k < curve_offsets[c + 1]; ++k) {
      const Index v = tables.target[curve_half_edges[k]];
      if (keep[v]) curve.vertices.push_back(compact[v]);
    }
    if (curve.kind != PartitionCurve::Kind::Boundary) continue;
    // The ring of a boundary curve: from any input vertex on it, else (a piece
    // between two new vertices) from the tessellation.
    for (const Index v : curve.vertices)
      if (partition.input_vertex[v] >= 0) {
        const auto it = std::upper_bound(region.ring_offsets.begin(), region.ring_offsets.end(),
                                         static_cast<Index>(partition.input_vertex[v]));
        curve.ring = static_cast<std::int32_t>(it - region.ring_offsets.begin() - 1);
        break;
      }
    if (curve.ring < 0 && first < tessellation.boundary_ring.size()) curve.ring = tessellation.boundary_ring[first];
  }

  // 5. Rings per part: trace each cycle of successors from a curve end; signed
  //    area > 0 is the outer ring (§3.1 step 4).
  partition.part_loops.assign(parts, {});
  std::vector<std::vector<std::vector<Index>>> rings(parts);
  std::vector<std::vector<double>> ring_areas(parts);
  std::vector<std::uint8_t> traced(half_edge_count, 0);
  std::vector<Vec2> metric_ring;
  for (Index h = 0; h < half_edge_count; ++h) {
    if (!boundary[h] || traced[h] || !curve_end[source(h)]) continue;
    const std::int32_t p = part_of(h);
    std::vector<std::int64_t> loop;
    std::vector<Index> ring;
    Index g = h;
    do {
      traced[g] = 1;
      const Index v = source(g);
      if (curve_end[v]) {
        const Index c = curve_of[canonical_of(g)];
        loop.push_back(canonical[g] ? static_cast<std::int64_t>(c) : -static_cast<std::int64_t>(c) - 1);
      }
      if (keep[v]) ring.push_back(compact[v]);
      g = successor[g];
    } while (g != h);
    metric_ring.clear();
    for (const Index v : ring) metric_ring.push_back(partition.metric_vertices[v]);
    ring_areas[p].push_back(signed_area(metric_ring));
    rings[p].push_back(std::move(ring));
    partition.part_loops[p].push_back(std::move(loop));
  }
  // Every cycle passes a junction or is a loop with its loop start, so nothing is
  // left over unless the twins are inconsistent.
  for (Index h = 0; h < half_edge_count; ++h)
    if (boundary[h] && !traced[h])
      throw Error("part geometry: half-edge " + std::to_string(h) + " of part " + std::to_string(part_of(h)) +
                  " lies on no boundary cycle (inconsistent twins)");

  partition.parts.assign(parts, {});
  partition.part_areas.assign(parts, 0.0);
  std::vector<Vec2> input_ring;
  for (std::size_t p = 0; p < parts; ++p) {
    const std::size_t pieces =
        std::count_if(ring_areas[p].begin(), ring_areas[p].end(), [](double a) { return a > 0; });
    if (pieces != 1)
      throw Error("part " + std::to_string(p) + " is not connected: " + std::to_string(pieces) + " pieces");
    // Loop 0 is the outer one; the holes keep their tracing order.
    const std::size_t outer = std::find_if(ring_areas[p].begin(), ring_areas[p].end(), [](double a) { return a > 0; }) -
                              ring_areas[p].begin();
    std::rotate(rings[p].begin(), rings[p].begin() + outer, rings[p].begin() + outer + 1);
    std::rotate(ring_areas[p].begin(), ring_areas[p].begin() + outer, ring_areas[p].begin() + outer + 1);
    std::rotate(partition.part_loops[p].begin(), partition.part_loops[p].begin() + outer,
                partition.part_loops[p].begin() + outer + 1);
    Polygon2& polygon = partition.parts[p];
    polygon.coordinates = region.coordinates;
    for (const auto& ring : rings[p]) {
      input_ring.clear();
      for (const Index v : ring) input_ring.push_back(partition.vertices[v]);
      polygon.add_ring(input_ring);
    }
    // Outer minus holes, in the metric plane (the holes' areas are negative).
    for (const double a : ring_areas[p]) partition.part_areas[p] += a;
  }
}

}  // namespace structmesh::partition2d
