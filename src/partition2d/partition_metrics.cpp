// measure_partition_geometry(): the metrics of a finished partition that follow
// from its geometry alone (design/partition2d.md §1.2-§1.4): R_W (3.2), L_S (3.3),
// R^_C (3.5) as printed and normalised, the area error, pieces per part, and the
// junction angle deviation by the chord rule of §1.4.
#include "partition2d/partition_internal.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace structmesh::partition2d {

namespace {

double polyline_length(const Partition& partition, const PartitionCurve& curve) {
  double length = 0;
  for (std::size_t i = 0; i + 1 < curve.vertices.size(); ++i)
    length += (partition.metric_vertices[curve.vertices[i + 1]] - partition.metric_vertices[curve.vertices[i]]).norm();
  return length;
}

// A curve leaving a junction: its chord direction and the part on its left
// (counter-clockwise side), -1 outside the region.
struct Spoke {
  double angle = 0;
  std::int32_t left_part = -1;
};

// The chord of §1.4: from the junction end of the curve, the point at arc length
// r = min(chord_length, half the curve's length); noisy first edges do not count.
Spoke chord_spoke(const Partition& partition, const PartitionCurve& curve, bool forwards, double curve_length,
                  double chord_length) {
  const std::size_t n = curve.vertices.size();
  const auto vertex = [&](std::size_t i) -> const Vec2& {
    return partition.metric_vertices[curve.vertices[forwards ? i : n - 1 - i]];
  };
  const double r = std::min(chord_length, 0.5 * curve_length);
  Vec2 point = vertex(n - 1);
  double walked = 0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double segment = (vertex(i + 1) - vertex(i)).norm();
    if (walked + segment >= r && segment > 0) {
      point = vertex(i) + (r - walked) / segment * (vertex(i + 1) - vertex(i));
      break;
    }
    walked += segment;
  }
  const Vec2 direction = point - vertex(0);
  return {std::atan2(direction.y(), direction.x()), forwards ? curve.left_part : curve.right_part};
}

}  // namespace

void measure_partition_geometry(Partition& partition, double region_area, double chord_length) {
  PartitionMetrics& metrics = partition.metrics;
  const std::size_t k = partition.part_areas.size();
  metrics.parts = k;
  metrics.region_area = region_area;

  double total_area = 0;
  if (k > 0) {
    const auto [smallest, largest] = std::minmax_element(partition.part_areas.begin(), partition.part_areas.end());
    metrics.workload_ratio = *largest / *smallest;  // (3.2)
    for (const double a : partition.part_areas) total_area += a;
  }
  metrics.area_error = std::abs(total_area - region_area) / region_area;

  std::vector<double> curve_length(partition.curves.size());
  double separator_length = 0;
  for (std::size_t c = 0; c < partition.curves.size(); ++c) {
    curve_length[c] = polyline_length(partition, partition.curves[c]);
    if (partition.curves[c].kind == PartitionCurve::Kind::Separator) separator_length += curve_length[c];
  }
  metrics.separator_length = separator_length;                                      // (3.3)
  metrics.compactness = separator_length / (static_cast<double>(k) * region_area);  // (3.5)
  metrics.compactness_normalized = separator_length / std::sqrt(static_cast<double>(k) * region_area);

  // Pieces per part: counter-clockwise loops (outer rings), from the metric vertices.
  std::size_t max_pieces = 0;
  std::vector<Vec2> ring;
  for (const auto& loops : partition.part_loops) {
    std::size_t pieces = 0;
    for (const auto& loop : loops) {
      ring.clear();
      for (const std::int64_t ref : loop) {
        const bool forwards = ref >= 0;
        const auto& vertices = partition.curves[forwards ? ref : -ref - 1].vertices;
        for (std::size_t i = 0; i + 1 < vertices.size(); ++i)
          ring.push_back(partition.metric_vertices[vertices[forwards ? i : vertices.size() - 1 - i]]);
      }
      pieces += signed_area(ring) > 0;
    }
    max_pieces = std::max(max_pieces, pieces);
  }
  metrics.max_components_per_part = max_pieces;

  // Junction corners (§1.4): the spokes of every junction sorted by angle; each
  // sector inside the region is one corner.
  std::vector<std::pair<Index, Spoke>> spokes;
  for (std::size_t c = 0; c < partition.curves.size(); ++c) {
    const PartitionCurve& curve = partition.curves[c];
    if (partition.junction[curve.vertices.front()])
      spokes.push_back({curve.vertices.front(), chord_spoke(partition, curve, true, curve_length[c], chord_length)});
    if (partition.junction[curve.vertices.back()])
      spokes.push_back({curve.vertices.back(), chord_spoke(partition, curve, false, curve_length[c], chord_length)});
  }
  std::sort(spokes.begin(), spokes.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second.angle < b.second.angle;
  });
  double deviation_sum = 0;
  std::size_t corners = 0;
  for (std::size_t begin = 0, end = 0; begin < spokes.size(); begin = end) {
    while (end < spokes.size() && spokes[end].first == spokes[begin].first) ++end;
    for (std::size_t s = begin; s < end; ++s) {
      if (spokes[s].second.left_part < 0) continue;  // the sector outside the region, between two boundary curves
      const bool last = s + 1 == end;
      double sector = spokes[last ? begin : s + 1].second.angle - spokes[s].second.angle;
      if (last) sector += 2 * std::numbers::pi;
      deviation_sum += angle_deviation(sector);
      ++corners;
    }
  }
  metrics.junction_corners = corners;
  metrics.junction_angle_deviation = corners == 0 ? 0.0 : deviation_sum / static_cast<double>(corners);
}

}  // namespace structmesh::partition2d
