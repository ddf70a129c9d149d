// structmesh partition2d REGION|key|pipe --parts K: geometry-aware partitioning of a
// planar region (dissertation §3.2). Parse, call partition_region, report.
#include "cli.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/partition2d.hpp"
#include "structmesh/regions.hpp"

#include <cmath>
#include <cstdio>
#include <memory>

namespace structmesh::cli {

Action add_partition2d_command(CLI::App& command, const GlobalOptions& global) {
  struct Settings {
    std::string source;
    std::size_t segments = 0;
    std::string polygon;
    std::string method = "cvtgp";
    PartitionOptions options;
    std::vector<std::string> outputs;
  };
  auto settings = std::make_shared<Settings>();
  PartitionOptions& o = settings->options;
  command.add_option("REGION", settings->source, "Region file (.geojson, .poly), or the built-in key or pipe")
      ->required();
  command.add_option("-k,--parts", o.parts, "Number of parts")->required()->check(CLI::PositiveNumber);
  command.add_option("--method", settings->method, "cvtgp (default), cvt, metis, madd or exact")
      ->check(CLI::IsMember({"cvtgp", "cvt", "metis", "madd", "exact"}));
  command
      .add_option("--cells", o.cells,
                  "CVT cells (cvtgp, exact) or fine triangles (metis, madd); raised to 24 per part "
                  "unless --exact-cells")
      ->capture_default_str();
  command.add_flag("--exact-cells", o.exact_cells, "Use --cells as given");
  command.add_option("--p", o.p, "Exponent of the L_p-CVT energy (even, eq. 3.12)")->capture_default_str();
  command.add_option("--imbalance", o.imbalance, "Balance tolerance: R_W <= 1 + imbalance")->capture_default_str();
  command.add_option("--angle-weight", o.angle_weight, "Weight of the separator angle term (eq. 3.7)")
      ->capture_default_str();
  command.add_flag("!--no-boundary-corners", o.boundary_corners,
                   "Leave separator/boundary corners out of the objective (the dissertation's exact J)");
  command.add_option("--cvt-iterations", o.cvt_max_iterations, "L-BFGS iterations")->capture_default_str();
  command
      .add_option("--time-limit", o.exact_time_limit,
                  "Seconds for --method exact (whole run; CVT-GP bisections kept where the MILP runs out of time)")
      ->capture_default_str();
  command.add_flag("!--no-proxy", o.proxy_domain, "Optimise the CVT on the full boundary, never a simplified one");
  command.add_option("--seed", o.seed, "Seed (jitter of the initial sites, METIS)")->capture_default_str();
  command.add_option("--segments", settings->segments, "Boundary segments of the built-in key or pipe")
      ->check(CLI::Range(std::size_t{16}, std::size_t{200'000'000}));
  command.add_option("--polygon", settings->polygon, "Which polygon of a multi-polygon file: INDEX or largest");
  command.add_option("-o,--output", settings->outputs,
                     "Outputs: .geojson (parts, separators), .svg, .png (repeatable)");

  return [&global, settings]() {
    PartitionOptions options = settings->options;
    options.method = parse_method(settings->method);
    options.progress = global.progress;
    for (const std::string& output : settings->outputs) {
      const FileFormat format = format_from_path(output);
      if (format != FileFormat::GeoJson && format != FileFormat::Svg && format != FileFormat::Png) {
        throw InputError(output + ": partition2d writes .geojson, .svg or .png");
      }
    }
    const Polygon2 region = load_region(settings->source, settings->segments, settings->polygon);
    const Partition partition = partition_region(region, options);
    const PartitionMetrics& m = partition.metrics;

    if (!partition.projection.empty()) say(global, "lon/lat input projected to " + partition.projection);
    char line[256];
    std::snprintf(line, sizeof line, "%zu parts (%s, %zu cells, %zu graph nodes)", m.parts, method_name(options.method),
                  m.cells, m.graph_nodes);
    say(global, line);
    std::snprintf(line, sizeof line, "  R_W (3.2)             %.4f", m.workload_ratio);
    say(global, line);
    std::snprintf(line, sizeof line, "  R_C (3.5)             %.6g   (normalised L_S/sqrt(k A) %.4f)", m.compactness,
                  m.compactness_normalized);
    say(global, line);
    std::snprintf(line, sizeof line, "  separator length      %.6g", m.separator_length);
    say(global, line);
    std::snprintf(line, sizeof line,
                  "  angle deviation (3.8) %.4f rad over %zu corners (edges < %.2g cells contracted;"
                  " %.4f at 1e-3)",
                  m.angle_deviation, m.corners, m.corner_resolution, m.angle_deviation_fine);
    say(global, line);
    std::snprintf(line, sizeof line, "  at junctions          %.4f rad over %zu corners", m.junction_angle_deviation,
                  m.junction_corners);
    say(global, line);
    std::snprintf(line, sizeof line, "  area error            %.3g, components per part %zu (before repair %zu)",
                  m.area_error, m.max_components_per_part, m.components_before_repair);
    say(global, line);
    double total = 0;
    std::string stages;
    for (const auto& [name, seconds] : m.stage_seconds) {
      total += seconds;
      std::snprintf(line, sizeof line, "%s%s %.2fs", stages.empty() ? "" : ", ", name.c_str(), seconds);
      stages += line;
    }
    std::snprintf(line, sizeof line, "  time %.2fs (%s), peak RSS %.0f MB", total, stages.c_str(), m.peak_rss_mb);
    say(global, line);

    for (const std::string& output : settings->outputs) {
      const FileFormat format = format_from_path(output);
      if (format == FileFormat::GeoJson) {
        write_file_atomic(output, write_partition_geojson(partition));
      } else if (format == FileFormat::Svg) {
        write_file_atomic(output, partition_svg(partition));
      } else {
        write_file_atomic(output, partition_png(partition));
      }
      say(global, "wrote " + output);
    }
    nlohmann::json report = metrics_json(partition);
    report["input"] = settings->source;
    report["method"] = method_name(options.method);
    report["projection"] = partition.projection;
    report["options"] = {{"parts", options.parts},
                         {"cells", options.cells},
                         {"exact_cells", options.exact_cells},
                         {"p", options.p},
                         {"imbalance", options.imbalance},
                         {"angle_weight", options.angle_weight},
                         {"boundary_corners", options.boundary_corners},
                         {"seed", options.seed}};
    nlohmann::json areas = nlohmann::json::array();
    for (const double a : partition.part_areas) areas.push_back(a);
    report["part_areas"] = areas;
    report["outputs"] = settings->outputs;
    write_json_report(global, report);
    return 0;
  };
}

}  // namespace structmesh::cli
