// collapse_tiny_separators(): two junctions of a partition a hair apart (a Voronoi edge
// of almost no length between two parts) become one before the curves are sampled.
//
// Every separator gets at least one segment, so such a curve leaves both parts a
// boundary edge a few thousandths of an element long, next to a corner. No block
// layout can put a good quad there (a corner quad with that edge as a side), and
// paving works around it with dozens of singular vertices: on the Key in 32 parts the
// one such curve (0.0034 h) sat at a corner of two of the parts left to paving, and
// every layout tried on one of them polished to 0.245 (limited by that corner); the
// Gulf of Mexico in 1024 parts at 1M quads had about 200. Merging the two junctions
// moves the curves that end there by less than the threshold and leaves the two parts
// touching at a point.
#include "structmesh/quad2d.hpp"

#include <numeric>

namespace structmesh {

std::size_t collapse_tiny_separators(Partition& partition, double min_length) {
  const std::size_t curve_count = partition.curves.size();
  std::vector<std::uint8_t> on_boundary(partition.metric_vertices.size(), 0);
  for (const PartitionCurve& curve : partition.curves)
    if (curve.kind == PartitionCurve::Kind::Boundary)
      for (const Index v : curve.vertices) on_boundary[v] = 1;
  std::vector<Index> root(partition.metric_vertices.size());
  std::iota(root.begin(), root.end(), Index{0});
  const auto find = [&](Index v) {
    while (root[v] != v) v = root[v] = root[root[v]];
    return v;
  };
  // A loop of a part keeps at least three curves.
  std::vector<std::uint8_t> removed(curve_count, 0);
  const auto loop_keeps_three = [&](std::int32_t part, std::size_t c) {
    if (part < 0) return true;
    for (const auto& loop : partition.part_loops[static_cast<std::size_t>(part)]) {
      std::size_t left = 0;
      bool has = false;
      for (const std::int64_t ref : loop) {
        const auto id = static_cast<std::size_t>(ref >= 0 ? ref : -ref - 1);
        if (id == c)
          has = true;
        else if (!removed[id])
          ++left;
      }
      if (has) return left >= 3;
    }
    return true;
  };
  std::size_t collapsed = 0;
  for (std::size_t c = 0; c < curve_count; ++c) {
    const PartitionCurve& curve = partition.curves[c];
    if (curve.kind != PartitionCurve::Kind::Separator || curve.vertices.size() < 2) continue;
    const Index first = curve.vertices.front(), last = curve.vertices.back();
    if (first == last) continue;  // a closed separator (around a part inside another)
    double length = 0;
    for (std::size_t i = 1; i < curve.vertices.size() && length < min_length; ++i)
      length +=
          (partition.metric_vertices[curve.vertices[i]] - partition.metric_vertices[curve.vertices[i - 1]]).norm();
    if (!(length < min_length)) continue;
    // Both ends on the region's boundary: merging them would pinch the region.
    if (on_boundary[first] && on_boundary[last]) continue;
    if (!loop_keeps_three(curve.left_part, c) || !loop_keeps_three(curve.right_part, c)) continue;
    // The end on the boundary stays where it is (the region is not changed).
    const Index keep = find(on_boundary[last] ? last : first), drop = find(on_boundary[last] ? first : last);
    if (keep != drop) root[drop] = keep;
    removed[c] = 1;
    ++collapsed;
  }
  if (collapsed == 0) return 0;
  std::vector<std::int64_t> new_id(curve_count, -1);
  std::vector<PartitionCurve> kept;
  kept.reserve(curve_count - collapsed);
  for (std::size_t c = 0; c < curve_count; ++c) {
    if (removed[c]) continue;
    new_id[c] = static_cast<std::int64_t>(kept.size());
    PartitionCurve curve = std::move(partition.curves[c]);
    curve.vertices.front() = find(curve.vertices.front());
    curve.vertices.back() = find(curve.vertices.back());
    kept.push_back(std::move(curve));
  }
  partition.curves = std::move(kept);
  for (auto& loops : partition.part_loops)
    for (auto& loop : loops) {
      std::vector<std::int64_t> refs;
      for (const std::int64_t ref : loop) {
        const auto id = static_cast<std::size_t>(ref >= 0 ? ref : -ref - 1);
        if (new_id[id] < 0) continue;
        refs.push_back(ref >= 0 ? new_id[id] : -new_id[id] - 1);
      }
      loop = std::move(refs);
    }
  return collapsed;
}

}  // namespace structmesh
