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
#include <atomic>
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
  // The zone: rings from the separator points over this piece's own quads, one sweep
  // over the quads per ring (a ring is the set of edge neighbours of the ring before
  // not yet reached). The shortest edge path from a vertex to a separator stays inside
  // the vertex's part (a part is bounded by separators and the region boundary), so the
  // rings are the same as on the whole mesh. No vertex-to-quad table of the whole
  // mesh: at 20M quads building one took 1.3 s, most of the relaxation's setup.
  std::vector<std::int32_t> ring(n, -1);
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t v) {
    if (piece.separator[v]) ring[v] = 0;
  });
  for (int r = 1; r <= options.rings; ++r) {
    // Concurrent writers store the same value r, and no reader of ring r - 1 can
    // mistake it: atomic_ref only keeps that race defined.
    const bool grew = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, piece.own_quads), false,
        [&](const tbb::blocked_range<std::size_t>& range, bool any) {
          for (std::size_t q = range.begin(); q != range.end(); ++q) {
            const auto& quad = piece.quads[q];
            for (int k = 0; k < 4; ++k) {
              if (std::atomic_ref<std::int32_t>(ring[quad[k]]).load(std::memory_order_relaxed) != r - 1) continue;
              for (const Index w : {quad[(k + 1) % 4], quad[(k + 3) % 4]}) {
                std::atomic_ref<std::int32_t> ring_w(ring[w]);
                if (ring_w.load(std::memory_order_relaxed) < 0) {
                  ring_w.store(r, std::memory_order_relaxed);
                  any = true;
                }
              }
            }
          }
          return any;
        },
        [](bool a, bool b) { return a || b; });
    if (!grew) break;
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
  std::vector<Index> moving_vertices;  // every copy that may move, owned or not
  for (Index v = 0; v < n; ++v)
    if (moving[v]) moving_vertices.push_back(v);
  const auto slot_of = [&](Index v) {
    return static_cast<Index>(std::lower_bound(moving_vertices.begin(), moving_vertices.end(), v) -
                              moving_vertices.begin());
  };
  // Every quad of a moving vertex is a zone quad: the zone quads around each moving
  // vertex (indices into zone_quads, ascending).
  CompressedRows zone_quads_of;
  {
    zone_quads_of.offsets.assign(moving_vertices.size() + 1, 0);
    for (const Index q : zone_quads)
      for (const Index v : piece.quads[q])
        if (moving[v]) ++zone_quads_of.offsets[slot_of(v) + 1];
    std::inclusive_scan(zone_quads_of.offsets.begin(), zone_quads_of.offsets.end(), zone_quads_of.offsets.begin());
    zone_quads_of.items.resize(zone_quads_of.offsets.back());
    std::vector<Index> fill(zone_quads_of.offsets.begin(), zone_quads_of.offsets.end() - 1);
    for (std::size_t i = 0; i < zone_quads.size(); ++i)
      for (const Index v : piece.quads[zone_quads[i]])
        if (moving[v]) zone_quads_of.items[fill[slot_of(v)]++] = static_cast<Index>(i);
  }

  // Neighbours of the zone vertices, each once, in ascending global order: counted,
  // then filled, each row in parallel (the same rows as one serial pass).
  CompressedRows neighbours;
  {
    const auto sorted_row = [&](Index v, std::vector<Index>& row) {
      row.clear();
      for (const Index i : zone_quads_of.row(slot_of(v))) {
        const auto& quad = piece.quads[zone_quads[i]];
        for (int k = 0; k < 4; ++k)
          if (quad[k] == v) {
            row.push_back(quad[(k + 1) % 4]);
            row.push_back(quad[(k + 3) % 4]);
          }
      }
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
  std::vector<std::uint8_t> before_and;
  static const Vec3 up(0, 0, 1);
  const auto jacobian = [&](const std::array<Index, 4>& quad, auto&& position) {
    std::array<Vec3, 4> corners;
    for (int k = 0; k < 4; ++k) corners[k] = position(quad[k]);
    return quad_scaled_jacobian(corners, &up);
  };
  // Only moving vertices ever get a proposal or move: the others keep accepted = 0 for
  // good (resetting all n points in every sweep was a serial pass over the whole mesh,
  // a fifth of the relaxation on the Key at 2M quads), and their proposals are never
  // read, so on one process they are never written either (a copy of all points was
  // 1.3 s at 20M quads, page faults mostly). The exchange sends every shared point's
  // proposal, so there they start as the points.
  std::vector<Vec3> proposal = comm.exchanges ? piece.points : std::vector<Vec3>(n);
  std::vector<std::uint8_t> accepted(moving);
  std::vector<double> quality_before(zone_quads.size()), quality_after(zone_quads.size());
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
    // A zone quad's quality now is the value its last refusal check computed in the
    // iteration before (nothing it reads changed after that check), so only the first
    // iteration computes it (this halved the scaled Jacobians the relaxation evaluates).
    if (iteration == 0)
      tbb::parallel_for(std::size_t{0}, zone_quads.size(), [&](std::size_t i) {
        quality_before[i] = jacobian(piece.quads[zone_quads[i]], [&](Index v) { return piece.points[v]; });
      });
    else
      quality_before.swap(quality_after);
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
        quality_after[check[i]] = after;
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
        for (const Index i : zone_quads_of.row(slot_of(v))) check.push_back(i);
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
