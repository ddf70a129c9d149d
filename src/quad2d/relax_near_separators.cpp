// relax_near_separators(): the post-processing of §3.3.2. After the parts are
// glued, the rows of neighbouring parts meet at the separators with a kink; a few
// Laplacian sweeps over the vertices within five rings of the separators smooth it.
//
// Each sweep is a Jacobi step: every zone vertex proposes the mean of its edge
// neighbours, summed in ascending vertex order, from the positions before the
// sweep. Then, in synchronous rounds, every quad that the proposals would invert
// (or push below the quality floor) refuses the proposals of all its moving
// vertices, until no quad objects. Nothing depends on the order in which vertices
// or quads are visited, so the result is bit-identical for any thread count and for
// any split of the mesh over MPI ranks that exchanges proposals and refusals of the
// shared vertices (apps/structmesh/quad2d_mpi.cpp).
#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/quality.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace structmesh {

namespace {

// A move may lower an incident quad's scaled Jacobian, as plain Laplacian smoothing
// does, but not below this floor (nor below the quad's current value when that is
// lower already), and never to an inverted quad.
constexpr double kQualityFloor = 0.5;

}  // namespace

RelaxStats relax_near_separators(MergedMesh& merged, const RelaxOptions& options) {
  if (options.rings < 0 || options.iterations < 0)
    throw InputError("relax_near_separators: negative rings or iterations");
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

  RelaxStats stats;
  stats.moved_vertices = zone.size();
  double scale = 0;  // mean edge length in the zone, for the convergence test
  std::size_t edges = 0;
  for (const Index v : zone)
    for_each_edge_neighbour(v, [&](Index w) { scale += (mesh.points[w] - mesh.points[v]).norm(), ++edges; });
  scale = edges > 0 ? scale / static_cast<double>(edges) : 0;

  // Neighbours of the zone vertices, each once, ascending (a fixed summation order).
  CompressedRows neighbours;
  {
    std::vector<Index> row;
    for (const Index v : zone) {
      row.clear();
      for_each_edge_neighbour(v, [&](Index w) { row.push_back(w); });
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
      neighbours.items.insert(neighbours.items.end(), row.begin(), row.end());
      neighbours.offsets.push_back(static_cast<Index>(neighbours.items.size()));
    }
  }
  // The quads that can change: those with a zone vertex.
  std::vector<Index> zone_quads;
  for (const Index v : zone)
    for (const Index q : vertex_quads.row(v)) zone_quads.push_back(q);
  std::sort(zone_quads.begin(), zone_quads.end());
  zone_quads.erase(std::unique(zone_quads.begin(), zone_quads.end()), zone_quads.end());
  std::vector<Index> zone_slot(n, kInvalidIndex);
  for (std::size_t i = 0; i < zone.size(); ++i) zone_slot[zone[i]] = static_cast<Index>(i);

  static const Vec3 up(0, 0, 1);
  const auto jacobian = [&](const std::array<Index, 4>& quad, auto&& position) {
    std::array<Vec3, 4> corners;
    for (int k = 0; k < 4; ++k) corners[k] = position(quad[k]);
    return quad_scaled_jacobian(corners, &up);
  };
  std::vector<Vec3> proposal(zone.size());
  std::vector<std::uint8_t> accepted(zone.size());
  std::vector<double> quality_before(zone_quads.size());
  std::size_t rejected = 0;
  for (int iteration = 0; iteration < options.iterations && !zone.empty(); ++iteration) {
    tbb::parallel_for(std::size_t{0}, zone.size(), [&](std::size_t i) {
      Vec3 sum = Vec3::Zero();
      const auto row = neighbours.row(i);
      for (const Index w : row) sum += mesh.points[w];
      proposal[i] = sum / static_cast<double>(row.size());
      accepted[i] = 1;
    });
    tbb::parallel_for(std::size_t{0}, zone_quads.size(), [&](std::size_t i) {
      quality_before[i] = jacobian(mesh.quads[zone_quads[i]], [&](Index v) { return mesh.points[v]; });
    });
    const auto proposed = [&](Index v) {
      const Index slot = zone_slot[v];
      return slot != kInvalidIndex && accepted[slot] ? proposal[slot] : mesh.points[v];
    };
    // Refusal rounds: each round reads the previous round's acceptances only.
    std::vector<Index> refuse;
    while (true) {
      refuse.clear();
      for (std::size_t i = 0; i < zone_quads.size(); ++i) {
        const auto& quad = mesh.quads[zone_quads[i]];
        const double after = jacobian(quad, proposed);
        if (after > 0 && after >= std::min(quality_before[i], kQualityFloor)) continue;
        for (const Index v : quad)
          if (zone_slot[v] != kInvalidIndex && accepted[zone_slot[v]]) refuse.push_back(zone_slot[v]);
      }
      if (refuse.empty()) break;
      for (const Index slot : refuse) rejected += accepted[slot], accepted[slot] = 0;
    }
    double largest_move = 0;
    for (std::size_t i = 0; i < zone.size(); ++i) {
      if (!accepted[i]) continue;
      largest_move = std::max(largest_move, (proposal[i] - mesh.points[zone[i]]).norm());
      mesh.points[zone[i]] = proposal[i];
    }
    stats.iterations = iteration + 1;
    if (largest_move <= 1e-9 * scale) break;
  }
  stats.rejected_moves = rejected;
  return stats;
}

}  // namespace structmesh
