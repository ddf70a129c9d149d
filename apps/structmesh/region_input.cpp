// Region input and partition reports shared by partition2d and quad2d.
#include "cli.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/regions.hpp"

#include <cmath>
#include <cstdio>

namespace structmesh::cli {

Polygon2 load_region(const std::string& source, std::size_t segments, const std::string& polygon_choice) {
  if (source == "key") return make_key_region(segments > 0 ? segments : 2000);
  if (source == "pipe") return make_pipe_region(segments > 0 ? segments : 4000);
  std::vector<Polygon2> polygons = read_region(source);
  if (polygons.empty()) throw InputError(source + ": no polygon in the file");
  if (polygons.size() == 1) return std::move(polygons.front());
  if (polygon_choice == "largest") {
    std::size_t best = 0;
    for (std::size_t i = 1; i < polygons.size(); ++i) {
      if (std::abs(area(polygons[i])) > std::abs(area(polygons[best]))) best = i;
    }
    return std::move(polygons[best]);
  }
  if (polygon_choice.empty()) {
    throw InputError(source + ": the file holds " + std::to_string(polygons.size()) +
                     " polygons; choose one with --polygon INDEX or --polygon largest");
  }
  std::size_t index = 0;
  try {
    index = std::stoul(polygon_choice);
  } catch (const std::exception&) {
    throw InputError("--polygon must be an index or 'largest', not '" + polygon_choice + "'");
  }
  if (index >= polygons.size()) {
    throw InputError("--polygon " + polygon_choice + ": the file holds " + std::to_string(polygons.size()) +
                     " polygons");
  }
  return std::move(polygons[index]);
}

nlohmann::json metrics_json(const Partition& partition) {
  const PartitionMetrics& m = partition.metrics;
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [name, seconds] : m.stage_seconds) stages[name] = seconds;
  return {{"parts", m.parts},
          {"workload_ratio", m.workload_ratio},
          {"separator_length", m.separator_length},
          {"compactness", m.compactness},
          {"compactness_normalized", m.compactness_normalized},
          {"angle_deviation", m.angle_deviation},
          {"corners", m.corners},
          {"corner_resolution", m.corner_resolution},
          {"angle_deviation_fine", m.angle_deviation_fine},
          {"junction_angle_deviation", m.junction_angle_deviation},
          {"junction_corners", m.junction_corners},
          {"region_area", m.region_area},
          {"area_error", m.area_error},
          {"max_components_per_part", m.max_components_per_part},
          {"components_before_repair", m.components_before_repair},
          {"cells", m.cells},
          {"graph_nodes", m.graph_nodes},
          {"graph_arcs", m.graph_arcs},
          {"cvt_energy_initial", m.cvt_energy_initial},
          {"cvt_energy_final", m.cvt_energy_final},
          {"cvt_iterations", m.cvt_iterations},
          {"cvt_stop_reason", m.cvt_stop_reason},
          {"exact_gap", m.exact_gap},
          {"stage_seconds", stages},
          {"peak_rss_mb", m.peak_rss_mb},
          {"coastline_filter", coastline_filter_json(partition.simplification)}};
}

nlohmann::json coastline_filter_json(const NarrowWaterReport& r) {
  return {{"channel_width", r.channel_width},
          {"min_island_area", r.min_island_area},
          {"changed", r.changed},
          {"islands_dropped", r.islands_dropped},
          {"island_area", r.island_area},
          {"pinch_chords", r.pinch_chords},
          {"pinch_vertices", r.pinch_vertices},
          {"closed_triangles", r.closed_triangles},
          {"closed_area", r.closed_area},
          {"pieces_dropped", r.pieces_dropped},
          {"dropped_area", r.dropped_area},
          {"tips_removed", r.tips_removed},
          {"tip_area", r.tip_area},
          {"area_before", r.area_before},
          {"area_after", r.area_after}};
}

std::string coastline_filter_summary(const NarrowWaterReport& r) {
  if (!r.changed) return {};
  char line[400];
  std::snprintf(line, sizeof line,
                "coastline filter: closed water narrower than %.4g (%.4g of %.4g area units; %zu pieces cut off), "
                "dropped %zu islands below %.4g, cut back %zu land tips (%.4g)",
                r.channel_width, r.closed_area + r.dropped_area, r.area_before, r.pieces_dropped, r.islands_dropped,
                r.min_island_area, r.tips_removed, r.tip_area);
  return line;
}

}  // namespace structmesh::cli
