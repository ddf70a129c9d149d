// Region input and partition reports shared by partition2d and quad2d.
#include "cli.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/regions.hpp"

#include <cmath>

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
          {"peak_rss_mb", m.peak_rss_mb}};
}

}  // namespace structmesh::cli
