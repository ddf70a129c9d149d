// Polycube construction benchmark (issue 6, dissertation ch. 4): per closed model of the
// data set, the pre-deformation, the Morse voxel size, the voxels, the corners before and
// after the optimisation of (4.1), the topology check, and the time of each stage beside
// Table 5.1's t_pre and t_opt; then Table 4.1's alpha trade-off on the rocker arm.
//   bench_polycube DATA_DIR [MODEL...]
#include "../surface_models.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/polycube.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

using namespace structmesh;

namespace {

// Table 5.1 (N_V, t_pre, t_opt in seconds; 2.27 GHz workstation) for the models we have.
const std::map<std::string, const char*>& dissertation() {
  static const std::map<std::string, const char*> rows = {
      {"bunny_hr.obj", "Bunny (34.8k): 294.2 / 521.2"}, {"rocker-arm.obj", "Rocker arm (45k): 312.4 / 610.0"},
      {"hand_closed.obj", "Hand (32k): 260.2 / 525.9"}, {"fertility.off", "Fertility (34k): 262.2 / 485.5"},
      {"kitten.off", "Kitten (35k): 284.2 / 515.9"},    {"kitten_40k.off", "Kitten (35k): 284.2 / 515.9"},
      {"3holes.off", "3-Torus (9.1k): 124.1 / 234.5"},
  };
  return rows;
}

double seconds_of(const PolycubeResult& r, const std::string& name) {
  for (const auto& [stage, seconds] : r.stage_seconds)
    if (stage == name) return seconds;
  return 0;
}

std::string topology(const VoxelTopology& t) {
  return std::to_string(t.components) + "/" + std::to_string(t.handles) + "/" + std::to_string(t.voids);
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::filesystem::path> models = bench::surface_models(argc, argv);

  std::printf(
      "| model | vertices | genus | normal deviation, input -> Q (deg) | wedges | Morse eta / diagonal | voxel size / "
      "diagonal | grid | voxels | corners, voxelized -> optimised -> planes merged | facet planes x/y/z, before -> "
      "after merging | E_g | topology (b0/b1/b2) kept | pre-deformation s "
      "| voxelization s | optimisation s | dissertation (N_V): t_pre / t_opt s |\n");
  std::printf("|---|---:|---:|---|---:|---:|---:|---|---:|---|---|---:|---|---:|---:|---:|---|\n");
  for (const auto& path : models) {
    const std::string name = path.filename().string();
    const auto row = dissertation().find(name);
    const char* anchor = row == dissertation().end() ? "-" : row->second;
    try {
      const TriMesh surface = to_tri_mesh(read_mesh(path));
      if (!check_surface(to_bundle(surface)).valid_solid_boundary) {
        std::printf(
            "| %s | %zu | not a solid boundary (open, self-intersecting or inward): skipped | | | | | | | | | | "
            "| | | | %s |\n",
            name.c_str(), surface.points.size(), anchor);
        continue;
      }
      const PolycubeResult r = build_polycube(surface);
      const double diagonal = r.pseudo.surface.bounding_box().diagonal();
      const bool kept =
          r.final.components == r.expected.components && r.final.handles == r.expected.handles && r.final.voids == 0;
      std::printf(
          "| %s | %zu | %lld | %.1f -> %.1f | %zu | %.4f | %.4f | %dx%dx%d | %zu | %zu -> %zu -> %zu | %zu/%zu/%zu -> "
          "%zu/%zu/%zu | %.2f | %s %s | %.2f | "
          "%.2f | %.2f | %s |\n",
          name.c_str(), surface.points.size(), static_cast<long long>(r.expected.handles),
          r.pseudo.input_deviation_degrees, r.pseudo.deviation_degrees, r.pseudo.wedges, r.morse.size / diagonal,
          r.voxels.size / diagonal, r.voxels.dims[0], r.voxels.dims[1], r.voxels.dims[2], r.voxels.count(),
          r.optimization.before.corners, r.before_merge.corners, r.optimization.after.corners,
          r.plane_merge.planes_before[0], r.plane_merge.planes_before[1], r.plane_merge.planes_before[2],
          r.plane_merge.planes_after[0], r.plane_merge.planes_after[1], r.plane_merge.planes_after[2],
          r.optimization.after.deviation, topology(r.final).c_str(), kept ? "yes" : "NO",
          seconds_of(r, "pre-deformation"), seconds_of(r, "voxelization"), seconds_of(r, "optimisation"), anchor);
    } catch (const std::exception& e) {
      std::string what = e.what();
      if (what.size() > 160) what = what.substr(0, 157) + "...";
      std::printf("| %s | failed: %s | | | | | | | | | | | | | | | %s |\n", name.c_str(), what.c_str(), anchor);
    }
    std::fflush(stdout);
  }

  // Table 4.1: the weight alpha against corners and deviation, on the rocker arm.
  const std::filesystem::path rocker =
      std::filesystem::path(argc > 1 ? argv[1] : "../shared/data") / "surfaces" / "rocker-arm.obj";
  if (argc > 2 || !std::filesystem::exists(rocker)) return 0;
  // The optimisation alone (plane merging off: its moves are not weighed by alpha), then
  // with the plane merging that build_polycube() does by default.
  std::printf(
      "\n| alpha | E_c (corners) | E_g (sum of distances / diagonal) | with plane merging: E_c / E_g | dissertation: "
      "E_c / E_g |\n");
  std::printf("|---:|---:|---:|---|---|\n");
  const TriMesh surface = to_tri_mesh(read_mesh(rocker));
  const std::map<int, const char*> table_4_1 = {
      {5, "41 / 6.82"}, {10, "60 / 5.51"}, {20, "80 / 4.10"}, {40, "134 / 3.12"}};
  for (const auto& [alpha, anchor] : table_4_1) {
    PolycubeOptions options;
    options.optimization.alpha = alpha;
    const PolycubeResult r = build_polycube(surface, options);
    std::printf("| %d | %zu | %.2f | %zu / %.2f | %s |\n", alpha, r.before_merge.corners, r.before_merge.deviation,
                r.optimization.after.corners, r.optimization.after.deviation, anchor);
    std::fflush(stdout);
  }
  return 0;
}
