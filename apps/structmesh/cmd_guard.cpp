// structmesh guard SURFACE|SOLID: fewest interior guards that see every boundary face
// (§2.2), with the per-face guard colouring and the guard graph.
#include "cli.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"
#include "structmesh/io.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/render.hpp"
#include "structmesh/tetmesh.hpp"

#include <filesystem>
#include <memory>

namespace structmesh::cli {

namespace {

nlohmann::json guards_json(const GuardResult& result, const std::string& method) {
  nlohmann::json guards = nlohmann::json::array();
  for (const Guard& guard : result.guards)
    guards.push_back(
        {{"position", {guard.position.x(), guard.position.y(), guard.position.z()}}, {"faces", guard.faces}});
  nlohmann::json graph = nlohmann::json::array();
  for (const auto& [a, b] : result.graph) graph.push_back({a, b});
  // Every candidate, so that `--candidates guards.json` reruns on the same ones.
  nlohmann::json candidates = nlohmann::json::array();
  for (const Vec3& p : result.candidate_points) candidates.push_back({p.x(), p.y(), p.z()});
  return {{"method", method}, {"guards", guards}, {"graph", graph}, {"candidates", candidates}};
}

}  // namespace

Action add_guard_command(CLI::App& command, const GlobalOptions& global) {
  struct Settings {
    std::string input, method = "ilp", candidates_path;
    std::vector<std::string> outputs;
    GuardOptions options;
    bool repair = false;
  };
  auto settings = std::make_shared<Settings>();
  command.add_option("INPUT", settings->input, "Closed surface (.obj .off .ply .stl) or tet mesh (.mesh .msh .vtu)")
      ->required();
  command
      .add_option(
          "--method", settings->method,
          "greedy, ilp (exact set cover with CBC, after reductions) or pilp (progressive ILP over coarse-to-fine "
          "levels of the surface, §2.2.3)")
      ->check(CLI::IsMember({"greedy", "ilp", "pilp"}))
      ->capture_default_str();
  command
      .add_option(
          "-o,--output", settings->outputs,
          "guards.json (positions, faces, graph); a surface file (.vtu .ply .obj .off .mesh) coloured by guard; a "
          "picture (.png) of the faces coloured by guard, guards as dots")
      ->required();
  command
      .add_option("--spacing", settings->options.spacing, "Skeleton resampling spacing (default 1% of the diagonal)")
      ->check(CLI::PositiveNumber);
  command.add_option("--skeleton-vertices", settings->options.skeleton_vertices,
                     "Simplify the surface to this many vertices for the skeleton (0: never)");
  command
      .add_option("--time-limit", settings->options.time_limit,
                  "ILP time limit in seconds (the best cover so far is kept)")
      ->check(CLI::PositiveNumber);
  command
      .add_option("--pilp-coarsest", settings->options.pilp_coarsest_vertices,
                  "pilp: vertices of the coarsest level (finer levels add --pilp-step each)")
      ->capture_default_str();
  command.add_option("--pilp-step", settings->options.pilp_level_step, "pilp: vertices each finer level adds")
      ->capture_default_str();
  command
      .add_option("--pilp-significance", settings->options.pilp_significance,
                  "pilp: guards seeing less than this share of a level's area are re-examined")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  command
      .add_option("--pilp-exchange-group", settings->options.pilp_exchange_group,
                  "pilp: at the end, groups of this many guards are replaced by fewer where a small exact ILP "
                  "finds it (0 or 1: off)")
      ->capture_default_str();
  command
      .add_option("--refine-seconds", settings->options.refine_seconds,
                  "ilp, pilp: after the cover, up to this many seconds of rounds of candidates where one guard may "
                  "replace two (in the kernel of the faces only those two see), solved again (0: off)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command.add_option("--candidates", settings->candidates_path,
                     "Candidate guards from the \"candidates\" of an earlier guards.json instead of the curve "
                     "skeleton (the skeleton varies slightly from run to run; this makes a rerun repeatable)");
  command.add_flag("--repair", settings->repair,
                   "Close holes (the faces of guards.json then index the closed surface: the input's triangles "
                   "first), turn an inward surface outward, and guard across self-intersections");
  return [&global, settings]() {
    const MeshBundle input = read_mesh(settings->input);
    TriMesh surface = input.tets.empty() ? to_tri_mesh(input) : boundary_surface(to_tet_mesh(input));
    GuardOptions options = settings->options;
    if (!settings->candidates_path.empty()) {
      options.candidates = read_json_points(settings->candidates_path, "candidates");
      if (options.candidates.empty()) throw InputError(settings->candidates_path + ": no candidates");
    }
    nlohmann::json repaired = nullptr;
    if (settings->repair) {
      repaired = repair_surface(surface, settings->input, global);
      options.allow_self_intersections = true;
    }
    options.method = settings->method == "greedy" ? GuardMethod::Greedy
                     : settings->method == "pilp" ? GuardMethod::Pilp
                                                  : GuardMethod::Ilp;
    options.progress = !global.quiet;
    GuardResult result;
    try {
      result = guard_surface(surface, options);
    } catch (const InputError& e) {
      throw InputError(settings->input + ": " + e.what());
    }
    if (result.self_intersections > 0)
      say(global, "--repair: guarding across " + std::to_string(result.self_intersections) +
                      " self-intersecting face pairs (visibility as the surface is)");

    for (const std::string& output : settings->outputs) {
      if (std::filesystem::path(output).extension() == ".json") {
        write_file_atomic(output, guards_json(result, settings->method).dump() + "\n");
        continue;
      }
      if (std::filesystem::path(output).extension() == ".png") {
        std::vector<std::int32_t> labels(surface.triangles.size());
        for (std::size_t f = 0; f < labels.size(); ++f)
          labels[f] = result.face_guard[f] == kInvalidIndex ? -1 : static_cast<std::int32_t>(result.face_guard[f]);
        std::vector<Vec3> positions;
        for (const Guard& guard : result.guards) positions.push_back(guard.position);
        write_file_atomic(output, surface_png(surface, labels, positions));
        continue;
      }
      MeshBundle coloured = to_bundle(surface);
      coloured.triangle_labels.resize(surface.triangles.size());
      WriteOptions write;
      DataArray guard{"guard", {}, {}};
      for (std::size_t f = 0; f < surface.triangles.size(); ++f) {
        const Index g = result.face_guard[f];
        coloured.triangle_labels[f] = g == kInvalidIndex ? -1 : static_cast<std::int32_t>(g);
        guard.i32.push_back(coloured.triangle_labels[f]);
      }
      write.cell_data.push_back(std::move(guard));
      write_mesh(output, coloured, write);
    }
    std::string how = settings->method;
    if (settings->method == "ilp")
      how += std::string(result.optimal ? ", optimal" : ", not proven optimal") + " over " +
             std::to_string(result.candidates) + " candidates";
    if (result.kernel_candidates > 0)
      how += "; " + std::to_string(result.guards_before_refinement) + " before the kernel rounds' " +
             std::to_string(result.kernel_candidates) + " candidates";
    say(global, std::to_string(result.guards.size()) + " guards (" + how + "; greedy " +
                    std::to_string(result.greedy_guards_before_refinement) + "); " +
                    std::to_string(result.uncovered_faces) + " faces seen by no candidate");
    nlohmann::json report{{"input", settings->input},
                          {"vertices", surface.points.size()},
                          {"faces", surface.triangles.size()},
                          {"method", settings->method},
                          {"guards", result.guards.size()},
                          {"greedy_guards", result.greedy_guards},
                          {"greedy_guards_before_refinement", result.greedy_guards_before_refinement},
                          {"guards_before_refinement", result.guards_before_refinement},
                          {"kernel_candidates", result.kernel_candidates},
                          {"refinement_rounds", result.refinement_rounds},
                          {"refinement_exchanges", result.refinement_exchanges},
                          {"refined_optimal", result.refined_optimal},
                          {"refined_lower_bound", result.refined_lower_bound},
                          {"optimal", result.optimal},
                          {"lower_bound", result.lower_bound},
                          {"skeleton_nodes", result.skeleton_nodes},
                          {"candidates", result.candidates},
                          {"added_candidates", result.added_candidates},
                          {"uncovered_faces", result.uncovered_faces},
                          {"ilp_rows", {result.rows_before, result.rows_after}},
                          {"ilp_columns", {result.columns_before, result.columns_after}},
                          {"graph_edges", result.graph.size()},
                          {"repaired", repaired},
                          {"self_intersections", result.self_intersections},
                          {"peak_rss_mb", peak_rss_mb()}};
    nlohmann::json levels = nlohmann::json::array();
    for (const PilpLevel& level : result.levels)
      levels.push_back({{"vertices", level.vertices},
                        {"faces", level.faces},
                        {"kept", level.kept},
                        {"dropped", level.dropped},
                        {"universe", level.universe},
                        {"added", level.added},
                        {"guards", level.guards},
                        {"optimal", level.optimal},
                        {"seconds", level.seconds}});
    report["pilp_levels"] = levels;
    report["pilp_pruned"] = result.pilp_pruned;
    report["pilp_exchanges"] = result.pilp_exchanges;
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& [name, seconds] : result.stage_seconds) stages[name] = seconds;
    report["stage_seconds"] = stages;
    write_json_report(global, report);
    return result.uncovered_faces == 0 ? 0 : 1;
  };
}

}  // namespace structmesh::cli
