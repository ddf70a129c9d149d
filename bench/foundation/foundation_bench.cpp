// Foundation benchmark: reading, validating and measuring meshes beside anchors on
// the same inputs, in one run.
//  - reading: our .msh reader vs the Gmsh 4.8 library opening the same file;
//  - quality: our hex/quad scaled Jacobian vs VTK's vtkMeshQuality (timed by
//    bench/foundation/vtk_quality.py on the same .vtu, run by bench/run_foundation.sh);
//  - checks: our surface check on every model vs the counts in shared/data/README.md.
// Prints Markdown; never fails the build.
#include "structmesh/check.hpp"
#include "structmesh/io.hpp"
#include "structmesh/quality.hpp"

#include <gmsh.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace structmesh;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <typename F>
double best_of(int runs, F&& f) {
  double best = 1e300;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    f();
    best = std::min(best, seconds_since(start));
  }
  return best;
}

// A structured n^3 hex grid with every interior point jittered by up to `jitter`
// of the spacing (deterministic seed), so the quality pass has real work.
HexMesh jittered_hex_grid(int n, double jitter) {
  HexMesh mesh;
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  const auto id = [n](int i, int j, int k) { return static_cast<Index>((k * (n + 1) + j) * (n + 1) + i); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const bool interior = i > 0 && j > 0 && k > 0 && i < n && j < n && k < n;
        mesh.points.emplace_back(i + (interior ? u(rng) : 0), j + (interior ? u(rng) : 0), k + (interior ? u(rng) : 0));
      }
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        mesh.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                              id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  return mesh;
}

QuadMesh jittered_quad_grid(int n, double jitter) {
  QuadMesh mesh;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const bool interior = i > 0 && j > 0 && i < n && j < n;
      mesh.points.emplace_back(i + (interior ? u(rng) : 0), j + (interior ? u(rng) : 0), 0.0);
    }
  const auto id = [n](int i, int j) { return static_cast<Index>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) mesh.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return mesh;
}

double gmsh_open_seconds(const fs::path& file) {
  gmsh::initialize();
  gmsh::option::setNumber("General.Terminal", 0);
  const auto start = std::chrono::steady_clock::now();
  gmsh::open(file.string());
  const double t = seconds_since(start);
  gmsh::finalize();
  return t;
}

// The anchor: a row of the surfaces table in shared/data/README.md
// (| file | KB | V | F | closed | orient | chi | g | selfX | notes |), markup stripped.
struct ReadmeRow {
  std::string closed = "?", genus = "?", self_intersections = "?";
};

ReadmeRow readme_row(const std::string& readme, const std::string& file) {
  ReadmeRow row;
  const std::size_t at = readme.find("| " + file + " |");
  if (at == std::string::npos) return row;
  const std::string line = readme.substr(at, readme.find('\n', at) - at);
  std::vector<std::string> cells;
  std::size_t start = 1;
  for (std::size_t bar = line.find('|', start); bar != std::string::npos; bar = line.find('|', start)) {
    std::string cell = line.substr(start, bar - start);
    std::erase(cell, '*');
    std::erase(cell, ' ');
    cells.push_back(cell);
    start = bar + 1;
  }
  if (cells.size() < 9) return row;
  row.closed = cells[4];
  row.genus = cells[7];
  row.self_intersections = cells[8];
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path data = argc > 1 ? fs::path(argv[1]) : fs::path("../shared/data");
  const fs::path work = argc > 2 ? fs::path(argv[2]) : fs::temp_directory_path() / "structmesh-bench";
  const int grid = argc > 3 ? std::atoi(argv[3]) : 100;
  fs::create_directories(work);

  // 1. Quality on a jittered hex grid and quad grid; the .vtu files feed the VTK timing.
  const HexMesh hexes = jittered_hex_grid(grid, 0.3);
  const QuadMesh quads = jittered_quad_grid(grid * 10, 0.3);
  HexQuality hq;
  QuadQuality qq;
  // The per-element scaled Jacobian alone is what vtkMeshQuality computes; the full
  // report adds the 8-corner value, dihedral angles, statistics and singular vertices.
  std::vector<double> values(hexes.hexes.size());
  const double t_hex_sj = best_of(3, [&] {
    tbb::parallel_for(std::size_t{0}, hexes.hexes.size(), [&](std::size_t i) {
      std::array<Vec3, 8> c;
      for (int k = 0; k < 8; ++k) c[k] = hexes.points[hexes.hexes[i][k]];
      values[i] = hex_scaled_jacobian(c).value_or(0.0);
    });
  });
  const double t_hex = best_of(3, [&] { hq = hex_quality(hexes); });
  values.assign(quads.quads.size(), 0.0);
  const Vec3 up(0, 0, 1);
  const double t_quad_sj = best_of(3, [&] {
    tbb::parallel_for(std::size_t{0}, quads.quads.size(), [&](std::size_t i) {
      const auto& q = quads.quads[i];
      values[i] =
          quad_scaled_jacobian({quads.points[q[0]], quads.points[q[1]], quads.points[q[2]], quads.points[q[3]]}, &up);
    });
  });
  const double t_quad = best_of(3, [&] { qq = quad_quality(quads); });
  write_mesh(work / "hex_grid.vtu", to_bundle(hexes));
  write_mesh(work / "quad_grid.vtu", to_bundle(quads));
  std::printf("## Quality measures (anchor: VTK's vtkMeshQuality, table below)\n\n");
  std::printf(
      "| input | elements | structmesh SJ only (s) | structmesh full report (s) | SJ min / avg | inverted | singular "
      "|\n|---|---|---|---|---|---|---|\n");
  std::printf("| jittered hex grid %d^3 | %zu | %.3f | %.3f | %.4f / %.4f | %zu | %zu |\n", grid, hexes.hexes.size(),
              t_hex_sj, t_hex, hq.scaled_jacobian_stats.min, hq.scaled_jacobian_stats.mean, hq.inverted,
              hq.singular_vertices);
  std::printf("| jittered quad grid %d^2 | %zu | %.3f | %.3f | %.4f / %.4f | %zu | %zu |\n\n", grid * 10,
              quads.quads.size(), t_quad_sj, t_quad, qq.scaled_jacobian_stats.min, qq.scaled_jacobian_stats.mean,
              qq.inverted, qq.singular_vertices);

  // 2. Reading .msh: ours vs Gmsh on the same file.
  std::printf("## Reading Gmsh .msh v4.1 (ASCII) — structmesh vs the Gmsh 4.8 library\n\n");
  std::printf("| file | elements | structmesh read (s) | Gmsh open (s) | Gmsh / structmesh |\n|---|---|---|---|---|\n");
  const fs::path hex_msh = work / "hex_grid.msh";
  write_mesh(hex_msh, to_bundle(hexes));
  const double ours_hex = best_of(3, [&] { (void)read_mesh(hex_msh); });
  const double gmsh_hex = gmsh_open_seconds(hex_msh);
  std::printf("| hex grid %d^3 | %zu | %.3f | %.3f | %.1fx |\n", grid, hexes.hexes.size(), ours_hex, gmsh_hex,
              gmsh_hex / ours_hex);

  // 3. Surfaces: read + full check (incl. exact self-intersections) vs the data README.
  std::printf("\n## Surface checks on shared/data/surfaces — structmesh vs the data README\n\n");
  std::printf(
      "| model | faces | read (s) | check (s) | closed (ours / README) | genus (ours / README) | selfX (ours / README) "
      "|\n|---|---|---|---|---|---|---|\n");
  std::vector<fs::path> files;
  if (fs::is_directory(data / "surfaces"))
    for (const auto& entry : fs::directory_iterator(data / "surfaces")) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  const std::string readme = fs::exists(data / "README.md") ? read_file(data / "README.md") : std::string();
  for (const fs::path& file : files) {
    MeshBundle mesh;
    const double t_read = best_of(1, [&] { mesh = read_mesh(file); });
    SurfaceReport report;
    const double t_check = best_of(1, [&] { report = check_surface(mesh); });
    const ReadmeRow anchor = readme_row(readme, file.filename().string());
    std::printf("| %s | %zu | %.3f | %.3f | %s / %s | %s / %s | %zu / %s |\n", file.filename().c_str(),
                mesh.triangles.size(), t_read, t_check, report.closed ? "yes" : "no", anchor.closed.c_str(),
                report.genus >= 0 ? std::to_string(report.genus).c_str() : "-", anchor.genus.c_str(),
                report.self_intersections, anchor.self_intersections.c_str());
  }
  return 0;
}
