// Star decomposition benchmark (issue 5, dissertation §2.3): the clean closed models of
// the data set tetrahedralized (TetGen, edge length `size factor` x the surface's mean
// edge), guarded (exact ILP), then split into star-shaped parts, relaxed and --strict,
// beside the dissertation's David (175,079 tets, 17 guards, 550 s with 400 s of
// guarding, > 99% of part vertices visible).
//   bench_star DATA_DIR [SIZE_FACTOR [MODEL ...]]
#include "structmesh/guard.hpp"
#include "structmesh/io.hpp"
#include "structmesh/star.hpp"
#include "structmesh/tetmesh.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

using namespace structmesh;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double mean_edge(const TriMesh& surface) {
  double sum = 0;
  for (const auto& t : surface.triangles)
    for (int i = 0; i < 3; ++i) sum += (surface.points[t[i]] - surface.points[t[(i + 1) % 3]]).norm();
  return sum / (3.0 * double(surface.triangles.size()));
}

std::size_t star_parts(const StarResult& r) {
  std::size_t n = 0;
  for (const StarPart& p : r.parts) n += p.star_shaped;
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path data = argc > 1 ? argv[1] : "../shared/data";
  const double factor = argc > 2 ? std::stod(argv[2]) : 1.0;
  std::vector<std::string> models;
  for (int i = 3; i < argc; ++i) models.emplace_back(argv[i]);
  if (models.empty())
    models = {"torus.obj", "3holes.off", "eight.off", "kitten.off", "rocker-arm.obj", "fertility.off"};
  std::printf(
      "| model | tets | guards (ILP) | parts, relaxed (added) | visible, relaxed | merged tets | parts, --strict "
      "(added) | star-shaped, --strict | tetmesh s | guard s | star s, relaxed | star s, --strict |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const std::string& name : models) {
    try {
      const TriMesh surface = to_tri_mesh(read_mesh(data / "surfaces" / name));
      auto start = Clock::now();
      TetmeshOptions tet_options;
      tet_options.size = factor * mean_edge(surface);
      const TetMesh solid = tetrahedralize(surface, tet_options).mesh;
      const double tet_seconds = since(start);
      start = Clock::now();
      std::vector<Vec3> guards;
      for (const Guard& g : guard_surface(surface).guards) guards.push_back(g.position);
      const double guard_seconds = since(start);
      start = Clock::now();
      const StarResult relaxed = star_decomposition(solid, guards, {});
      const double relaxed_seconds = since(start);
      StarOptions strict_options;
      strict_options.strict = true;
      start = Clock::now();
      const StarResult strict = star_decomposition(solid, guards, strict_options);
      const double strict_seconds = since(start);
      std::size_t added_relaxed = 0, added_strict = 0;
      for (const StarPart& p : relaxed.parts) added_relaxed += p.added;
      for (const StarPart& p : strict.parts) added_strict += p.added;
      std::printf(
          "| %s | %zu | %zu | %zu (%zu) | %.4f%% | %zu | %zu (%zu) | %zu of %zu | %.2f | %.2f | %.2f | %.2f |\n",
          name.c_str(), solid.tets.size(), guards.size(), relaxed.parts.size(), added_relaxed,
          100.0 * relaxed.visible_fraction, relaxed.merged_tets, strict.parts.size(), added_strict, star_parts(strict),
          strict.parts.size(), tet_seconds, guard_seconds, relaxed_seconds, strict_seconds);
    } catch (const std::exception& e) {
      std::printf("| %s | failed: %s | | | | | | | | | | |\n", name.c_str(), e.what());
    }
    std::fflush(stdout);
  }
  std::printf("| David (dissertation §2.3) | 175,079 | 17 | - | > 99%% | - | - | - | - | 400 | 150 | - |\n");
  return 0;
}
