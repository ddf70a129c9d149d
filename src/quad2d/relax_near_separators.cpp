// relax_near_separators(): the post-processing of §3.3.2. After the parts are
// glued, the rows of neighbouring parts meet at the separators with a kink; a few
// Laplacian sweeps over the vertices within five rings of the separators smooth it.
//
// The sweeps are Gauss-Seidel over colour classes: no two vertices of one colour
// share a quad, so the vertices of a colour move in parallel without touching each
// other's quads, and the result is the same for any thread count (and, with a halo
// exchange after each colour, for any number of MPI ranks).
#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/quality.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>

namespace structmesh {

namespace {

// A move may lower an incident quad's scaled Jacobian, as plain Laplacian smoothing
// does, but not below this floor (nor below the quad's current value when that is
// lower already), and never to an inverted quad.
constexpr double kQualityFloor = 0.5;

double min_incident_jacobian(const QuadMesh& mesh, std::span<const Index> quads, Index vertex, const Vec3& position) {
  static const Vec3 up(0, 0, 1);
  double worst = std::numeric_limits<double>::infinity();
  for (const Index q : quads) {
    std::array<Vec3, 4> corners;
    for (int k = 0; k < 4; ++k) {
      const Index v = mesh.quads[q][k];
      corners[k] = v == vertex ? position : mesh.points[v];
    }
    worst = std::min(worst, quad_scaled_jacobian(corners, &up));
  }
  return worst;
}

}  // namespace

RelaxStats relax_near_separators(MergedMesh& merged, const RelaxOptions& options) {
  if (options.rings < 0 || options.iterations < 0) throw InputError("relax_near_separators: negative rings or iterations");
  QuadMesh& mesh = merged.mesh;
  const std::size_t n = mesh.points.size();
  if (merged.fixed.size() != n || merged.separator.size() != n)
    throw InputError("relax_near_separators: fixed/separator flags must have one entry per point");
  const CompressedRows vertex_quads = build_vertex_elements(mesh.quads, n);

  const auto for_each_edge_neighbour = [&](Index v, auto&& visit) {
    for (const Index q : vertex_quads.row(v)) {
      const auto& quad = mesh.quads[q];
      for (int k = 0; k < 4; ++k)
        if (quad[k] == v) {
          visit(quad[(k + 1) % 4]);
          visit(quad[(k + 3) % 4]);
        }
    }
  };

  // The zone: breadth-first rings from the separator points.
  std::vector<std::int32_t> ring(n, -1);
  std::vector<Index> frontier, next;
  for (Index v = 0; v < n; ++v)
    if (merged.separator[v]) ring[v] = 0, frontier.push_back(v);
  for (int r = 1; r <= options.rings && !frontier.empty(); ++r) {
    next.clear();
    for (const Index v : frontier)
      for_each_edge_neighbour(v, [&](Index w) {
        if (ring[w] < 0) ring[w] = r, next.push_back(w);
      });
    std::sort(next.begin(), next.end());
    frontier.swap(next);
  }
  std::vector<Index> zone;
  for (Index v = 0; v < n; ++v)
    if (ring[v] >= 0 && !merged.fixed[v] && vertex_quads.row(v).size() > 0) zone.push_back(v);

  // Greedy colouring in vertex order: a colour not used by any zone vertex sharing a quad.
  std::vector<std::int32_t> colour(n, -1);
  std::int32_t colours = 0;
  std::vector<std::uint8_t> used;
  for (const Index v : zone) {
    used.assign(static_cast<std::size_t>(colours) + 1, 0);
    for (const Index q : vertex_quads.row(v))
      for (const Index w : mesh.quads[q])
        if (colour[w] >= 0) used[static_cast<std::size_t>(colour[w])] = 1;
    std::int32_t c = 0;
    while (used[static_cast<std::size_t>(c)]) ++c;
    colour[v] = c;
    colours = std::max(colours, c + 1);
  }
  std::vector<std::vector<Index>> classes(static_cast<std::size_t>(colours));
  for (const Index v : zone) classes[static_cast<std::size_t>(colour[v])].push_back(v);

  RelaxStats stats;
  stats.moved_vertices = zone.size();
  double scale = 0;  // mean edge length in the zone, for the convergence test
  std::size_t edges = 0;
  for (const Index v : zone)
    for_each_edge_neighbour(v, [&](Index w) { scale += (mesh.points[w] - mesh.points[v]).norm(), ++edges; });
  scale = edges > 0 ? scale / static_cast<double>(edges) : 0;

  std::atomic<std::size_t> rejected{0};
  for (int iteration = 0; iteration < options.iterations && !zone.empty(); ++iteration) {
    std::atomic<std::uint64_t> largest_move_bits{0};  // doubles >= 0 order like their bits
    for (const std::vector<Index>& members : classes) {
      tbb::parallel_for(std::size_t{0}, members.size(), [&](std::size_t i) {
        const Index v = members[i];
        Vec3 sum = Vec3::Zero();
        int count = 0;
        for_each_edge_neighbour(v, [&](Index w) { sum += mesh.points[w], ++count; });
        const Vec3 target = sum / count;
        const std::span<const Index> quads = vertex_quads.row(v);
        const double before = min_incident_jacobian(mesh, quads, v, mesh.points[v]);
        const double after = min_incident_jacobian(mesh, quads, v, target);
        if (!(after > 0) || after < std::min(before, kQualityFloor)) {
          rejected.fetch_add(1, std::memory_order_relaxed);
          return;
        }
        const double move = (target - mesh.points[v]).norm();
        mesh.points[v] = target;
        std::uint64_t bits = 0;
        std::memcpy(&bits, &move, sizeof bits);
        std::uint64_t seen = largest_move_bits.load(std::memory_order_relaxed);
        while (bits > seen && !largest_move_bits.compare_exchange_weak(seen, bits)) {
        }
      });
    }
    stats.iterations = iteration + 1;
    double largest_move = 0;
    const std::uint64_t bits = largest_move_bits.load();
    std::memcpy(&largest_move, &bits, sizeof largest_move);
    if (largest_move <= 1e-9 * scale) break;
  }
  stats.rejected_moves = rejected.load();
  return stats;
}

}  // namespace structmesh
