// structmesh quad2d REGION|key|pipe --size H|--quads N [--parts K] -o mesh.vtu|.msh|.mesh|.pvtu|.png:
// parallel all-quad meshing of a planar region (dissertation ch. 3.3-3.4).
// Parse, call mesh_region_quads, write, report.
#include "cli.hpp"
#include "quad2d_command.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/render.hpp"

#include <oneapi/tbb/task_arena.h>

#include <cstdio>
#include <filesystem>
#include <memory>

namespace structmesh::cli {

void check_outputs(const std::vector<std::string>& outputs) {
  for (const std::string& output : outputs) {
    const FileFormat format = format_from_path(output);
    if (format != FileFormat::Vtu && format != FileFormat::Pvtu && format != FileFormat::Msh &&
        format != FileFormat::Medit && format != FileFormat::Png)
      throw InputError(output + ": quad2d writes .vtu, .pvtu, .msh, .mesh or .png");
  }
}

void write_outputs(const std::vector<std::string>& outputs, const QuadMesh& mesh,
                   const std::vector<std::int32_t>& part_of_quad, const std::vector<double>& scaled_jacobian,
                   const QuadPictureOptions& picture) {
  MeshBundle bundle;
  bundle.points = mesh.points;
  bundle.quads = mesh.quads;
  bundle.quad_labels = part_of_quad;
  WriteOptions data;
  data.cell_data.push_back({.name = "part", .f64 = {}, .i32 = part_of_quad});
  data.cell_data.push_back({.name = "scaled_jacobian", .f64 = scaled_jacobian, .i32 = {}});
  for (const std::string& output : outputs) {
    if (format_from_path(output) == FileFormat::Png) {
      write_file_atomic(output, quad_mesh_png(mesh, scaled_jacobian, picture));
    } else if (format_from_path(output) == FileFormat::Pvtu) {
      // One process: a single piece beside the .pvtu (MPI runs write one per rank).
      const std::filesystem::path path(output);
      const std::string piece = path.stem().string() + "_0.vtu";
      write_mesh(path.parent_path() / piece, bundle, data);
      write_file_atomic(path, write_pvtu({piece}, data));
    } else {
      write_mesh(output, bundle, data);
    }
  }
}

namespace {

nlohmann::json report_json(const Quad2dResult& result, const Quad2dSettings& settings) {
  const Quad2dReport& r = result.report;
  nlohmann::json stages = nlohmann::json::object();
  double total = 0;
  for (const auto& [name, seconds] : r.stage_seconds) {
    stages[name] = seconds;
    if (name == "total") total = seconds;
  }
  return {{"region", settings.source},
          {"quads", r.quads},
          {"points", r.points},
          {"parts", r.parts},
          {"size", r.size},
          {"scaled_jacobian",
           {{"avg", r.scaled_jacobian_avg}, {"std", r.scaled_jacobian_std}, {"min", r.scaled_jacobian_min}}},
          {"inverted", r.inverted},
          {"singular_vertices", r.singular_vertices},
          {"region_area", r.region_area},
          {"mesh_area", r.mesh_area},
          {"paving",
           {{"rows", r.paving.rows},
            {"seams", r.paving.seams},
            {"splits", r.paving.splits},
            {"templates", r.paving.templates},
            {"fallback_loops", r.paving.fallback_loops},
            {"repairs", r.paving.repairs},
            {"untangled", r.paving.untangled},
            {"mapped_parts", r.paving.mapped},
            {"polar_parts", r.paving.polar},
            {"unplanned_block_parts", r.paving.unplanned_blocks},
            {"retried_parts", r.paving.retries},
            {"cleanup_operations", r.paving.cleanup_operations},
            {"grid_interior_quads", r.paving.grid_interior_quads}}},
          {"relax",
           {{"zone_vertices", r.relax.moved_vertices},
            {"refused_moves", r.relax.rejected_moves},
            {"iterations", r.relax.iterations}}},
          {"part_seconds", r.part_seconds},
          {"stage_seconds", stages},
          {"quads_per_second", total > 0 ? static_cast<double>(r.quads) / total : 0.0},
          {"threads", tbb::this_task_arena::max_concurrency()},
          {"peak_rss_mb", r.peak_rss_mb},
          {"projection", r.projection},
          {"coordinates", settings.lonlat_output ? "lonlat" : (r.projection.empty() ? "input" : "projected")},
          {"partition", nullptr}};
}

}  // namespace

Action add_quad2d_command(CLI::App& command, const GlobalOptions& global) {
  auto settings = std::make_shared<Quad2dSettings>();
  Quad2dOptions& o = settings->options;
  command.add_option("REGION", settings->source, "Region file (.geojson, .poly), or the built-in key or pipe")
      ->required();
  auto* size =
      command.add_option("--size", settings->size, "Target quad edge length (metric units; metres for lon/lat)")
          ->check(CLI::PositiveNumber);
  command.add_option("--quads", settings->quads, "About this many quads (derives --size from the area)")
      ->check(CLI::PositiveNumber)
      ->excludes(size);
  command.add_option("-k,--parts", o.partition.parts,
                     "Parts (default: 1 below 20k quads, else max(8, 1 per 500k quads, 2 per MPI rank))");
  command.add_option("--method", settings->method, "Partitioning: cvtgp (default), cvt, metis, madd or exact")
      ->check(CLI::IsMember({"cvtgp", "cvt", "metis", "madd", "exact"}));
  command.add_option("--cells", o.partition.cells,
                     "CVT cells / fine triangles of the partitioning (default: one per 100 quads, 256..4000)");
  command.add_option("--seed", o.partition.seed, "Seed of the partitioning")->capture_default_str();
  command.add_option("--relax-rings", o.relax.rings, "Rings around the separators that relaxation moves (§3.3.2)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command.add_option("--relax-iterations", o.relax.iterations, "Laplacian sweeps near the separators")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command
      .add_option("--min-channel", o.min_channel,
                  "Close water narrower than this many element sizes before meshing (0: keep all)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command.add_option("--min-island", o.min_island, "Drop islands smaller than this many element areas (0: keep all)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command.add_flag("!--no-blocks", o.blocks,
                   "Pave every part whole (the dissertation's mesher) instead of structured blocks and grid "
                   "interiors where they fit");
  command
      .add_option("--grid-interior", o.paving.grid_interior_quads,
                  "Parts of at least this many quads get a grid of squares inside, paving only along their "
                  "boundary (0: pave whole parts)")
      ->capture_default_str();
  command.add_option("--segments", settings->segments, "Boundary segments of the built-in key or pipe")
      ->check(CLI::Range(std::size_t{16}, std::size_t{200'000'000}));
  command.add_option("--polygon", settings->polygon, "Which polygon of a multi-polygon file: INDEX or largest");
  command.add_flag("--lonlat-output", settings->lonlat_output,
                   "Write lon/lat input back in degrees (default: the projected plane)");
  command.add_option("-o,--output", settings->outputs,
                     "Outputs: .vtu, .pvtu, .msh, .mesh, .png (coloured by scaled Jacobian) (repeatable)");
  command.add_option("--merged", settings->merged_outputs,
                     "Under mpirun: also gather the whole mesh on rank 0 and write it here (repeatable)");
  command.add_option("--view", settings->view, "Picture window x0,y0,x1,y1 (output coordinates; default: all)");
  command.add_option("--picture-width", settings->picture_width, "Picture width in pixels")
      ->capture_default_str()
      ->check(CLI::Range(64, 20000));

  return [&command, &global, settings]() {
    check_outputs(settings->outputs);
    QuadPictureOptions picture;
    picture.width_px = settings->picture_width;
    if (!settings->view.empty()) picture.view = parse_view(settings->view);
    picture.title = "scaled Jacobian";
    Quad2dOptions options = settings->options;
    options.auto_cells = command.count("--cells") == 0;
    options.size = settings->size;
    options.target_quads = settings->quads;
    options.partition.method = parse_method(settings->method);
    options.progress = global.progress;
    if (!options.blocks) options.paving.grid_interior_quads = 0;  // the dissertation's paving of whole parts
    const Polygon2 region = load_region(settings->source, settings->segments, settings->polygon);
    if (settings->lonlat_output && region.coordinates != Polygon2::Coordinates::LonLat)
      throw InputError("--lonlat-output needs a lon/lat region; " + settings->source + " is planar");
    if (launched_by_mpirun()) return run_quad2d_mpi(*settings, options, region, picture, global);
    Quad2dResult result = mesh_region_quads(region, options);
    const Quad2dReport& r = result.report;
    if (settings->lonlat_output) points_to_lonlat(region, result.merged.mesh.points);
    write_outputs(settings->outputs, result.merged.mesh, result.merged.part_of_quad, result.scaled_jacobian, picture);

    if (!r.projection.empty()) say(global, "lon/lat input meshed in " + r.projection);
    if (const std::string filter = coastline_filter_summary(r.coastline_filter); !filter.empty()) say(global, filter);
    double total = 0;
    for (const auto& [name, seconds] : r.stage_seconds)
      if (name == "total") total = seconds;
    char line[256];
    std::snprintf(line, sizeof line, "%zu quads in %zu parts (size %.6g), %.2f s, %.0f quads/s", r.quads, r.parts,
                  r.size, total, total > 0 ? static_cast<double>(r.quads) / total : 0.0);
    say(global, line);
    std::snprintf(line, sizeof line, "  scaled Jacobian avg/std/min  %.4f / %.4f / %.4f", r.scaled_jacobian_avg,
                  r.scaled_jacobian_std, r.scaled_jacobian_min);
    say(global, line);
    std::snprintf(line, sizeof line, "  inverted %zu, singular vertices %zu, area %.8g (region %.8g)", r.inverted,
                  r.singular_vertices, r.mesh_area, r.region_area);
    say(global, line);
    for (const std::string& output : settings->outputs) say(global, "wrote " + output);
    nlohmann::json report = report_json(result, *settings);
    Partition for_metrics;
    for_metrics.metrics = r.partition;
    for_metrics.simplification = r.coastline_filter;
    report["partition"] = metrics_json(for_metrics);
    write_json_report(global, report);
    return r.inverted == 0 ? 0 : 1;
  };
}

}  // namespace structmesh::cli
