// Shape guarding benchmark (issue 5, dissertation §2.2): Table 2.1 recomputed on the
// closed models of the data set: guards by greedy and by the exact ILP, the ILP's
// reduction, and the time of every stage, beside the dissertation's rows.
//   bench_guard DATA_DIR               Table 2.1 (every surface)
//   bench_guard DATA_DIR --table-2.2   Table 2.2 (skeleton against tet-vertex candidates)
//   bench_guard DATA_DIR --only NAME... Table 2.1 for the named surfaces only
#include "../surface_models.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"
#include "structmesh/io.hpp"
#include "structmesh/skeleton.hpp"
#include "structmesh/tetmesh.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

using namespace structmesh;

namespace {

// Table 2.1 (N_V, ILP / greedy / PILP guards, seconds) for the models we also have
// (TOSCA models at another resolution: orientation only).
const std::map<std::string, const char*>& dissertation() {
  static const std::map<std::string, const char*> rows = {
      {"tosca_dog0_closed.off", "Dog (15,002): - / 39 / 27, 412 s greedy"},
      {"tosca_victoria.off", "Victoria (15,000): - / 35 / 27, 409 s"},
      {"horse.off", "Horse (20,002): - / 38 / 29, 376 s"},
      {"tosca_michael.off", "Michael (20,002): - / 46 / 31, 321 s"},
      {"tosca_gorilla.off", "Gorilla (30,004): - / 60 / 46, 462 s"},
      {"tosca_centaur.off", "Centaur (30,002): - / 52 / 32, 488 s"},
      {"kitten.off", "Kitten (400, Table 2.2): 3"},
      {"bunny_hr.obj", "Bunny (998, Table 2.2): 5"},
  };
  return rows;
}

double seconds_of(const GuardResult& r, const std::string& name) {
  for (const auto& [stage, seconds] : r.stage_seconds)
    if (stage == name) return seconds;
  return 0;
}

}  // namespace

// Table 2.2: guards (ILP) from skeleton candidates against guards from every interior
// tet vertex, on models simplified to the dissertation's sizes (400-1,000 vertices).
int table_2_2(const std::filesystem::path& data) {
  struct Model {
    const char* file;
    std::size_t vertices;
    const char* anchor;
  };
  const Model models[] = {{"kitten.off", 400, "Kitten (400): 3 / 3"},
                          {"bunny_hr.obj", 1000, "Bunny (998): 5 / 5"},
                          {"3holes.off", 600, "-"},
                          {"fertility.off", 750, "-"},
                          {"torus.obj", 500, "-"}};
  std::printf(
      "| model | boundary vertices | tet vertices | skeleton candidates | guards, tet vertices | guards, "
      "skeleton | both optimal | dissertation (V: G_VM / G_S) |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---|---|\n");
  for (const Model& model : models) {
    try {
      // Edge collapse can fold the surface onto itself: then a few more vertices.
      const TriMesh input = to_tri_mesh(read_mesh(data / "surfaces" / model.file));
      TriMesh surface;
      TetMesh solid;
      for (const double grow : {1.0, 1.1, 1.2, 1.3, 1.5}) {
        surface = simplify_surface(input, static_cast<std::size_t>(grow * double(model.vertices)));
        try {
          solid = tetrahedralize(surface).mesh;
          break;
        } catch (const InputError&) {
          if (grow == 1.5) throw;
        }
      }
      GuardOptions options;
      options.skeleton_vertices = 0;
      const GuardResult skeletal = guard_surface(surface, options);
      // Every tet vertex; guard_surface() keeps those strictly inside.
      options.candidates = solid.points;
      const GuardResult all = guard_surface(surface, options);
      std::printf("| %s | %zu | %zu | %zu | %zu | %zu | %s | %s |\n", model.file, surface.points.size(),
                  solid.points.size(), skeletal.candidates, all.guards.size(), skeletal.guards.size(),
                  skeletal.optimal && all.optimal ? "yes" : "no", model.anchor);
    } catch (const std::exception& e) {
      std::printf("| %s | failed: %s | | | | | | %s |\n", model.file, e.what(), model.anchor);
    }
    std::fflush(stdout);
  }
  return 0;
}

int main(int argc, char** argv) {
  const std::filesystem::path data = argc > 1 ? argv[1] : "../shared/data";
  if (argc > 2 && std::string(argv[2]) == "--table-2.2") return table_2_2(data);
  bench::require_surfaces_folder(data);
  std::vector<std::filesystem::path> models;
  for (const auto& entry : std::filesystem::directory_iterator(data / "surfaces")) models.push_back(entry.path());
  std::sort(models.begin(), models.end());
  // --only NAME...: just those models (e.g. to add the slow ones to a table).
  if (argc > 2 && std::string(argv[2]) == "--only") {
    const std::vector<std::string> only(argv + 3, argv + argc);
    std::erase_if(models, [&](const std::filesystem::path& path) {
      return std::find(only.begin(), only.end(), path.filename().string()) == only.end();
    });
  }
  std::printf(
      "| model | vertices | skeleton nodes | candidates (added; kernel) | greedy | ILP (before kernel rounds) | "
      "optimal "
      "(before; after) | PILP (levels) | greedy, ILP's candidates | ILP rows / columns (reduced) | skeleton s | "
      "visibility s | ILP cover s | kernel rounds s | PILP cover + kernel s | total s (ILP) | dissertation (N_V: ILP / "
      "greedy / PILP) |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---|\n");
  double ratio_sum = 0, pilp_ratio_sum = 0, same_candidates_ratio_sum = 0;
  std::size_t rows = 0;
  for (const auto& path : models) {
    const std::string name = path.filename().string();
    const auto row = dissertation().find(name);
    const char* anchor = row == dissertation().end() ? "-" : row->second;
    try {
      TriMesh surface = to_tri_mesh(read_mesh(path));
      GuardOptions options;
      options.method = GuardMethod::Ilp;
      options.time_limit = 20;  // per ILP (per level for PILP): keeps the 52k-vertex TOSCA models to minutes
      // Models that are not valid solid boundaries go through `guard --repair`: holes
      // closed, an inward surface turned, self-intersections guarded across.
      std::string repaired;
      if (!check_surface(to_bundle(surface)).valid_solid_boundary) {
        const SurfaceRepair repair = repair_solid_surface(surface);
        options.allow_self_intersections = true;
        repaired = " (repaired: " + bench::repair_label(repair);
      }
      const auto start = std::chrono::steady_clock::now();
      const GuardResult r = guard_surface(surface, options);
      const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      // PILP on the same candidates (CGAL's skeleton differs from call to call).
      GuardOptions progressive = options;
      progressive.method = GuardMethod::Pilp;
      progressive.candidates = r.candidate_points;
      progressive.max_added_candidates = 0;  // exactly the ILP's candidates, also where faces stay unseen
      const GuardResult p = guard_surface(surface, progressive);
      if (!repaired.empty())
        repaired += ", " + std::to_string(r.self_intersections) + " crossing face pairs, " +
                    std::to_string(r.uncovered_faces) + " faces seen by no candidate)";
      const std::string label = name + repaired;
      std::printf(
          "| %s | %zu | %zu | %zu (%zu; %zu) | %zu | %zu (%zu) | %s; %s | %zu (%zu) | %zu | %zu / %zu (%zu / %zu) | "
          "%.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %s |\n",
          label.c_str(), surface.points.size(), r.skeleton_nodes, r.candidates + r.kernel_candidates,
          r.added_candidates, r.kernel_candidates, r.greedy_guards_before_refinement, r.guards.size(),
          r.guards_before_refinement, r.optimal ? "yes" : "no", r.refined_optimal ? "yes" : "no", p.guards.size(),
          p.levels.size(), r.greedy_guards, r.rows_before, r.columns_before, r.rows_after, r.columns_after,
          seconds_of(r, "skeleton"), seconds_of(r, "visibility"), seconds_of(r, "cover"), seconds_of(r, "refinement"),
          seconds_of(p, "cover") + seconds_of(p, "refinement"), total, anchor);
      const auto greedy = static_cast<double>(r.greedy_guards_before_refinement);
      ratio_sum += static_cast<double>(r.guards.size()) / greedy;
      pilp_ratio_sum += static_cast<double>(p.guards.size()) / greedy;
      same_candidates_ratio_sum += static_cast<double>(r.guards.size()) / static_cast<double>(r.greedy_guards);
      ++rows;
    } catch (const std::exception& e) {
      std::string what = e.what();
      if (what.size() > 120) what = what.substr(0, 117) + "...";
      std::printf("| %s | rejected: %s | | | | | | | | | | | | | | | %s |\n", name.c_str(), what.c_str(), anchor);
    }
    std::fflush(stdout);
  }
  if (rows > 0)
    std::printf(
        "\nOn average over the %zu rows: ILP / greedy %.3f, PILP / greedy %.3f; ILP / greedy over the ILP's "
        "candidates (kernel ones included) %.3f.\n",
        rows, ratio_sum / static_cast<double>(rows), pilp_ratio_sum / static_cast<double>(rows),
        same_candidates_ratio_sum / static_cast<double>(rows));
  return 0;
}
