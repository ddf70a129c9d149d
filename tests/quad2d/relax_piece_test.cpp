// relax_piece() on a mesh split over simulated processes (threads exchanging through
// shared memory) must give bit-identically the mesh relax_near_separators() gives:
// the property the MPI driver relies on.
#include "structmesh/quad2d.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <barrier>
#include <cmath>
#include <map>
#include <thread>

namespace structmesh {
namespace {

// A k x k block of parts, each an n x n structured grid of the unit square scaled
// by 1/k, with interior points jittered so that relaxation has work to do.
MergedMesh jittered_blocks(int k, int n, double jitter) {
  MergedMesh merged;
  const int size = k * n;
  const double h = 1.0 / size;
  const auto id = [&](int i, int j) { return static_cast<Index>(j * (size + 1) + i); };
  for (int j = 0; j <= size; ++j)
    for (int i = 0; i <= size; ++i) {
      const bool boundary = i == 0 || j == 0 || i == size || j == size;
      const bool separator = !boundary && (i % n == 0 || j % n == 0);
      Vec3 p(i * h, j * h, 0);
      if (!boundary) {
        const double t = static_cast<double>(id(i, j));
        p.x() += jitter * h * std::sin(12.9898 * t);
        p.y() += jitter * h * std::cos(78.233 * t);
      }
      merged.mesh.points.push_back(p);
      merged.fixed.push_back(boundary ? 1 : 0);
      merged.separator.push_back(separator ? 1 : 0);
    }
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      merged.mesh.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      merged.part_of_quad.push_back((j / n) * k + i / n);
    }
  merged.size = h;
  return merged;
}

// Shared memory standing in for MPI: values by global id, one slot per process.
struct SharedMemory {
  explicit SharedMemory(int processes, std::size_t points)
      : barrier(processes),
        positions(points),
        flags(static_cast<std::size_t>(processes), std::vector<std::uint8_t>(points, 1)),
        owner_flags(points),
        bools(static_cast<std::size_t>(processes)),
        doubles(static_cast<std::size_t>(processes)),
        sizes(static_cast<std::size_t>(processes)) {}
  std::barrier<> barrier;
  std::vector<Vec3> positions;
  std::vector<std::vector<std::uint8_t>> flags;
  std::vector<std::uint8_t> owner_flags;
  std::vector<std::uint8_t> bools;
  std::vector<double> doubles;
  std::vector<std::size_t> sizes;
};

RelaxComm shared_comm(SharedMemory& shared, const RelaxPiece& piece, int process) {
  RelaxComm comm;
  comm.exchanges = true;
  const auto r = static_cast<std::size_t>(process);
  comm.sync_points = [&shared, &piece](std::vector<Vec3>& values) {
    for (std::size_t v = 0; v < values.size(); ++v)
      if (piece.owned[v]) shared.positions[piece.global[v]] = values[v];
    shared.barrier.arrive_and_wait();
    for (std::size_t v = 0; v < values.size(); ++v)
      if (!piece.owned[v]) values[v] = shared.positions[piece.global[v]];
    shared.barrier.arrive_and_wait();
  };
  comm.sync_flags = [&shared, &piece](std::vector<std::uint8_t>& values) {
    for (std::size_t v = 0; v < values.size(); ++v)
      if (piece.owned[v]) shared.owner_flags[piece.global[v]] = values[v];
    shared.barrier.arrive_and_wait();
    for (std::size_t v = 0; v < values.size(); ++v)
      if (!piece.owned[v]) values[v] = shared.owner_flags[piece.global[v]];
    shared.barrier.arrive_and_wait();
  };
  comm.and_flags = [&shared, &piece, r](std::vector<std::uint8_t>& values) {
    std::fill(shared.flags[r].begin(), shared.flags[r].end(), 1);
    for (std::size_t v = 0; v < values.size(); ++v) shared.flags[r][piece.global[v]] = values[v];
    shared.barrier.arrive_and_wait();
    for (std::size_t v = 0; v < values.size(); ++v)
      for (const auto& other : shared.flags) values[v] = values[v] && other[piece.global[v]] ? 1 : 0;
    shared.barrier.arrive_and_wait();
  };
  comm.any = [&shared, r](bool value) {
    shared.bools[r] = value;
    shared.barrier.arrive_and_wait();
    const bool any = std::any_of(shared.bools.begin(), shared.bools.end(), [](std::uint8_t b) { return b != 0; });
    shared.barrier.arrive_and_wait();
    return any;
  };
  comm.max = [&shared, r](double value) {
    shared.doubles[r] = value;
    shared.barrier.arrive_and_wait();
    const double result = *std::max_element(shared.doubles.begin(), shared.doubles.end());
    shared.barrier.arrive_and_wait();
    return result;
  };
  comm.sum = [&shared, r](std::size_t value) {
    shared.sizes[r] = value;
    shared.barrier.arrive_and_wait();
    std::size_t result = 0;
    for (const std::size_t s : shared.sizes) result += s;
    shared.barrier.arrive_and_wait();
    return result;
  };
  return comm;
}

// Process `process`'s piece when part p goes to process part_process[p]: its quads,
// then the other processes' quads touching a separator point of its own quads.
RelaxPiece make_piece(const MergedMesh& merged, const std::vector<int>& part_process, int process) {
  const std::size_t n = merged.mesh.points.size();
  std::vector<int> owner(n, 1 << 30);
  for (std::size_t q = 0; q < merged.mesh.quads.size(); ++q)
    for (const Index v : merged.mesh.quads[q]) owner[v] = std::min(owner[v], part_process[merged.part_of_quad[q]]);
  std::vector<std::uint8_t> mine(n, 0);
  std::vector<std::size_t> own, ghost;
  for (std::size_t q = 0; q < merged.mesh.quads.size(); ++q)
    if (part_process[merged.part_of_quad[q]] == process) {
      own.push_back(q);
      for (const Index v : merged.mesh.quads[q]) mine[v] = 1;
    }
  for (std::size_t q = 0; q < merged.mesh.quads.size(); ++q) {
    if (part_process[merged.part_of_quad[q]] == process) continue;
    for (const Index v : merged.mesh.quads[q])
      if (mine[v] && merged.separator[v]) {
        ghost.push_back(q);
        break;
      }
  }
  RelaxPiece piece;
  for (const auto* list : {&own, &ghost})
    for (const std::size_t q : *list)
      for (const Index v : merged.mesh.quads[q]) piece.global.push_back(v);
  std::sort(piece.global.begin(), piece.global.end());
  piece.global.erase(std::unique(piece.global.begin(), piece.global.end()), piece.global.end());
  const auto local = [&](Index g) {
    return static_cast<Index>(std::lower_bound(piece.global.begin(), piece.global.end(), g) - piece.global.begin());
  };
  for (const Index g : piece.global) {
    piece.points.push_back(merged.mesh.points[g]);
    piece.owned.push_back(owner[g] == process ? 1 : 0);
    piece.fixed.push_back(merged.fixed[g]);
    piece.separator.push_back(merged.separator[g]);
  }
  for (const auto* list : {&own, &ghost})
    for (const std::size_t q : *list) {
      const auto& quad = merged.mesh.quads[q];
      piece.quads.push_back({local(quad[0]), local(quad[1]), local(quad[2]), local(quad[3])});
    }
  piece.own_quads = own.size();
  piece.size = merged.size;
  return piece;
}

class RelaxPieceSplit : public ::testing::TestWithParam<int> {};

TEST_P(RelaxPieceSplit, SplitOverProcessesEqualsTheWholeMeshBitForBit) {
  const int processes = GetParam();
  const MergedMesh original = jittered_blocks(3, 6, 0.45);
  MergedMesh whole = original;
  const RelaxStats whole_stats = relax_near_separators(whole);
  ASSERT_GT(whole_stats.moved_vertices, 0U);
  ASSERT_GT(whole_stats.rejected_moves, 0U);  // the refusal exchange is exercised
  ASSERT_EQ(quad_quality(whole.mesh).inverted, 0U);

  // Parts 0..8 to processes round-robin, so every process has neighbours elsewhere.
  std::vector<int> part_process(9);
  for (int p = 0; p < 9; ++p) part_process[p] = p % processes;
  std::vector<RelaxPiece> pieces;
  for (int r = 0; r < processes; ++r) pieces.push_back(make_piece(original, part_process, r));
  SharedMemory shared(processes, original.mesh.points.size());
  std::vector<RelaxStats> stats(static_cast<std::size_t>(processes));
  std::vector<std::thread> threads;
  for (int r = 0; r < processes; ++r)
    threads.emplace_back([&, r] {
      const RelaxComm comm = shared_comm(shared, pieces[r], r);
      stats[r] = relax_piece(pieces[r], RelaxOptions{}, comm);
    });
  for (std::thread& t : threads) t.join();

  for (int r = 0; r < processes; ++r) {
    EXPECT_EQ(stats[r].moved_vertices, whole_stats.moved_vertices);
    EXPECT_EQ(stats[r].iterations, whole_stats.iterations);
    EXPECT_EQ(stats[r].rejected_moves, whole_stats.rejected_moves);
    for (std::size_t v = 0; v < pieces[r].points.size(); ++v)
      ASSERT_EQ(pieces[r].points[v], whole.mesh.points[pieces[r].global[v]])
          << "process " << r << " point " << pieces[r].global[v];
  }
}

INSTANTIATE_TEST_SUITE_P(Processes, RelaxPieceSplit, ::testing::Values(1, 2, 4));

}  // namespace
}  // namespace structmesh
