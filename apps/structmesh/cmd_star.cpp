// structmesh star SOLID [--guards guards.json] -o parts.vtu: star decomposition (§2.3)
// of a tet mesh (or of a closed surface, tetrahedralized first), seeded by the guards of
// `structmesh guard` or, without --guards, by guards computed here.
#include "cli.hpp"
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"
#include "structmesh/io.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/render.hpp"
#include "structmesh/star.hpp"
#include "structmesh/tetmesh.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

namespace structmesh::cli {

Action add_star_command(CLI::App& command, const GlobalOptions& global) {
  struct Settings {
    std::string input, guards_path, method = "ilp";
    std::vector<std::string> outputs;
    StarOptions options;
    double size = 0;
  };
  auto settings = std::make_shared<Settings>();
  command
      .add_option("SOLID", settings->input,
                  "Tet mesh (.mesh .msh .vtu), or a closed surface (.obj .off .ply .stl) tetrahedralized first")
      ->required();
  command.add_option("--guards", settings->guards_path,
                     "guards.json from structmesh guard (default: guard the solid's boundary here)");
  command.add_option("--method", settings->method, "Guarding method when --guards is not given: greedy or ilp")
      ->check(CLI::IsMember({"greedy", "ilp"}))
      ->capture_default_str();
  command
      .add_option("-o,--output", settings->outputs,
                  "parts.vtu (cell data part), parts.mesh (part id as the tet reference), parts.msh, or parts.png (the "
                  "boundary coloured by part); repeatable")
      ->required();
  command.add_flag("--strict", settings->options.strict,
                   "Every part star-shaped (exactly): leftover tets are re-guarded instead of merged");
  command
      .add_option("--merge-max-tets", settings->options.merge_max_tets,
                  "Without --strict: leftover components up to this many tets join a neighbouring part")
      ->capture_default_str();
  command
      .add_option("--merge-max-violations", settings->options.merge_max_violations,
                  "Without --strict: a leftover component joins a neighbouring part only if at most this many of "
                  "its faces still break the growth rule after the vertex moves (else it is re-guarded)")
      ->capture_default_str();
  command
      .add_option("--repair-max-tets", settings->options.repair_max_tets,
                  "Leftover components up to this many tets try to join a neighbouring part with interior points "
                  "moved until the part is star-shaped again (0: never)")
      ->capture_default_str();
  command
      .add_option("--smooth", settings->options.smoothing_iterations,
                  "Laplacian smoothing sweeps of the borders between parts (moves interior points only; keeps "
                  "every star-shaped part star-shaped)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  command.add_option("--size", settings->size, "Tet size when the input is a surface (0: its mean edge length)")
      ->check(CLI::NonNegativeNumber);

  return [&global, settings]() {
    for (const std::string& output : settings->outputs) {
      const FileFormat format = format_from_path(output);
      if (std::filesystem::path(output).extension() == ".png") continue;
      if (format != FileFormat::Medit && format != FileFormat::Vtu && format != FileFormat::Msh)
        throw InputError(output + ": star writes .vtu, .mesh, .msh or .png");
    }
    const MeshBundle bundle = read_mesh(settings->input);
    TetMesh solid;
    if (!bundle.tets.empty()) {
      solid = to_tet_mesh(bundle);
    } else if (!bundle.triangles.empty() && bundle.quads.empty() && bundle.hexes.empty()) {
      TetmeshOptions tet_options;
      tet_options.size = settings->size;
      if (!global.quiet) status("star: tetrahedralizing " + settings->input);
      try {
        solid = tetrahedralize(to_tri_mesh(bundle), tet_options).mesh;
      } catch (const InputError& e) {
        throw InputError(settings->input + ": " + e.what());
      }
    } else {
      throw InputError(settings->input + ": star needs a tet mesh or a closed triangle surface");
    }

    std::vector<Vec3> guards;
    double guard_seconds = 0;
    if (!settings->guards_path.empty()) {
      guards = read_json_points(settings->guards_path, "guards", "position");
    } else {
      GuardOptions guard_options;
      guard_options.method = settings->method == "greedy" ? GuardMethod::Greedy : GuardMethod::Ilp;
      guard_options.progress = !global.quiet;
      const auto start = std::chrono::steady_clock::now();
      try {
        for (const Guard& guard : guard_surface(boundary_surface(solid), guard_options).guards)
          guards.push_back(guard.position);
      } catch (const InputError& e) {
        throw InputError(settings->input + ": its boundary cannot be guarded: " + e.what());
      }
      guard_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }

    StarOptions options = settings->options;
    options.progress = !global.quiet;
    StarResult result;
    try {
      result = star_decomposition(solid, guards, options);
    } catch (const InputError& e) {
      throw InputError(settings->input + ": " + e.what());
    }

    MeshBundle out;
    out.points = result.points;
    out.tets = solid.tets;
    out.tet_labels.assign(result.tet_part.begin(), result.tet_part.end());
    WriteOptions write;
    DataArray part{"part", {}, out.tet_labels};
    DataArray added{"added_guard", {}, {}};
    for (const Index p : result.tet_part) added.i32.push_back(result.parts[p].added ? 1 : 0);
    write.cell_data = {std::move(part), std::move(added)};
    for (const std::string& output : settings->outputs) {
      if (std::filesystem::path(output).extension() != ".png") {
        write_mesh(output, out, write);
        continue;
      }
      // The solid's boundary faces coloured by the part of their tet, guards as dots.
      TetMesh moved{result.points, solid.tets};
      const TriMesh boundary = boundary_surface(moved);
      const FaceAdjacency<3> faces = build_faces(moved);
      std::vector<std::int32_t> labels;
      for (std::size_t f = 0; f < faces.faces.size(); ++f)
        if (faces.face_cells[f][1] == kInvalidIndex)
          labels.push_back(static_cast<std::int32_t>(result.tet_part[faces.face_cells[f][0]]));
      std::vector<Vec3> positions;
      for (const StarPart& p : result.parts) positions.push_back(p.guard);
      write_file_atomic(output, surface_png(boundary, labels, positions));
    }

    std::size_t star_parts = 0, added_parts = 0;
    for (const StarPart& p : result.parts) {
      star_parts += p.star_shaped;
      added_parts += p.added;
    }
    char line[320];
    std::snprintf(line, sizeof line,
                  "%zu parts (%zu from the %zu guards, %zu added), %zu star-shaped; %.4f%% of part vertices visible "
                  "from their guard; %zu tets merged, %zu joined after moving %zu interior points",
                  result.parts.size(), result.parts.size() - added_parts, guards.size(), added_parts, star_parts,
                  100.0 * result.visible_fraction, result.merged_tets, result.repaired_tets, result.relocated_vertices);
    say(global, line);
    for (const std::string& output : settings->outputs) say(global, "wrote " + output);

    nlohmann::json parts = nlohmann::json::array();
    for (const StarPart& p : result.parts)
      parts.push_back({{"guard", {p.guard.x(), p.guard.y(), p.guard.z()}},
                       {"added", p.added},
                       {"tets", p.tets},
                       {"volume", p.volume},
                       {"vertices", p.vertices},
                       {"visible_vertices", p.visible_vertices},
                       {"visible_fraction", p.vertices ? double(p.visible_vertices) / double(p.vertices) : 1.0},
                       {"kernel_violations", p.kernel_violations},
                       {"star_shaped", p.star_shaped}});
    nlohmann::json stages = nlohmann::json::object();
    if (guard_seconds > 0) stages["guarding"] = guard_seconds;
    for (const auto& [name, seconds] : result.stage_seconds) stages[name] = seconds;
    write_json_report(global, {{"input", settings->input},
                               {"outputs", settings->outputs},
                               {"strict", settings->options.strict},
                               {"tets", solid.tets.size()},
                               {"points", solid.points.size()},
                               {"guards", guards.size()},
                               {"dropped_guards", result.dropped_guards},
                               {"moved_guards", result.moved_guards},
                               {"parts", parts},
                               {"part_count", result.parts.size()},
                               {"star_shaped_parts", star_parts},
                               {"added_parts", added_parts},
                               {"merged_tets", result.merged_tets},
                               {"absorbed_tets", result.absorbed_tets},
                               {"repaired_tets", result.repaired_tets},
                               {"relocated_vertices", result.relocated_vertices},
                               {"growth_rounds", result.growth_rounds},
                               {"visible_fraction", result.visible_fraction},
                               {"smoothed_vertices", result.smoothed_vertices},
                               {"interface_area", {result.interface_area_before, result.interface_area_after}},
                               {"stage_seconds", stages},
                               {"peak_rss_mb", peak_rss_mb()}});
    return 0;
  };
}

}  // namespace structmesh::cli
