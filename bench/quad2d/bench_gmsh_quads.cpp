// The Gmsh 4.8 all-quad baseline on the benchmark's planar inputs: algorithms 6 and
// 8 with Blossom full-quad recombination (gmsh_quads.hpp), quality as we measure
// ours (quad_quality: Verdict's scaled Jacobian, singular = interior valence != 4).
//
//   bench_gmsh_quads     prints one Markdown table
//
// Each case runs in a forked child process: Gmsh can abort the process (an odd
// 1D mesh, a segfault in a meshing algorithm), and one crash must not end the run.
#include "gmsh_quads.hpp"
#include "structmesh/quality.hpp"
#include "structmesh/regions.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

using namespace structmesh;

namespace {

constexpr unsigned kCaseTimeoutSeconds = 900;

std::vector<Vec2> circle(const Vec2& centre, double radius, int n, bool clockwise) {
  std::vector<Vec2> ring;
  for (int i = 0; i < n; ++i) {
    const double t = (clockwise ? -2 : 2) * M_PI * i / n;
    ring.emplace_back(centre + radius * Vec2(std::cos(t), std::sin(t)));
  }
  return ring;
}

// (a) The unit square with a round hole of radius 0.25 (a 256-gon) in the middle.
Polygon2 square_with_hole() {
  Polygon2 region;
  const std::vector<Vec2> outer{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  region.add_ring(outer);
  region.add_ring(circle({0.5, 0.5}, 0.25, 256, true));
  return region;
}

// (b) A disk of radius about 1 with a noisy coast (a fixed sum of sines: no random
// numbers, the same on every machine) and a noisy island off centre.
Polygon2 noisy_disk_with_island() {
  const auto noisy = [](const Vec2& centre, double radius, int n, bool clockwise, double phase) {
    std::vector<Vec2> ring;
    for (int i = 0; i < n; ++i) {
      const double t = (clockwise ? -2 : 2) * M_PI * i / n;
      const double r = radius * (1 + 0.04 * std::sin(7 * t + phase) + 0.025 * std::sin(13 * t + 1.1 + phase) +
                                 0.015 * std::sin(29 * t + 2.0) + 0.008 * std::sin(61 * t + 0.7));
      ring.emplace_back(centre + r * Vec2(std::cos(t), std::sin(t)));
    }
    return ring;
  };
  Polygon2 region;
  region.add_ring(noisy({0, 0}, 1.0, 720, false, 0.0));
  region.add_ring(noisy({0.35, 0.1}, 0.22, 180, true, 0.9));
  return region;
}

double perimeter(const Polygon2& region) {
  double length = 0;
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const auto ring = region.ring(r);
    for (std::size_t i = 0; i < ring.size(); ++i) length += (ring[(i + 1) % ring.size()] - ring[i]).norm();
  }
  return length;
}

// One table row, computed in the child process.
std::string run_case(const std::string& name, const Polygon2& region, double h, int algorithm) {
  const GmshQuadResult result = gmsh_all_quad(region, h, algorithm);
  char row[512];
  if (!result.error.empty()) {
    std::snprintf(row, sizeof row, "| %s | %d | failed: %s | | | | | | | | |", name.c_str(), algorithm,
                  result.error.c_str());
    return row;
  }
  const QuadQuality q = quad_quality(result.mesh);
  const double rate = result.seconds > 0 ? result.mesh.quads.size() / result.seconds : 0;
  std::snprintf(row, sizeof row, "| %s | %d | %zu | %zu | %zu | %.3f | %.3f | %.3f | %zu | %.2f | %.0f |", name.c_str(),
                algorithm, result.mesh.quads.size(), result.leftover_triangles, q.inverted,
                q.scaled_jacobian_stats.mean, q.scaled_jacobian_stats.stddev, q.scaled_jacobian_stats.min,
                q.singular_vertices, result.seconds, rate);
  return row;
}

// Runs run_case in a child process and returns its row, or a "crashed" row.
std::string guarded_case(const std::string& name, const Polygon2& region, double h, int algorithm) {
  int fds[2];
  if (pipe(fds) != 0) return "| " + name + " | " + std::to_string(algorithm) + " | pipe failed | | | | | | | | |";
  std::fflush(stdout);
  const pid_t child = fork();
  if (child == 0) {
    close(fds[0]);
    alarm(kCaseTimeoutSeconds);
    const std::string row = run_case(name, region, h, algorithm);
    const ssize_t written = write(fds[1], row.data(), row.size());
    _exit(written == static_cast<ssize_t>(row.size()) ? 0 : 1);
  }
  close(fds[1]);
  std::string row;
  char buffer[512];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof buffer)) > 0) row.append(buffer, static_cast<std::size_t>(n));
  close(fds[0]);
  int status = 0;
  waitpid(child, &status, 0);
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    const std::string what = signal == SIGALRM ? "timed out (" + std::to_string(kCaseTimeoutSeconds) + " s)"
                                               : "crashed (" + std::string(strsignal(signal)) + ")";
    return "| " + name + " | " + std::to_string(algorithm) + " | " + what + " | | | | | | | | |";
  }
  return row;
}

}  // namespace

int main() {
  struct Case {
    std::string name;
    Polygon2 region;
    double h;
  };
  std::vector<Case> cases;
  cases.push_back({"(a) unit square, hole r = 0.25, h = 0.02", square_with_hole(), 0.02});
  cases.push_back({"(b) noisy disk + island, h = 0.01", noisy_disk_with_island(), 0.01});
  Polygon2 key = make_key_region(2000);
  const double key_h = perimeter(key) / 2000;
  char key_name[128];
  std::snprintf(key_name, sizeof key_name, "(c) Key (2000 segments), h = perimeter/2000 = %.4g", key_h);
  cases.push_back({key_name, std::move(key), key_h});

  std::printf("## Gmsh 4.8.4 all-quad baseline (Blossom full-quad, RecombinationAlgorithm = 3, 1 thread)\n\n");
  std::printf(
      "| input | algorithm | quads | leftover triangles | inverted | SJ avg | SJ std | SJ min | singular vertices | "
      "seconds | quads/s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Case& c : cases)
    for (const int algorithm : {6, 8}) std::printf("%s\n", guarded_case(c.name, c.region, c.h, algorithm).c_str());
  std::printf(
      "\nAnchor (the issue, input (a), algorithm 6): 2,660 quads, SJ avg/min 0.962/0.715, 132 singular interior "
      "vertices.\n");
  return 0;
}
