// relax_near_separators() and relax_piece(): the post-processing of §3.3.2. After
// the parts are glued, the rows of neighbouring parts meet at the separators with a
// kink; Laplacian sweeps over the vertices within five rings of the separators
// smooth it.
//
// Each sweep is a Jacobi step: every zone vertex proposes the mean of its edge
// neighbours, summed in ascending global vertex order, from the positions before
// the sweep. Then, in synchronous rounds, every quad that the proposals would invert
// (or push below the quality floor) refuses the proposals of all its moving
// vertices, until no quad objects. Nothing depends on the order in which vertices
// or quads are visited, so the result is bit-identical for any thread count and for
// any split of the mesh over processes: relax_piece() runs the same steps on one
// process's piece, with the exchanges of shared vertices done by RelaxComm.
#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/quality.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace structmesh {

namespace {

// A move may lower an incident quad's scaled Jacobian, as plain Laplacian smoothing
// does, but not below this floor (nor below the quad's current value when that is
// lower already), and never to an inverted quad.
constexpr double kQualityFloor = 0.7;

}  // namespace

RelaxStats relax_piece(RelaxPiece& piece, const RelaxOptions& options, const RelaxComm& comm) {
  if (options.rings < 0 || options.iterations < 0)
    throw InputError("relax_near_separators: negative rings or iterations");
  const std::size_t n = piece.points.size();
  if (piece.fixed.size() != n || piece.separator.size() != n || piece.owned.size() != n || piece.global.size() != n)
    throw InputError("relax_near_separators: fixed/separator/owned/global must have one entry per point");
  if (piece.own_quads > piece.quads.size()) throw InputError("relax_near_separators: own_quads exceeds the quads");
  const CompressedRows vertex_quads = build_vertex_elements(piece.quads, n);

  const auto for_each_edge_neighbour = [&](Index v, bool own_only, auto&& visit) {
    for (const Index q : vertex_quads.row(v)) {
      if (own_only && q >= piece.own_quads) continue;
      const auto& quad = piece.quads[q];
      for (int k = 0; k < 4; ++k)
        if (quad[k] == v) {
          visit(quad[(k + 1) % 4]);
          visit(quad[(k + 3) % 4]);
        }
    }
  };

  // The zone: breadth-first rings from the separator points over this piece's own
  // quads. The shortest edge path from a vertex to a separator stays inside the
  // vertex's part (a part is bounded by separators and the region boundary), so the
  // rings are the same as on the whole mesh.
  std::vector<std::int32_t> ring(n, -1);
  std::vector<Index> frontier, next;
  for (Index v = 0; v < n; ++v)
    if (piece.separator[v]) ring[v] = 0, frontier.push_back(v);
  for (int r = 1; r <= options.rings && !frontier.empty(); ++r) {
    next.clear();
    for (const Index v : frontier)
      for_each_edge_neighbour(v, true, [&](Index w) {
        if (ring[w] < 0) ring[w] = r, next.push_back(w);
      });
    std::sort(next.begin(), next.end());
    frontier.swap(next);
  }
  // Moving vertices: in the zone and not on the region boundary; their owners
  // decide, the other copies learn it.
  std::vector<std::uint8_t> moving(n, 0);
  for (Index v = 0; v < n; ++v) moving[v] = piece.owned[v] && ring[v] >= 0 && !piece.fixed[v] ? 1 : 0;
  comm.sync_flags(moving);
  std::vector<Index> zone;  // owned moving vertices
  for (Index v = 0; v < n; ++v)
    if (moving[v] && piece.owned[v]) zone.push_back(v);

  RelaxStats stats;
  stats.moved_vertices = comm.sum(zone.size());

  // Neighbours of the zone vertices, each once, in ascending global order: counted,
  // then filled, each row in parallel (the same rows as one serial pass).
  CompressedRows neighbours;
  {
    const auto sorted_row = [&](Index v, std::vector<Index>& row) {
      row.clear();
      for_each_edge_neighbour(v, false, [&](Index w) { row.push_back(w); });
      std::sort(row.begin(), row.end(), [&](Index a, Index b) { return piece.global[a] < piece.global[b]; });
      row.erase(std::unique(row.begin(), row.end()), row.end());
    };
    std::vector<Index> counts(zone.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, zone.size()),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        std::vector<Index> row;
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          sorted_row(zone[i], row);
                          counts[i] = static_cast<Index>(row.size());
                        }
                      });
    neighbours.offsets.resize(zone.size() + 1);
    neighbours.offsets[0] = 0;
    std::inclusive_scan(counts.begin(), counts.end(), neighbours.offsets.begin() + 1);
    neighbours.items.resize(neighbours.offsets.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, zone.size()),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        std::vector<Index> row;
                        for (std::size_t i = range.begin(); i != range.end(); ++i) {
                          sorted_row(zone[i], row);
                          std::copy(row.begin(), row.end(), neighbours.items.begin() + neighbours.offsets[i]);
                        }
                      });
  }
  // The quads that can change: those with a moving vertex (flagged in parallel, then
  // listed in order).
  std::vector<Index> zone_quads;
  {
    std::vector<std::uint8_t> touched(piece.quads.size(), 0);
    tbb::parallel_for(std::size_t{0}, piece.quads.size(), [&](std::size_t q) {
      const auto& quad = piece.quads[q];
      touched[q] = moving[quad[0]] | moving[quad[1]] | moving[quad[2]] | moving[quad[3]];
    });
    for (Index q = 0; q < piece.quads.size(); ++q)
      if (touched[q]) zone_quads.push_back(q);
  }

  std::vector<Index> zone_slot(piece.quads.size(), kInvalidIndex);  // quad -> index in zone_quads
  for (std::size_t i = 0; i < zone_quads.size(); ++i) zone_slot[zone_quads[i]] = static_cast<Index>(i);
  std::vector<Index> moving_vertices;  // every copy that may move, owned or not
  for (Index v = 0; v < n; ++v)
    if (moving[v]) moving_vertices.push_back(v);
  std::vector<std::uint8_t> before_and;
  static const Vec3 up(0, 0, 1);
  const auto jacobian = [&](const std::array<Index, 4>& quad, auto&& position) {
    std::array<Vec3, 4> corners;
    for (int k = 0; k < 4; ++k) corners[k] = position(quad[k]);
    return quad_scaled_jacobian(corners, &up);
  };
  // Only moving vertices ever get a proposal or move: the others keep proposal =
  // position and accepted = 0 for good (resetting all n points in every sweep was a
  // serial pass over the whole mesh, a fifth of the relaxation on the Key at 2M quads).
  std::vector<Vec3> proposal(piece.points.begin(), piece.points.end());
  std::vector<std::uint8_t> accepted(moving);
  std::vector<double> quality_before(zone_quads.size());
  std::size_t refused = 0;
  const double tolerance = 1e-9 * piece.size;
  for (int iteration = 0; iteration < options.iterations && stats.moved_vertices > 0; ++iteration) {
    tbb::parallel_for(std::size_t{0}, moving_vertices.size(), [&](std::size_t i) {
      const Index v = moving_vertices[i];
      proposal[v] = piece.points[v];
      accepted[v] = 1;
    });
    tbb::parallel_for(std::size_t{0}, zone.size(), [&](std::size_t i) {
      Vec3 sum = Vec3::Zero();
      const auto row = neighbours.row(i);
      for (const Index w : row) sum += piece.points[w];
      proposal[zone[i]] = sum / static_cast<double>(row.size());
    });
    comm.sync_points(proposal);
    tbb::parallel_for(std::size_t{0}, zone_quads.size(), [&](std::size_t i) {
      quality_before[i] = jacobian(piece.quads[zone_quads[i]], [&](Index v) { return piece.points[v]; });
    });
    const auto proposed = [&](Index v) { return accepted[v] ? proposal[v] : piece.points[v]; };
    // Refusal rounds: each round reads the previous round's acceptances only. The
    // first round checks every zone quad, later ones only the quads around the
    // vertices whose acceptance changed.
    std::vector<Index> check(zone_quads.size());
    std::iota(check.begin(), check.end(), Index{0});
    std::vector<std::uint8_t> bad;
    std::vector<Index> refuse, changed;
    while (true) {
      bad.assign(check.size(), 0);
      tbb::parallel_for(std::size_t{0}, check.size(), [&](std::size_t i) {
        const double after = jacobian(piece.quads[zone_quads[check[i]]], proposed);
        bad[i] = !(after > 0 && after >= std::min(quality_before[check[i]], kQualityFloor));
      });
      refuse.clear();
      for (std::size_t i = 0; i < check.size(); ++i)
        if (bad[i])
          for (const Index v : piece.quads[zone_quads[check[i]]])
            if (accepted[v]) refuse.push_back(v);
      for (const Index v : refuse) accepted[v] = 0;
      // A vertex stays accepted only if no copy refused it.
      if (!comm.any(!refuse.empty())) break;
      changed = refuse;
      if (comm.exchanges) {
        before_and.assign(accepted.begin(), accepted.end());
        comm.and_flags(accepted);
        for (const Index v : moving_vertices)
          if (before_and[v] != accepted[v]) changed.push_back(v);
      }
      check.clear();
      for (const Index v : changed)
        for (const Index q : vertex_quads.row(v))
          if (zone_slot[q] != kInvalidIndex) check.push_back(zone_slot[q]);
      std::sort(check.begin(), check.end());
      check.erase(std::unique(check.begin(), check.end()), check.end());
    }
    // The moves, in parallel: a maximum and a count do not depend on the order.
    const auto [largest_move, refused_now] = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, zone.size()), std::pair<double, std::size_t>{0.0, 0},
        [&](const tbb::blocked_range<std::size_t>& range, std::pair<double, std::size_t> partial) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const Index v = zone[i];
            if (!accepted[v]) {
              ++partial.second;
              continue;
            }
            partial.first = std::max(partial.first, (proposal[v] - piece.points[v]).norm());
            piece.points[v] = proposal[v];
          }
          return partial;
        },
        [](const std::pair<double, std::size_t>& a, const std::pair<double, std::size_t>& b) {
          return std::pair<double, std::size_t>{std::max(a.first, b.first), a.second + b.second};
        });
    refused += refused_now;
    comm.sync_points(piece.points);
    stats.iterations = iteration + 1;
    if (comm.max(largest_move) <= tolerance) break;
  }
  stats.rejected_moves = comm.sum(refused);
  return stats;
}

RelaxStats relax_near_separators(MergedMesh& merged, const RelaxOptions& options) {
  const std::size_t n = merged.mesh.points.size();
  if (merged.fixed.size() != n || merged.separator.size() != n)
    throw InputError("relax_near_separators: fixed/separator flags must have one entry per point");
  RelaxPiece piece;
  piece.points = std::move(merged.mesh.points);
  piece.quads = std::move(merged.mesh.quads);
  piece.own_quads = piece.quads.size();
  piece.global.resize(n);
  std::iota(piece.global.begin(), piece.global.end(), Index{0});
  piece.owned.assign(n, 1);
  piece.fixed = merged.fixed;
  piece.separator = merged.separator;
  piece.size = merged.size;
  RelaxStats stats;
  try {
    stats = relax_piece(piece, options, RelaxComm{});
  } catch (...) {
    merged.mesh.points = std::move(piece.points);
    merged.mesh.quads = std::move(piece.quads);
    throw;
  }
  merged.mesh.points = std::move(piece.points);
  merged.mesh.quads = std::move(piece.quads);
  return stats;
}

}  // namespace structmesh
