// `mpirun -np N structmesh quad2d ...`: the distributed pipeline of §3.3.
//
// Every rank computes the same partition and samples (deterministic, and cheap
// next to the meshing), assigns parts to ranks by predicted work (area / size^2,
// longest first onto the least loaded rank), paves its own parts with its threads,
// numbers points exactly as merge_parts() does (samples first, then each part's
// interior points in part order), and relaxes with relax_piece(): each rank holds
// its own quads plus the other ranks' quads around the separator points it shares,
// and exchanges positions, proposals and refusals of shared points with their
// owners. The result is bit-identical to the threaded run with the same --parts.
#include "quad2d_command.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/quality.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <numeric>

namespace structmesh::cli {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

void check_mpi(int code, const char* what) {
  if (code != MPI_SUCCESS) throw Error(std::string("MPI: ") + what + " failed");
}

// MPI_Init on construction, MPI_Finalize on destruction.
class MpiSession {
 public:
  MpiSession() {
    int provided = 0;
    check_mpi(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiSession() { MPI_Finalize(); }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
};

template <typename T>
MPI_Datatype mpi_type();
template <>
MPI_Datatype mpi_type<double>() {
  return MPI_DOUBLE;
}
template <>
MPI_Datatype mpi_type<std::uint8_t>() {
  return MPI_UINT8_T;
}
template <>
MPI_Datatype mpi_type<std::uint32_t>() {
  return MPI_UINT32_T;
}

// All-to-all of variable-length blocks: send[r] goes to rank r; returns what each
// rank sent here, concatenated in rank order (with per-rank counts).
template <typename T>
std::vector<T> all_to_all(const std::vector<std::vector<T>>& send, std::vector<int>& received_counts) {
  const int ranks = static_cast<int>(send.size());
  std::vector<int> send_counts(ranks), send_displs(ranks + 1, 0), recv_displs(ranks + 1, 0);
  received_counts.assign(ranks, 0);
  for (int r = 0; r < ranks; ++r) send_counts[r] = static_cast<int>(send[r].size());
  check_mpi(MPI_Alltoall(send_counts.data(), 1, MPI_INT, received_counts.data(), 1, MPI_INT, MPI_COMM_WORLD),
            "MPI_Alltoall");
  std::vector<T> flat;
  for (int r = 0; r < ranks; ++r) {
    send_displs[r + 1] = send_displs[r] + send_counts[r];
    recv_displs[r + 1] = recv_displs[r] + received_counts[r];
    flat.insert(flat.end(), send[r].begin(), send[r].end());
  }
  std::vector<T> received(static_cast<std::size_t>(recv_displs[ranks]));
  check_mpi(MPI_Alltoallv(flat.data(), send_counts.data(), send_displs.data(), mpi_type<T>(), received.data(),
                          received_counts.data(), recv_displs.data(), mpi_type<T>(), MPI_COMM_WORLD),
            "MPI_Alltoallv");
  return received;
}

// Which local points each rank needs from this one (owner -> copies) and where the
// copies here come from, both in ascending global order per rank.
struct Exchange {
  std::vector<std::vector<Index>> send;  // per rank: owned local points whose copies live there
  std::vector<std::vector<Index>> recv;  // per rank: local copies owned there
};

Exchange build_exchange(const RelaxPiece& piece, const std::vector<int>& owner_rank, int ranks) {
  Exchange exchange;
  exchange.recv.assign(ranks, {});
  exchange.send.assign(ranks, {});
  std::vector<std::vector<std::uint32_t>> wanted(ranks);
  for (Index v = 0; v < piece.points.size(); ++v) {
    if (piece.owned[v]) continue;
    exchange.recv[owner_rank[v]].push_back(v);  // local order = ascending global order
    wanted[owner_rank[v]].push_back(piece.global[v]);
  }
  std::vector<int> counts;
  const std::vector<std::uint32_t> asked = all_to_all(wanted, counts);
  std::size_t at = 0;
  for (int r = 0; r < ranks; ++r)
    for (int i = 0; i < counts[r]; ++i, ++at) {
      const auto it = std::lower_bound(piece.global.begin(), piece.global.end(), asked[at]);
      if (it == piece.global.end() || *it != asked[at]) throw Error("MPI: a rank asked for a point this rank lacks");
      exchange.send[r].push_back(static_cast<Index>(it - piece.global.begin()));
    }
  return exchange;
}

// Owner values to the copies (component-wise for Vec3).
template <typename T, typename Get, typename Set>
void push_to_copies(const Exchange& exchange, int components, Get get, Set set) {
  const int ranks = static_cast<int>(exchange.send.size());
  std::vector<std::vector<T>> send(ranks);
  for (int r = 0; r < ranks; ++r)
    for (const Index v : exchange.send[r])
      for (int c = 0; c < components; ++c) send[r].push_back(get(v, c));
  std::vector<int> counts;
  const std::vector<T> received = all_to_all(send, counts);
  std::size_t at = 0;
  for (int r = 0; r < ranks; ++r)
    for (const Index v : exchange.recv[r])
      for (int c = 0; c < components; ++c) set(v, c, received[at++]);
}

RelaxComm make_comm(const Exchange& exchange) {
  RelaxComm comm;
  comm.exchanges = true;
  comm.sync_points = [&exchange](std::vector<Vec3>& values) {
    push_to_copies<double>(
        exchange, 3, [&](Index v, int c) { return values[v][c]; }, [&](Index v, int c, double x) { values[v][c] = x; });
  };
  comm.sync_flags = [&exchange](std::vector<std::uint8_t>& flags) {
    push_to_copies<std::uint8_t>(
        exchange, 1, [&](Index v, int) { return flags[v]; }, [&](Index v, int, std::uint8_t x) { flags[v] = x; });
  };
  comm.and_flags = [&exchange](std::vector<std::uint8_t>& flags) {
    // Copies to owners (the exchange reversed), AND at the owner, then back out.
    const int ranks = static_cast<int>(exchange.send.size());
    std::vector<std::vector<std::uint8_t>> send(ranks);
    for (int r = 0; r < ranks; ++r)
      for (const Index v : exchange.recv[r]) send[r].push_back(flags[v]);
    std::vector<int> counts;
    const std::vector<std::uint8_t> received = all_to_all(send, counts);
    std::size_t at = 0;
    for (int r = 0; r < ranks; ++r)
      for (const Index v : exchange.send[r]) {
        const std::uint8_t copy = received[at++];  // read before the && (no short circuit past it)
        flags[v] = flags[v] && copy ? 1 : 0;
      }
    push_to_copies<std::uint8_t>(
        exchange, 1, [&](Index v, int) { return flags[v]; }, [&](Index v, int, std::uint8_t x) { flags[v] = x; });
  };
  comm.any = [](bool value) {
    int local = value ? 1 : 0, global = 0;
    MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
    return global != 0;
  };
  comm.max = [](double value) {
    double global = 0;
    MPI_Allreduce(&value, &global, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    return global;
  };
  comm.sum = [](std::size_t value) {
    unsigned long long local = value, global = 0;
    MPI_Allreduce(&local, &global, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    return static_cast<std::size_t>(global);
  };
  return comm;
}

// Rank 0's size, part areas, samples and part loops to every rank (the partition's
// geometry and metrics stay on rank 0, which writes the report).
void broadcast_setup(Quad2dSetup& setup, bool root) {
  std::vector<double> reals;
  std::vector<std::uint32_t> integers;
  std::vector<std::uint8_t> flags;
  if (root) {
    const SampledPartition& sampled = setup.sampled;
    reals.push_back(setup.size);
    reals.insert(reals.end(), setup.partition.part_areas.begin(), setup.partition.part_areas.end());
    for (const Vec2& p : sampled.points) reals.insert(reals.end(), {p.x(), p.y()});
    integers.push_back(static_cast<std::uint32_t>(sampled.part_loops.size()));
    integers.push_back(static_cast<std::uint32_t>(sampled.points.size()));
    for (const auto& loops : sampled.part_loops) {
      integers.push_back(static_cast<std::uint32_t>(loops.size()));
      for (const auto& loop : loops) {
        integers.push_back(static_cast<std::uint32_t>(loop.size()));
        integers.insert(integers.end(), loop.begin(), loop.end());
      }
    }
    for (const auto& corners : sampled.part_corners)
      for (const std::int64_t c : corners) integers.push_back(static_cast<std::uint32_t>(c + 1));  // 0: none
    for (std::size_t p = 0; p < sampled.part_loops.size(); ++p) {
      const PolarBlocks& blocks = sampled.part_polar[p];
      integers.push_back(static_cast<std::uint32_t>(blocks.corners.size()));
      for (std::size_t i = 0; i < blocks.corners.size(); ++i)
        integers.insert(integers.end(), {static_cast<std::uint32_t>(blocks.corners[i]),
                                         static_cast<std::uint32_t>(blocks.splits[i]), blocks.chord_segments[i]});
    }
    flags = sampled.on_region_boundary;
    flags.insert(flags.end(), sampled.fixed.begin(), sampled.fixed.end());
  }
  std::uint64_t lengths[3] = {reals.size(), integers.size(), flags.size()};
  MPI_Bcast(lengths, 3, MPI_UINT64_T, 0, MPI_COMM_WORLD);
  reals.resize(lengths[0]);
  integers.resize(lengths[1]);
  flags.resize(lengths[2]);
  MPI_Bcast(reals.data(), static_cast<int>(reals.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  MPI_Bcast(integers.data(), static_cast<int>(integers.size()), MPI_UINT32_T, 0, MPI_COMM_WORLD);
  MPI_Bcast(flags.data(), static_cast<int>(flags.size()), MPI_UINT8_T, 0, MPI_COMM_WORLD);
  if (root) return;
  SampledPartition& sampled = setup.sampled;
  const std::size_t parts = integers[0], points = integers[1];
  setup.size = reals[0];
  sampled.size = setup.size;
  setup.partition.part_areas.assign(reals.begin() + 1, reals.begin() + 1 + static_cast<std::ptrdiff_t>(parts));
  for (std::size_t i = 0; i < points; ++i)
    sampled.points.emplace_back(reals[1 + parts + 2 * i], reals[2 + parts + 2 * i]);
  std::size_t at = 2;
  sampled.part_loops.assign(parts, {});
  for (std::size_t p = 0; p < parts; ++p) {
    const std::size_t loops = integers[at++];
    for (std::size_t l = 0; l < loops; ++l) {
      const std::size_t length = integers[at++];
      sampled.part_loops[p].emplace_back(integers.begin() + static_cast<std::ptrdiff_t>(at),
                                         integers.begin() + static_cast<std::ptrdiff_t>(at + length));
      at += length;
    }
  }
  sampled.part_corners.assign(parts, {-1, -1, -1, -1});
  for (std::size_t p = 0; p < parts; ++p)
    for (int i = 0; i < 4; ++i) sampled.part_corners[p][i] = static_cast<std::int64_t>(integers[at++]) - 1;
  sampled.part_polar.assign(parts, {});
  for (std::size_t p = 0; p < parts; ++p) {
    const std::size_t k = integers[at++];
    PolarBlocks& blocks = sampled.part_polar[p];
    for (std::size_t i = 0; i < k; ++i) {
      blocks.corners.push_back(integers[at++]);
      blocks.splits.push_back(integers[at++]);
      blocks.chord_segments.push_back(integers[at++]);
    }
  }
  sampled.on_region_boundary.assign(flags.begin(), flags.begin() + static_cast<std::ptrdiff_t>(points));
  sampled.fixed.assign(flags.begin() + static_cast<std::ptrdiff_t>(points), flags.end());
}

}  // namespace

bool launched_by_mpirun() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr ||
         std::getenv("PMIX_RANK") != nullptr;
}

namespace {

int run_ranks(const MpiSession& mpi, const Quad2dSettings& settings, const Quad2dOptions& options,
              const Polygon2& region, const QuadPictureOptions& picture, const GlobalOptions& global) {
  const int rank = mpi.rank(), ranks = mpi.size();
  const bool root = rank == 0;
  const auto start = Clock::now();
  std::vector<std::pair<std::string, double>> stages;
  auto stage_start = Clock::now();
  const auto stage = [&](const char* name) {
    stages.emplace_back(name, seconds_since(stage_start));
    stage_start = Clock::now();
  };

  // 1. Rank 0 partitions and samples; every rank gets the samples and part areas.
  Quad2dOptions rank_options = options;
  rank_options.progress = options.progress && root;
  Quad2dSetup setup;
  if (root) setup = setup_quad2d(region, rank_options, static_cast<std::size_t>(ranks));
  broadcast_setup(setup, root);
  const SampledPartition& sampled = setup.sampled;
  const std::size_t parts = sampled.part_loops.size();
  const std::size_t sample_count = sampled.points.size();
  for (const auto& s : setup.stage_seconds) stages.push_back(s);
  stage_start = Clock::now();

  // 2. Parts to ranks by predicted work; pave this rank's parts.
  std::vector<double> work(parts);
  for (std::size_t p = 0; p < parts; ++p) work[p] = predicted_part_work(setup, p);
  const std::vector<std::int32_t> part_rank = assign_parts(work, static_cast<std::size_t>(ranks));
  std::vector<std::size_t> mine;
  for (std::size_t p = 0; p < parts; ++p)
    if (part_rank[p] == rank) mine.push_back(p);
  std::vector<double> part_seconds;
  std::vector<PavedPart> paved = pave_parts(setup, mine, options.paving, part_seconds, rank_options.progress);
  const double paving_seconds = seconds_since(stage_start);
  stage("paving");

  // 3. Global numbering: samples, then each part's interior points in part order.
  std::vector<std::uint64_t> interior(parts, 0), interior_all(parts, 0);
  std::vector<std::vector<Index>> maps(parts);
  for (const std::size_t p : mine) {
    maps[p] = part_boundary(sampled, p).second;
    interior[p] = paved[p].points.size() - maps[p].size();
  }
  MPI_Allreduce(interior.data(), interior_all.data(), static_cast<int>(parts), MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
  std::vector<std::uint64_t> offset(parts + 1, sample_count);
  for (std::size_t p = 0; p < parts; ++p) offset[p + 1] = offset[p] + interior_all[p];
  if (offset[parts] > kInvalidIndex) throw Error("quad2d: more points than 32-bit indices can address");
  const auto global_of = [&](std::size_t p, Index local) -> Index {
    return local < maps[p].size() ? maps[p][local] : static_cast<Index>(offset[p] + (local - maps[p].size()));
  };

  // Ranks using each sample (sorted, unique) and the owner of each sample (lowest).
  std::vector<std::vector<int>> sample_ranks(sample_count);
  for (std::size_t p = 0; p < parts; ++p)
    for (const auto& loop : sampled.part_loops[p])
      for (const Index i : loop) sample_ranks[i].push_back(part_rank[p]);
  for (auto& users : sample_ranks) {
    std::sort(users.begin(), users.end());
    users.erase(std::unique(users.begin(), users.end()), users.end());
  }

  // 4. Ghost quads: my quads touching a separator sample another rank also uses go there.
  std::vector<std::vector<std::uint32_t>> quad_out(ranks);  // 4 global ids + part per quad
  std::vector<std::vector<std::uint32_t>> point_id_out(ranks);
  std::vector<std::vector<double>> point_xyz_out(ranks);
  std::vector<int> targets;
  for (const std::size_t p : mine) {
    for (const auto& quad : paved[p].quads) {
      targets.clear();
      for (const Index local : quad) {
        const Index g = global_of(p, local);
        if (g >= sample_count || sampled.on_region_boundary[g]) continue;
        for (const int r : sample_ranks[g])
          if (r != rank) targets.push_back(r);
      }
      std::sort(targets.begin(), targets.end());
      targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
      for (const int r : targets) {
        for (const Index local : quad) {
          const Index g = global_of(p, local);
          quad_out[r].push_back(g);
          point_id_out[r].push_back(g);
          const Vec2& x = paved[p].points[local];
          point_xyz_out[r].insert(point_xyz_out[r].end(), {x.x(), x.y(), 0.0});
        }
        quad_out[r].push_back(static_cast<std::uint32_t>(p));
      }
    }
  }
  std::vector<int> counts;
  const std::vector<std::uint32_t> ghost_quads = all_to_all(quad_out, counts);
  const std::vector<std::uint32_t> ghost_ids = all_to_all(point_id_out, counts);
  const std::vector<double> ghost_xyz = all_to_all(point_xyz_out, counts);
  quad_out.clear();
  point_id_out.clear();
  point_xyz_out.clear();

  // 5. The local piece: points in ascending global order.
  RelaxPiece piece;
  std::vector<Index>& gids = piece.global;
  for (const std::size_t p : mine) {
    gids.insert(gids.end(), maps[p].begin(), maps[p].end());
    for (std::uint64_t g = offset[p]; g < offset[p + 1]; ++g) gids.push_back(static_cast<Index>(g));
  }
  gids.insert(gids.end(), ghost_ids.begin(), ghost_ids.end());
  std::sort(gids.begin(), gids.end());
  gids.erase(std::unique(gids.begin(), gids.end()), gids.end());
  const auto local_of = [&](Index g) {
    return static_cast<Index>(std::lower_bound(gids.begin(), gids.end(), g) - gids.begin());
  };
  const std::size_t n = gids.size();
  piece.points.assign(n, Vec3::Zero());
  piece.owned.assign(n, 0);
  piece.fixed.assign(n, 0);
  piece.separator.assign(n, 0);
  piece.size = setup.size;
  std::vector<int> owner_rank(n, rank);
  std::vector<std::int32_t> own_quad_part;
  for (const std::size_t p : mine) {
    for (Index local = 0; local < paved[p].points.size(); ++local) {
      const Vec2& x = paved[p].points[local];
      piece.points[local_of(global_of(p, local))] = Vec3(x.x(), x.y(), 0.0);
    }
    for (const auto& quad : paved[p].quads) {
      std::array<Index, 4> mapped{};
      for (int k = 0; k < 4; ++k) mapped[k] = local_of(global_of(p, quad[k]));
      piece.quads.push_back(mapped);
      own_quad_part.push_back(static_cast<std::int32_t>(p));
    }
  }
  piece.own_quads = piece.quads.size();
  paved.clear();
  for (std::size_t i = 0; i < ghost_ids.size(); ++i)
    piece.points[local_of(ghost_ids[i])] = Vec3(ghost_xyz[3 * i], ghost_xyz[3 * i + 1], ghost_xyz[3 * i + 2]);
  for (std::size_t i = 0; i + 5 <= ghost_quads.size(); i += 5) {
    piece.quads.push_back({local_of(ghost_quads[i]), local_of(ghost_quads[i + 1]), local_of(ghost_quads[i + 2]),
                           local_of(ghost_quads[i + 3])});
  }
  for (Index v = 0; v < n; ++v) {
    const Index g = gids[v];
    if (g < sample_count) {
      owner_rank[v] = sample_ranks[g].front();
      piece.fixed[v] = sampled.fixed[g];
      piece.separator[v] = sampled.on_region_boundary[g] ? 0 : 1;
    } else {
      const std::size_t p =
          static_cast<std::size_t>(std::upper_bound(offset.begin(), offset.end(), g) - offset.begin()) - 1;
      owner_rank[v] = part_rank[p];
    }
    piece.owned[v] = owner_rank[v] == rank ? 1 : 0;
  }
  stage("distribute");

  // 6. Relaxation with halo exchanges.
  const Exchange exchange = build_exchange(piece, owner_rank, ranks);
  const RelaxComm comm = make_comm(exchange);
  const RelaxStats relax = relax_piece(piece, options.relax, comm);
  stage("relax");

  // 7. Quality of the own quads, reduced over ranks.
  static const Vec3 up(0, 0, 1);
  std::vector<double> scaled_jacobian(piece.own_quads);
  double sums[3] = {0, 0, 0};  // count, sum, sum of squares
  double minimum = std::numeric_limits<double>::infinity(), area = 0;
  unsigned long long inverted = 0, singular = 0;
  for (std::size_t q = 0; q < piece.own_quads; ++q) {
    std::array<Vec3, 4> corners;
    for (int k = 0; k < 4; ++k) corners[k] = piece.points[piece.quads[q][k]];
    const double sj = quad_scaled_jacobian(corners, &up);
    scaled_jacobian[q] = sj;
    sums[0] += 1, sums[1] += sj, sums[2] += sj * sj;
    minimum = std::min(minimum, sj);
    inverted += sj <= 0;
    const Vec3 d0 = corners[2] - corners[0], d1 = corners[3] - corners[1];
    area += 0.5 * (d0.x() * d1.y() - d0.y() * d1.x());
  }
  {
    std::vector<std::uint32_t> valence(n, 0);
    for (const auto& quad : piece.quads)
      for (const Index v : quad) ++valence[v];
    for (Index v = 0; v < n; ++v) singular += piece.owned[v] && !piece.fixed[v] && valence[v] != 4;
  }
  double total_sums[3], total_min = 0, total_area = 0;
  unsigned long long total_inverted = 0, total_singular = 0;
  MPI_Allreduce(sums, total_sums, 3, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(&minimum, &total_min, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(&area, &total_area, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(&inverted, &total_inverted, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(&singular, &total_singular, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  std::vector<double> all_part_seconds(parts, 0);
  MPI_Allreduce(part_seconds.data(), all_part_seconds.data(), static_cast<int>(parts), MPI_DOUBLE, MPI_SUM,
                MPI_COMM_WORLD);
  std::vector<double> rank_paving(static_cast<std::size_t>(ranks), 0);
  MPI_Gather(&paving_seconds, 1, MPI_DOUBLE, rank_paving.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  stage("quality");

  // 8. Output: one .vtu piece per rank under each .pvtu; the other formats (and
  //    --merged) gather the whole mesh on rank 0 in merge_parts() order.
  std::vector<std::string> merged_outputs = settings.merged_outputs;
  for (const std::string& output : settings.outputs) {
    if (format_from_path(output) != FileFormat::Pvtu) {
      merged_outputs.push_back(output);
      continue;
    }
    const std::filesystem::path path(output);
    const std::string piece_name = path.stem().string() + "_" + std::to_string(rank) + ".vtu";
    MeshBundle bundle;
    std::vector<Index> compact(n, kInvalidIndex);
    for (std::size_t q = 0; q < piece.own_quads; ++q) {
      std::array<Index, 4> quad{};
      for (int k = 0; k < 4; ++k) {
        const Index v = piece.quads[q][k];
        if (compact[v] == kInvalidIndex) {
          compact[v] = static_cast<Index>(bundle.points.size());
          bundle.points.push_back(piece.points[v]);
        }
        quad[k] = compact[v];
      }
      bundle.quads.push_back(quad);
    }
    if (settings.lonlat_output) points_to_lonlat(region, bundle.points);
    bundle.quad_labels = own_quad_part;
    WriteOptions data;
    data.cell_data.push_back({.name = "part", .f64 = {}, .i32 = own_quad_part});
    data.cell_data.push_back({.name = "scaled_jacobian", .f64 = scaled_jacobian, .i32 = {}});
    write_mesh(path.parent_path() / piece_name, bundle, data);
    MPI_Barrier(MPI_COMM_WORLD);
    if (root) {
      std::vector<std::string> pieces;
      for (int r = 0; r < ranks; ++r) pieces.push_back(path.stem().string() + "_" + std::to_string(r) + ".vtu");
      write_file_atomic(path, write_pvtu(pieces, data));
    }
  }
  if (!merged_outputs.empty()) {
    // Owned points by global id, own quads (global ids) with their parts, part by part.
    std::vector<std::uint32_t> my_ids;
    std::vector<double> my_xyz;
    for (Index v = 0; v < n; ++v)
      if (piece.owned[v]) {
        my_ids.push_back(gids[v]);
        my_xyz.insert(my_xyz.end(), {piece.points[v].x(), piece.points[v].y(), piece.points[v].z()});
      }
    std::vector<std::uint32_t> my_quads;
    for (std::size_t q = 0; q < piece.own_quads; ++q) {
      for (const Index v : piece.quads[q]) my_quads.push_back(gids[v]);
      my_quads.push_back(static_cast<std::uint32_t>(own_quad_part[q]));
    }
    const auto gather = [&](const auto& mine_values, auto tag) {
      using T = decltype(tag);
      int count = static_cast<int>(mine_values.size());
      std::vector<int> all_counts(static_cast<std::size_t>(ranks)), displs(static_cast<std::size_t>(ranks) + 1, 0);
      MPI_Gather(&count, 1, MPI_INT, all_counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
      for (int r = 0; r < ranks; ++r) displs[r + 1] = displs[r] + (root ? all_counts[r] : 0);
      std::vector<T> all(root ? static_cast<std::size_t>(displs[ranks]) : 0);
      MPI_Gatherv(mine_values.data(), count, mpi_type<T>(), all.data(), all_counts.data(), displs.data(), mpi_type<T>(),
                  0, MPI_COMM_WORLD);
      return all;
    };
    const std::vector<std::uint32_t> all_ids = gather(my_ids, std::uint32_t{});
    const std::vector<double> all_xyz = gather(my_xyz, double{});
    const std::vector<std::uint32_t> all_quads = gather(my_quads, std::uint32_t{});
    if (root) {
      QuadMesh mesh;
      mesh.points.assign(offset[parts], Vec3::Zero());
      for (std::size_t i = 0; i < all_ids.size(); ++i)
        mesh.points[all_ids[i]] = Vec3(all_xyz[3 * i], all_xyz[3 * i + 1], all_xyz[3 * i + 2]);
      // Quads grouped by part in part order; within a part, in paving order (each
      // part comes whole from one rank, in its order).
      std::vector<std::size_t> part_start(parts + 1, 0);
      for (std::size_t i = 0; i < all_quads.size(); i += 5) ++part_start[all_quads[i + 4] + 1];
      for (std::size_t p = 0; p < parts; ++p) part_start[p + 1] += part_start[p];
      mesh.quads.resize(part_start[parts]);
      std::vector<std::int32_t> part_of_quad(part_start[parts]);
      std::vector<std::size_t> next(part_start.begin(), part_start.end() - 1);
      for (std::size_t i = 0; i < all_quads.size(); i += 5) {
        const std::size_t p = all_quads[i + 4];
        mesh.quads[next[p]] = {all_quads[i], all_quads[i + 1], all_quads[i + 2], all_quads[i + 3]};
        part_of_quad[next[p]++] = static_cast<std::int32_t>(p);
      }
      const QuadQuality quality = quad_quality(mesh);
      if (settings.lonlat_output) points_to_lonlat(region, mesh.points);
      write_outputs(merged_outputs, mesh, part_of_quad, quality.scaled_jacobian, picture);
    }
  }
  stage("write");
  stages.emplace_back("total", seconds_since(start));
  double peak = peak_rss_mb(), peak_max = 0;
  MPI_Reduce(&peak, &peak_max, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);

  if (root) {
    const double count = total_sums[0];
    const double mean = count > 0 ? total_sums[1] / count : 0;
    const double stddev = count > 0 ? std::sqrt(std::max(0.0, total_sums[2] / count - mean * mean)) : 0;
    double total = 0;
    nlohmann::json stage_json = nlohmann::json::object();
    for (const auto& [name, seconds] : stages) {
      stage_json[name] = seconds;
      if (name == "total") total = seconds;
    }
    // The same lines in the same order as without MPI (cmd_quad2d.cpp).
    if (!setup.partition.projection.empty()) say(global, "lon/lat input meshed in " + setup.partition.projection);
    if (const std::string filter = coastline_filter_summary(setup.partition.simplification); !filter.empty())
      say(global, filter);
    char line[256];
    std::snprintf(line, sizeof line, "%.0f quads in %zu parts on %d ranks (size %.6g), %.2f s, %.0f quads/s", count,
                  parts, ranks, setup.size, total, total > 0 ? count / total : 0.0);
    say(global, line);
    std::snprintf(line, sizeof line, "  scaled Jacobian avg/std/min  %.4f / %.4f / %.4f", mean, stddev, total_min);
    say(global, line);
    std::snprintf(line, sizeof line, "  inverted %llu, singular vertices %llu, area %.8g (region %.8g)", total_inverted,
                  total_singular, total_area, setup.partition.metrics.region_area);
    say(global, line);
    for (const std::string& output : settings.outputs) say(global, "wrote " + output);
    for (const std::string& output : settings.merged_outputs) say(global, "wrote " + output);
    nlohmann::json report = {
        {"region", settings.source},
        {"ranks", ranks},
        {"quads", static_cast<std::uint64_t>(count)},
        {"points", offset[parts]},
        {"parts", parts},
        {"size", setup.size},
        {"scaled_jacobian", {{"avg", mean}, {"std", stddev}, {"min", total_min}}},
        {"inverted", total_inverted},
        {"singular_vertices", total_singular},
        {"region_area", setup.partition.metrics.region_area},
        {"mesh_area", total_area},
        {"relax",
         {{"zone_vertices", relax.moved_vertices},
          {"refused_moves", relax.rejected_moves},
          {"iterations", relax.iterations}}},
        {"part_rank", part_rank},
        {"part_seconds", all_part_seconds},
        {"rank_paving_seconds", rank_paving},
        {"stage_seconds", stage_json},
        {"quads_per_second", total > 0 ? count / total : 0.0},
        {"peak_rss_mb_max_rank", peak_max},
        {"projection", setup.partition.projection},
        {"coordinates",
         settings.lonlat_output ? "lonlat" : (setup.partition.projection.empty() ? "input" : "projected")},
        {"partition", metrics_json(setup.partition)}};
    write_json_report(global, report);
  }
  return total_inverted == 0 ? 0 : 1;
}

}  // namespace

int run_quad2d_mpi(const Quad2dSettings& settings, const Quad2dOptions& options, const Polygon2& region,
                   const QuadPictureOptions& picture, const GlobalOptions& global) {
  MpiSession mpi;
  // A failure on one rank would leave the others waiting in a collective: report
  // it and abort the whole job with the usual exit code (2 bad input, 1 runtime).
  try {
    return run_ranks(mpi, settings, options, region, picture, global);
  } catch (const InputError& e) {
    std::fprintf(stderr, "structmesh: error (rank %d): %s\n", mpi.rank(), e.what());
    MPI_Abort(MPI_COMM_WORLD, 2);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "structmesh: error (rank %d): %s\n", mpi.rank(), e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  return 1;
}

}  // namespace structmesh::cli
