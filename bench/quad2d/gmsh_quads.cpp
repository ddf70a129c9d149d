// Gmsh 4.8.4 all-quad baseline; see gmsh_quads.hpp and RECIPES.md (Gmsh section).
#include "gmsh_quads.hpp"

#include "structmesh/quality.hpp"

#include <gmsh.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <unordered_map>
#include <vector>

namespace structmesh {
namespace {

constexpr double kCornerDegrees = 30;
constexpr std::size_t kMinCurvesPerRing = 3;

// Ring points without consecutive duplicates (zero-length segments have no direction).
std::vector<Vec2> clean_ring(std::span<const Vec2> ring) {
  std::vector<Vec2> points;
  for (const Vec2& p : ring)
    if (points.empty() || p != points.back()) points.push_back(p);
  while (points.size() > 1 && points.front() == points.back()) points.pop_back();
  return points;
}

// Indices of the ring's points where its curves start: the corners, plus vertices
// splitting the longest curves until there are kMinCurvesPerRing (when a curve has
// an interior vertex to split at).
std::vector<std::size_t> curve_starts(const std::vector<Vec2>& ring) {
  const std::size_t n = ring.size();
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 in = ring[i] - ring[(i + n - 1) % n], out = ring[(i + 1) % n] - ring[i];
    const double turn = std::atan2(in.x() * out.y() - in.y() * out.x(), in.dot(out));
    if (std::abs(turn) > kCornerDegrees * M_PI / 180) starts.push_back(i);
  }
  if (starts.empty()) starts.push_back(0);
  std::vector<double> arc(n + 1, 0);  // arc length from point 0 to point i (arc[n] = perimeter)
  for (std::size_t i = 0; i < n; ++i) arc[i + 1] = arc[i] + (ring[(i + 1) % n] - ring[i]).norm();
  const auto length = [&](std::size_t a, std::size_t b) { return b > a ? arc[b] - arc[a] : arc[n] - arc[a] + arc[b]; };
  while (starts.size() < kMinCurvesPerRing) {
    std::size_t longest = 0;
    for (std::size_t k = 1; k < starts.size(); ++k)
      if (length(starts[k], starts[(k + 1) % starts.size()]) >
          length(starts[longest], starts[(longest + 1) % starts.size()]))
        longest = k;
    const std::size_t a = starts[longest], b = starts[(longest + 1) % starts.size()];
    const std::size_t count = (b > a ? b - a : n - a + b);  // segments in the curve
    if (count < 2) break;
    // The interior vertex nearest to the curve's middle by arc length.
    const double middle = 0.5 * length(a, b);
    std::size_t best = 1;
    for (std::size_t k = 1; k < count; ++k)
      if (std::abs(length(a, (a + k) % n) - middle) < std::abs(length(a, (a + best) % n) - middle)) best = k;
    starts.push_back((a + best) % n);
    std::sort(starts.begin(), starts.end());
  }
  return starts;
}

// Builds the geometry: one polyline curve per ring piece, transfinite with an even
// number of segments of length about h, one plane surface.
void build_geometry(const Polygon2& region, double h) {
  int next_point = 1;
  std::vector<int> loops;
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const std::vector<Vec2> ring = clean_ring(region.ring(r));
    if (ring.size() < 3) continue;
    std::vector<int> point_tags(ring.size());
    for (std::size_t i = 0; i < ring.size(); ++i)
      point_tags[i] = gmsh::model::geo::addPoint(ring[i].x(), ring[i].y(), 0, h, next_point++);
    const std::vector<std::size_t> starts = curve_starts(ring);
    std::vector<int> curves;
    for (std::size_t k = 0; k < starts.size(); ++k) {
      const std::size_t a = starts[k], b = starts[(k + 1) % starts.size()];
      std::vector<int> tags{point_tags[a]};
      double length = 0;
      std::size_t i = a;
      do {
        const std::size_t j = (i + 1) % ring.size();
        length += (ring[j] - ring[i]).norm();
        tags.push_back(point_tags[j]);
        i = j;
      } while (i != b);
      const int curve = gmsh::model::geo::addPolyline(tags);
      // Blossom full-quad halves every curve's 1D mesh: the segment count must be even.
      const int segments = std::max(2, 2 * static_cast<int>(std::lround(length / (2 * h))));
      gmsh::model::geo::mesh::setTransfiniteCurve(curve, segments + 1);
      curves.push_back(curve);
    }
    loops.push_back(gmsh::model::geo::addCurveLoop(curves));
  }
  gmsh::model::geo::addPlaneSurface(loops);
  gmsh::model::geo::synchronize();
}

void set_options(int algorithm) {
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 1);  // errors only
  gmsh::option::setNumber("General.NumThreads", 1);
  gmsh::option::setNumber("Mesh.MaxNumThreads2D", 1);
  gmsh::option::setNumber("Mesh.Algorithm", algorithm);
  // Without it Debian's build of algorithm 8 segfaults (no ANN library).
  gmsh::option::setNumber("Mesh.CrossFieldClosestPoint", 0);
  gmsh::option::setNumber("Mesh.RecombineAll", 1);
  gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 3);
}

// The quads Gmsh made, compacted to the nodes they use, counter-clockwise.
void collect_mesh(GmshQuadResult& result) {
  std::vector<std::size_t> node_tags, quad_tags, quad_nodes, triangle_tags, triangle_nodes;
  std::vector<double> coords, parametric;
  gmsh::model::mesh::getNodes(node_tags, coords, parametric, -1, -1, true, false);
  gmsh::model::mesh::getElementsByType(3, quad_tags, quad_nodes);
  gmsh::model::mesh::getElementsByType(2, triangle_tags, triangle_nodes);
  result.leftover_triangles = triangle_tags.size();

  std::unordered_map<std::size_t, std::size_t> node_index;  // Gmsh tag -> position in coords
  node_index.reserve(node_tags.size());
  for (std::size_t i = 0; i < node_tags.size(); ++i) node_index.emplace(node_tags[i], i);
  std::unordered_map<std::size_t, Index> point_of_tag;
  QuadMesh& mesh = result.mesh;
  mesh.quads.reserve(quad_tags.size());
  for (std::size_t q = 0; q < quad_tags.size(); ++q) {
    std::array<Index, 4> quad{};
    for (int k = 0; k < 4; ++k) {
      const std::size_t tag = quad_nodes[4 * q + k];
      auto [it, inserted] = point_of_tag.emplace(tag, static_cast<Index>(mesh.points.size()));
      if (inserted) {
        const std::size_t i = node_index.at(tag);
        mesh.points.emplace_back(coords[3 * i], coords[3 * i + 1], 0);
      }
      quad[k] = it->second;
    }
    mesh.quads.push_back(quad);
  }
  // Orientation is decided for the whole mesh (by its total signed area), not per
  // quad, so that quads Gmsh inverted stay inverted.
  double twice_area = 0;
  for (const auto& quad : mesh.quads) {
    const Vec3 d1 = mesh.points[quad[2]] - mesh.points[quad[0]], d2 = mesh.points[quad[3]] - mesh.points[quad[1]];
    twice_area += d1.x() * d2.y() - d1.y() * d2.x();
  }
  if (twice_area < 0)
    for (auto& quad : mesh.quads) std::swap(quad[1], quad[3]);
}

}  // namespace

GmshQuadResult gmsh_all_quad(const Polygon2& region, double h, int algorithm) {
  GmshQuadResult result;
  gmsh::initialize(0, nullptr, false);
  try {
    set_options(algorithm);
    gmsh::model::add("region");
    build_geometry(region, h);
    const auto start = std::chrono::steady_clock::now();
    gmsh::model::mesh::generate(2);
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    collect_mesh(result);
  } catch (const std::string& message) {  // Gmsh 4.8 throws its error messages as strings
    result.error = message.empty() ? "Gmsh failed" : message;
  } catch (const std::exception& e) {
    result.error = e.what();
  }
  if (!result.error.empty()) result.mesh = {};
  gmsh::finalize();
  return result;
}

GmshQuadSummary gmsh_all_quad_isolated(const Polygon2& region, double h, int algorithm, unsigned timeout_seconds) {
  // The child sends the numbers (a fixed-size record) and then the failure text.
  struct Record {
    std::uint64_t quads, leftover_triangles, inverted, singular_vertices;
    double avg, stddev, min, seconds;
  };
  GmshQuadSummary summary;
  int fds[2];
  if (pipe(fds) != 0) {
    summary.failure = "pipe failed";
    return summary;
  }
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t child = fork();
  if (child == 0) {
    close(fds[0]);
    alarm(timeout_seconds);
    const GmshQuadResult result = gmsh_all_quad(region, h, algorithm);
    Record record{};
    std::string failure = result.error;
    if (failure.empty()) {
      const QuadQuality q = quad_quality(result.mesh);
      record = {result.mesh.quads.size(),
                result.leftover_triangles,
                q.inverted,
                q.singular_vertices,
                q.scaled_jacobian_stats.mean,
                q.scaled_jacobian_stats.stddev,
                q.scaled_jacobian_stats.min,
                result.seconds};
    }
    bool ok = write(fds[1], &record, sizeof record) == static_cast<ssize_t>(sizeof record);
    ok = ok && write(fds[1], failure.data(), failure.size()) == static_cast<ssize_t>(failure.size());
    _exit(ok ? 0 : 1);
  }
  close(fds[1]);
  std::string bytes;
  char buffer[4096];
  ssize_t n;
  while ((n = read(fds[0], buffer, sizeof buffer)) > 0) bytes.append(buffer, static_cast<std::size_t>(n));
  close(fds[0]);
  int status = 0;
  waitpid(child, &status, 0);
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    summary.failure = signal == SIGALRM ? "timed out (" + std::to_string(timeout_seconds) + " s)"
                                        : "crashed (" + std::string(strsignal(signal)) + ")";
    return summary;
  }
  if (bytes.size() < sizeof(Record)) {
    summary.failure = "no result from the child process";
    return summary;
  }
  Record record;
  std::memcpy(&record, bytes.data(), sizeof record);
  summary.failure = bytes.substr(sizeof record);
  summary.quads = record.quads;
  summary.leftover_triangles = record.leftover_triangles;
  summary.inverted = record.inverted;
  summary.singular_vertices = record.singular_vertices;
  summary.scaled_jacobian_avg = record.avg;
  summary.scaled_jacobian_std = record.stddev;
  summary.scaled_jacobian_min = record.min;
  summary.seconds = record.seconds;
  return summary;
}

}  // namespace structmesh
