// Polycube hex meshing benchmark (issue 6, dissertation ch. 5): Table 5.2's measures and
// Table 5.1's stage times for every closed model of the data set, at the dissertation's hex
// counts where it has a row (10k hexes otherwise), beside its numbers.
//   bench_hex DATA_DIR [MODEL...]
//   bench_hex --unseen [SHAPES_DIR [SHAPE...]]   the built-in solids of solids.hpp (all, or the
//       ones named) at 10k hexes; each written as OBJ into SHAPES_DIR unless that is empty
// With BENCH_HEX_UNTANGLE_MAP=1 in the environment, with `--smooth-surface-map --untangle-map`
// (HexOptions::smooth_surface_map, the joint untangling over 3, 6 and 12 rings).
#include "../surface_models.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/io.hpp"
#include "structmesh/solids.hpp"
#include "structmesh/tetmesh.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

using namespace structmesh;

namespace {

struct Anchor {
  std::size_t hexes;
  const char* row;  // Table 5.2 (ours): #hexes, avg scaled Jacobian, dihedral avg/std, D_v, N_h; Table 5.1 times
};

const std::map<std::string, Anchor>& dissertation() {
  static const std::map<std::string, Anchor> rows = {
      {"bunny_hr.obj", {80000, "80k, 0.938, 89.99/11.43, 0.997, N_h 211; 884 s"}},
      {"rocker-arm.obj", {18000, "18k, 0.931, 90.00/12.75, 0.997, N_h 200; 997 s"}},
      {"fertility.off", {18000, "18k, 0.914, 89.99/10.41, 0.993, N_h 366; 815 s"}},
      {"hand_closed.obj", {10000, "10k, 0.937, 89.88/12.88, 0.994, N_h 110; 867 s"}},
      {"kitten.off", {16000, "16k, 0.923, 89.98/12.18, 0.997, N_h 941; 887 s"}},
      {"kitten_40k.off", {16000, "16k, 0.923, 89.98/12.18, 0.997, N_h 941; 887 s"}},
      {"3holes.off", {25000, "25k, 0.927, 89.99/10.31, 0.996, N_h 944; 400 s"}},
  };
  return rows;
}

// The seconds of the stages named `name`, with any suffix: an extraction made twice reports
// "smoothing" and "smoothing (boundary on P)", and the kept mesh's "smoothing (kept mesh)".
double stage(const HexResult& r, const std::string& name) {
  double total = 0;
  for (const auto& [s, seconds] : r.stage_seconds)
    if (s == name || s.starts_with(name + " (")) total += seconds;
  return total;
}

// The table's header: `first` names the first column(s) ("| model"), `alignment` aligns them
// ("|---"), `anchor` heads the last column.
void print_header(const char* first, const char* alignment, const char* anchor) {
  std::printf(
      "%s | vertices | target | hexes | scaled Jacobian min / avg | 8-corner min | inverted | dihedral avg / std "
      "| D_v | map's flipped tets: solved → untangled → star cavities → joint untangling | Q folded on P; branch "
      "points | surface map distortion | D_g (1e-3) | N_h | corners; facet planes x/y/z | polycube s | tets + map s "
      "| grid + smoothing s | total s | %s |\n",
      first, anchor);
  std::printf("%s|---:|---:|---:|---|---:|---:|---|---:|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|\n",
              alignment);
}

// One row: `surface` meshed at `target` hexes with default settings (plus the opt-in map
// steps with `untangle_map`); `label` names it, `anchor` is the dissertation's row or "-".
void print_row(const std::string& label, const TriMesh& surface, std::size_t target, const char* anchor,
               bool untangle_map) {
  HexOptions options;
  options.target_hexes = target;
  if (untangle_map) {
    options.smooth_surface_map = true;
    options.map_untangling = TetMapUntanglingOptions{};  // 3, 6 and 12 rings, never giving up
    options.untangle_map_onto_q = true;
  }
  const auto start = std::chrono::steady_clock::now();
  const HexResult r = polycube_hex_mesh(surface, options);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const HexQuality& q = r.quality;
  char buffer[64];
  if (r.map.flipped == 0)
    std::snprintf(buffer, sizeof buffer, "%.3f", r.map.volume_distortion);
  else
    std::snprintf(buffer, sizeof buffer, "- (%zu flipped)", r.map.flipped);
  const std::string volume_distortion = buffer;
  const auto& planes = r.polycube.plane_merge.planes_after;
  std::snprintf(buffer, sizeof buffer, "%zu; %zu/%zu/%zu%s", r.polycube.optimization.after.corners, planes[0],
                planes[1], planes[2],
                r.merged_map_folded ? " (unmerged: merged map folded)"
                : r.unmerged_kept   ? " (unmerged: retry)"
                : r.merging_retried ? " (merged, retry worse)"
                                    : "");
  const std::string corners = buffer;
  std::snprintf(buffer, sizeof buffer, "%zu → %zu → %zu → %zu", r.map.flipped_before_untangling,
                r.flipped_repair.flipped_before, r.flipped_repair.flipped_after, r.map.flipped);
  const std::string flipped = buffer;
  // smooth_surface_map()'s energy (1 at best) and the worst area ratio, before -> after.
  if (r.surface_map_smoothing.sweeps > 0)
    std::snprintf(buffer, sizeof buffer, "%.3g → %.3g; %.3g → %.3g%s", r.surface_map_smoothing.energy_before,
                  r.surface_map_smoothing.energy_after, r.surface_map_smoothing.worst_area_ratio_before,
                  r.surface_map_smoothing.worst_area_ratio_after,
                  r.surface_map_smoothed_after_flips ? " (after flips)" : "");
  else
    std::snprintf(buffer, sizeof buffer, "%s", r.surface_map_smoothed_after_flips ? "- (after flips: not kept)" : "-");
  const std::string distortion = buffer;
  std::printf(
      "| %s | %zu | %zu | %zu | %.3f / %.3f | %.3f | %zu | %.2f / %.2f | %s | %s | %zu → %zu; %zu → %zu | %s | "
      "%.3f | "
      "%zu | %s | %.1f | "
      "%.1f | "
      "%.1f | %.1f | %s |\n",
      label.c_str(), surface.points.size(), target, r.mesh.hexes.size(), q.scaled_jacobian_stats.min,
      q.scaled_jacobian_stats.mean, q.corner_scaled_jacobian_stats.min, q.inverted + q.invalid, q.dihedral_degrees.mean,
      q.dihedral_degrees.stddev, volume_distortion.c_str(), flipped.c_str(), r.surface_map.folded_before,
      r.surface_map.folded_after, r.surface_map.branched_before, r.surface_map.branched_after, distortion.c_str(),
      1e3 * r.geometric_deviation, q.singular_vertices, corners.c_str(), stage(r, "polycube (total)"),
      stage(r, "tet mesh") + stage(r, "surface map") + stage(r, "surface map smoothing") + stage(r, "volumetric map"),
      stage(r, "hex grid") + stage(r, "inverse map") + stage(r, "padding") + stage(r, "smoothing"), total, anchor);
}
}  // namespace

int main(int argc, char** argv) {
  const char* untangle_env = std::getenv("BENCH_HEX_UNTANGLE_MAP");
  const bool untangle_map = untangle_env != nullptr && std::string(untangle_env) == "1";
  if (argc > 1 && std::string(argv[1]) == "--unseen") {
    const std::filesystem::path shapes_dir = argc > 2 ? argv[2] : "";
    if (!shapes_dir.empty()) std::filesystem::create_directories(shapes_dir);
    print_header("| shape | what", "|---|---", "dissertation");
    const std::vector<std::string> only(argv + std::min(argc, 3), argv + argc);
    for (const BuiltinSolid& solid : builtin_solids()) {
      const std::string name(solid.name), what(solid.description);
      if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end()) continue;
      const TriMesh surface = make_builtin_solid(solid.name);
      if (!shapes_dir.empty()) write_mesh(shapes_dir / (name + ".obj"), to_bundle(surface));
      const SurfaceReport report = check_surface(to_bundle(surface));
      if (!report.valid_solid_boundary) {
        std::printf("| %s | %s | %zu | not a solid boundary:%s ||||||||||||||||| - |\n", name.c_str(), what.c_str(),
                    surface.points.size(), solid_boundary_problems(report).c_str());
        continue;
      }
      try {
        print_row(name + " | " + what, surface, 10000, "-", untangle_map);
      } catch (const std::exception& e) {
        std::printf("| %s | %s | failed: %s ||||||||||||||||||| - |\n", name.c_str(), what.c_str(), e.what());
      }
      std::fflush(stdout);
    }
    return 0;
  }
  const std::vector<std::filesystem::path> models = bench::surface_models(argc, argv);
  print_header("| model", "|---", "dissertation (Table 5.2; 5.1 total)");
  for (const auto& path : models) {
    const std::string name = path.filename().string();
    const auto row = dissertation().find(name);
    const std::size_t target = row == dissertation().end() ? 10000 : row->second.hexes;
    const char* anchor = row == dissertation().end() ? "-" : row->second.row;
    try {
      TriMesh surface = to_tri_mesh(read_mesh(path));
      // What `structmesh hex --repair` does for a surface that does not bound a solid: holes
      // closed, an inward surface turned; a self-intersecting one stays skipped.
      std::string label = name;
      if (!check_surface(to_bundle(surface)).valid_solid_boundary) {
        const SurfaceRepair repair = repair_solid_surface(surface);
        const std::string what = bench::repair_label(repair);
        const SurfaceReport after = check_surface(to_bundle(surface));
        if (!after.valid_solid_boundary) {
          std::printf(
              "| %s | %zu | not a solid boundary, also after --repair (%s):%s; skipped ||||||||||||||||| %s |\n",
              name.c_str(), surface.points.size(), what.c_str(), solid_boundary_problems(after).c_str(), anchor);
          std::fflush(stdout);
          continue;
        }
        label += " (--repair: " + what + ")";
      }
      print_row(label, surface, target, anchor, untangle_map);
    } catch (const std::exception& e) {
      std::string message = e.what();
      if (message.size() > 160) message = message.substr(0, 160) + "...";
      std::printf("| %s | failed: %s ||||||||||||||||||| %s |\n", name.c_str(), message.c_str(), anchor);
    }
    std::fflush(stdout);
  }
  return 0;
}
