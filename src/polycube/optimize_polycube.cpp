// polycube_energy(), optimize_polycube(): the polycube optimisation of §4.4.2, which
// trades domain simplicity against geometric fidelity with energy (4.1),
// E_p = E_c + alpha * E_g (E_c the corners of the voxel union's boundary, E_g the sum of
// the distances to the pseudo-polycube Q at its boundary grid vertices), by greedy
// homotopic openings and closings in a moving window.
//
// Costs: a window of radius r is the box c +- 2r around a boundary voxel c, and only
// the grid vertices of that box (its voxels plus one) can change their corner or
// boundary status, so the energy change of an operation is counted there, on the bit
// rows of the window (voxel_window.hpp): the face directions meeting at a row of
// vertices are XORs of the four voxel rows around it. A sweep re-evaluates a window
// only when some voxel near its box changed since the window was last evaluated at
// this radius (versions per 4^3 tile): the outcome depends on nothing else, so the
// sweeps that follow the first cost little.
//
// Written by hand: no Debian-packaged library does homotopic voxel morphology (see
// homotopic_morphology.cpp), let alone this energy.
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"
#include "structmesh/progress.hpp"
#include "voxel_neighbourhood.hpp"
#include "voxel_window.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace structmesh {
namespace {

void check_distances(const VoxelGrid& grid, std::span<const double> vertex_distance, const char* caller) {
  if (vertex_distance.size() != grid.vertex_count())
    throw InputError(std::string(caller) + ": " + std::to_string(vertex_distance.size()) +
                     " vertex distances for a grid of " + std::to_string(grid.vertex_count()) + " vertices");
  for (std::size_t v = 0; v < vertex_distance.size(); ++v)
    if (!std::isfinite(vertex_distance[v]))
      throw InputError(std::string(caller) + ": the distance at grid vertex " + std::to_string(v) + " is not finite");
}

/// The change of (4.1) an operation in a window made: corners gained (negative: lost),
/// and the distances of the vertices that joined and left the boundary.
struct EnergyChange {
  std::int64_t corners = 0;
  double joined = 0, left = 0;
  double departed = 0, returned = 0;  // weights of voxels leaving / rejoining their state in Q's voxelization
  double total(double alpha) const {
    return static_cast<double>(corners) + alpha * (joined - left + departed - returned);
  }
  /// Below this, a change is the rounding of the sums and not a change.
  double noise(double alpha) const { return 1e-9 * alpha * (joined + left + departed + returned); }
};

/// The weight of a voxel in the volume term of E_g: the distance of its centre to Q,
/// estimated as the mean of its eight corners' distances.
double voxel_weight(const VoxelGrid& grid, std::span<const double> vertex_distance, int x, int y, int z) {
  double sum = 0;
  for (int c = 0; c < 8; ++c) sum += vertex_distance[grid.vertex_index(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2))];
  return sum / 8;
}

/// Corner and boundary masks of the vertex row (j, k) of a window (vertex u between
/// local voxels u and u + 1 along each axis), word w, from the four voxel rows around it.
struct VertexRowStatus {
  std::uint64_t corner, boundary;
};
VertexRowStatus vertex_row_status(const std::uint64_t* a, const std::uint64_t* b, const std::uint64_t* c,
                                  const std::uint64_t* d, int w, int words) {
  // a = (j, k), b = (j + 1, k), c = (j, k + 1), d = (j + 1, k + 1); suffix 1: voxel u + 1.
  const auto next = [&](const std::uint64_t* row) { return (row[w] >> 1) | (w + 1 < words ? row[w + 1] << 63 : 0); };
  const std::uint64_t a0 = a[w], b0 = b[w], c0 = c[w], d0 = d[w];
  const std::uint64_t a1 = next(a), b1 = next(b), c1 = next(c), d1 = next(d);
  const std::uint64_t x_faces = (a0 ^ a1) | (b0 ^ b1) | (c0 ^ c1) | (d0 ^ d1);
  const std::uint64_t y_faces = (a0 ^ b0) | (a1 ^ b1) | (c0 ^ d0) | (c1 ^ d1);
  const std::uint64_t z_faces = (a0 ^ c0) | (a1 ^ c1) | (b0 ^ d0) | (b1 ^ d1);
  return {x_faces & y_faces & z_faces, x_faces | y_faces | z_faces};
}

EnergyChange energy_change(const voxel::VoxelWindow& window, const VoxelGrid& grid,
                           std::span<const double> vertex_distance, const std::vector<std::uint8_t>& reference) {
  EnergyChange change;
  const auto& size = window.size();
  const auto& origin = window.origin();
  const int words = window.words();
  // The volume term: each flipped voxel either leaves the state it has in Q's voxelization
  // (the reference) or returns to it.
  for (int k = 0; k < size[2]; ++k)
    for (int j = 0; j < size[1]; ++j)
      for (int w = 0; w < words; ++w)
        for (std::uint64_t flipped = window.row(j, k)[w] ^ window.loaded_row(j, k)[w]; flipped != 0;
             flipped &= flipped - 1) {
          const int x = origin[0] + 64 * w + std::countr_zero(flipped), y = origin[1] + j, z = origin[2] + k;
          if (!grid.inside(x, y, z)) continue;
          const bool now = (window.row(j, k)[w] >> std::countr_zero(flipped)) & 1;
          const double weight = voxel_weight(grid, vertex_distance, x, y, z);
          if (now != (reference[grid.index(x, y, z)] != 0))
            change.departed += weight;
          else
            change.returned += weight;
        }
  const int vertices_x = size[0] - 1;  // the box's vertices: local 0 .. size - 2
  const auto same = [&](int j, int k) {
    return std::equal(window.row(j, k), window.row(j, k) + words, window.loaded_row(j, k));
  };
  for (int k = 0; k + 1 < size[2]; ++k)
    for (int j = 0; j + 1 < size[1]; ++j) {
      if (same(j, k) && same(j + 1, k) && same(j, k + 1) && same(j + 1, k + 1)) continue;
      for (int w = 0; w < words; ++w) {
        const int valid = std::min(64, vertices_x - 64 * w);
        if (valid <= 0) break;
        const std::uint64_t mask = valid == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << valid) - 1;
        const VertexRowStatus before =
            vertex_row_status(window.loaded_row(j, k), window.loaded_row(j + 1, k), window.loaded_row(j, k + 1),
                              window.loaded_row(j + 1, k + 1), w, words);
        const VertexRowStatus after = vertex_row_status(window.row(j, k), window.row(j + 1, k), window.row(j, k + 1),
                                                        window.row(j + 1, k + 1), w, words);
        change.corners += std::popcount(after.corner & mask) - std::popcount(before.corner & mask);
        for (std::uint64_t moved = (before.boundary ^ after.boundary) & mask; moved != 0; moved &= moved - 1) {
          const int bit = std::countr_zero(moved);
          // Local vertex u is grid vertex origin + 1 + u.
          const double distance =
              vertex_distance[grid.vertex_index(origin[0] + 1 + 64 * w + bit, origin[1] + 1 + j, origin[2] + 1 + k)];
          if ((after.boundary >> bit) & 1)
            change.joined += distance;
          else
            change.left += distance;
        }
      }
    }
  return change;
}

/// Occupied voxels with an empty 26-neighbour, in scan order: a voxel is interior when
/// the AND of the nine rows around its row is set at x - 1, x and x + 1.
std::vector<std::uint32_t> boundary_voxels(const VoxelGrid& grid) {
  const int nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  std::vector<std::uint32_t> boundary;
  std::vector<std::uint8_t> all_nine(static_cast<std::size_t>(std::max(nx, 0)) + 2);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y) {
      const std::uint8_t* row = grid.occupied.data() + grid.index(0, y, z);
      if (std::none_of(row, row + nx, [](std::uint8_t v) { return v != 0; })) continue;
      // all_nine[x + 1]: voxel column x of the 3x3 rows is full; columns -1 and nx are not.
      std::fill(all_nine.begin(), all_nine.end(), 0);
      bool any_row_missing = y == 0 || z == 0 || y == ny - 1 || z == nz - 1;
      if (!any_row_missing) {
        std::fill(all_nine.begin() + 1, all_nine.end() - 1, 1);
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy) {
            const std::uint8_t* other = grid.occupied.data() + grid.index(0, y + dy, z + dz);
            for (int x = 0; x < nx; ++x) all_nine[x + 1] &= other[x] != 0;
          }
      }
      for (int x = 0; x < nx; ++x)
        if (row[x] && !(all_nine[x] && all_nine[x + 1] && all_nine[x + 2]))
          boundary.push_back(static_cast<std::uint32_t>(grid.index(x, y, z)));
    }
  return boundary;
}

/// Versions of the 4^3 tiles of voxels: the number of the last accepted operation that
/// changed a voxel there (0: none).
class TileVersions {
 public:
  explicit TileVersions(const VoxelGrid& grid) {
    for (int a = 0; a < 3; ++a) tiles_[a] = (grid.dims[a] + kTile - 1) / kTile;
    versions_.assign(static_cast<std::size_t>(tiles_[0]) * tiles_[1] * tiles_[2], 0);
  }
  /// The newest version among the tiles that meet voxels [lo, hi).
  std::uint32_t newest(const std::array<int, 3>& lo, const std::array<int, 3>& hi) const {
    std::uint32_t newest = 0;
    for_tiles(lo, hi, [&](std::size_t tile) { newest = std::max(newest, versions_[tile]); });
    return newest;
  }
  void stamp(const std::array<int, 3>& lo, const std::array<int, 3>& hi, std::uint32_t version) {
    for_tiles(lo, hi, [&](std::size_t tile) { versions_[tile] = version; });
  }

 private:
  static constexpr int kTile = 4;
  template <class Visit>
  void for_tiles(const std::array<int, 3>& lo, const std::array<int, 3>& hi, Visit&& visit) const {
    std::array<int, 3> first{}, last{};
    for (int a = 0; a < 3; ++a) {
      if (hi[a] <= 0) return;
      first[a] = std::max(lo[a], 0) / kTile;
      last[a] = std::min((hi[a] - 1) / kTile, tiles_[a] - 1);
      if (last[a] < first[a]) return;
    }
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int x = first[0]; x <= last[0]; ++x)
          visit(static_cast<std::size_t>(x) +
                static_cast<std::size_t>(tiles_[0]) * (y + static_cast<std::size_t>(tiles_[1]) * z));
  }
  std::array<int, 3> tiles_{};
  std::vector<std::uint32_t> versions_;
};

/// Windows per chunk of the parallel evaluation.
constexpr std::size_t kChunk = 64;

/// What a window's evaluation chose.
struct WindowDecision {
  enum Operation : std::uint8_t { kKeep, kOpen, kClose };
  Operation operation = kKeep;
  bool evaluated = false;
  bool opening_refused = false;  // the opening would have lowered E_p but cut off points of Q
};

/// Windows whose opening or closing leaves every voxel as it was, by content: that
/// depends on the window's voxels alone (not on where it is or on the distances), and
/// windows on flat faces and straight edges of a polycube repeat the same few contents,
/// so most of them are answered without carrying the operations out. Contents are
/// compared in full, not by hash alone.
class UnchangedMemo {
 public:
  static constexpr std::uint8_t kOpeningUnchanged = 1, kClosingUnchanged = 2;
  /// The flags stored for the window's content at `radius`; 0 when not stored.
  std::uint8_t find(const voxel::VoxelWindow& window, int radius) const {
    const auto bucket = entries_.find(hash(window, radius));
    if (bucket == entries_.end()) return 0;
    for (const Entry& entry : bucket->second)
      if (entry.radius == radius && entry.size == window.size() && entry.rows == window.loaded_rows())
        return entry.unchanged;
    return 0;
  }
  void insert(const voxel::VoxelWindow& window, int radius, std::uint8_t unchanged) {
    if (unchanged == 0) return;
    if (stored_words_ > kMaxWords) {
      entries_.clear();
      stored_words_ = 0;
    }
    entries_[hash(window, radius)].push_back(Entry{radius, window.size(), window.loaded_rows(), unchanged});
    stored_words_ += window.loaded_rows().size();
  }

 private:
  static constexpr std::size_t kMaxWords = std::size_t{1} << 21;  // 16 MB per thread
  struct Entry {
    int radius;
    std::array<int, 3> size;
    std::vector<std::uint64_t> rows;
    std::uint8_t unchanged;
  };
  static std::uint64_t hash(const voxel::VoxelWindow& window, int radius) {
    std::uint64_t h = static_cast<std::uint64_t>(radius) * 0x9E3779B97F4A7C15ull;
    for (const int extent : window.size()) h = (h ^ static_cast<std::uint64_t>(extent)) * 0xBF58476D1CE4E5B9ull;
    for (const std::uint64_t word : window.loaded_rows()) {
      h = (h ^ word) * 0x94D049BB133111EBull;
      h ^= h >> 31;
    }
    return h;
  }
  std::unordered_map<std::uint64_t, std::vector<Entry>> entries_;
  std::size_t stored_words_ = 0;
};

/// The guard that keeps openings from cutting off thin parts of Q. E_g sums distances at
/// P's boundary (P to Q) and, in its volume term, the distances of flipped voxels' centres
/// to Q, so removing a limb a few voxels thick costs almost nothing: its voxels all lie
/// near Q's surface, and the stump's new boundary lies on Q too. The TOSCA dog lost a leg
/// so (an opening of radius 5 took 30 voxels of a plank two thick), and its hex mesh with
/// it. Here each of Q's points counts the occupied voxels within kCoverageRadius voxels of
/// its own (by index, a 7 x 7 x 7 box); an opening that would leave a point that had one
/// with none is refused (when the window is evaluated, and again when it is committed, as
/// operations committed since may have changed the counts). Closings only add voxels.
class CoverageGuard {
 public:
  static constexpr int kCoverageRadius = 3;
  /// Per thread: the coverage each point would lose, and which points lost some.
  struct Scratch {
    std::vector<std::uint32_t> lost, touched;
  };
  CoverageGuard(const VoxelGrid& grid, std::span<const Vec3> points) : grid_(grid) {
    // The points of each voxel, as compressed rows over the whole grid.
    std::vector<std::uint32_t> cell(points.size());
    first_.assign(grid.occupied.size() + 1, 0);
    for (std::size_t p = 0; p < points.size(); ++p) {
      const auto [x, y, z] = grid.voxel_of(points[p]);
      cell[p] = static_cast<std::uint32_t>(grid.index(x, y, z));
      ++first_[cell[p] + 1];
    }
    for (std::size_t i = 1; i < first_.size(); ++i) first_[i] += first_[i - 1];
    point_.resize(points.size());
    std::vector<std::uint32_t> at(first_.begin(), first_.end() - 1);
    for (std::size_t p = 0; p < points.size(); ++p) point_[at[cell[p]]++] = static_cast<std::uint32_t>(p);
    count_.assign(points.size(), 0);
    for (std::size_t p = 0; p < points.size(); ++p) {
      const auto [x, y, z] = grid.coordinates(cell[p]);
      std::uint32_t n = 0;
      for_box(x, y, z, [&](std::size_t i) { n += grid.occupied[i] != 0; });
      count_[p] = n;
    }
  }
  /// Whether emptying `removed` (voxel indices, occupied now) leaves every point that has
  /// an occupied voxel within the radius with one. Reads only: threads may ask at once.
  bool allows(const std::vector<std::uint32_t>& removed, Scratch& scratch) const {
    if (scratch.lost.size() != count_.size()) scratch.lost.assign(count_.size(), 0);
    scratch.touched.clear();
    bool allowed = true;
    for (const std::uint32_t voxel : removed) {
      const auto [x, y, z] = grid_.coordinates(voxel);
      for_box(x, y, z, [&](std::size_t cell) {
        for (std::uint32_t k = first_[cell]; k < first_[cell + 1]; ++k) {
          const std::uint32_t p = point_[k];
          if (scratch.lost[p]++ == 0) scratch.touched.push_back(p);
          if (count_[p] > 0 && scratch.lost[p] >= count_[p]) allowed = false;
        }
      });
    }
    for (const std::uint32_t p : scratch.touched) scratch.lost[p] = 0;
    return allowed;
  }
  /// Counts the voxels an operation emptied (-1) or filled (+1).
  void update(const std::vector<std::uint32_t>& voxels, int sign) {
    for (const std::uint32_t voxel : voxels) {
      const auto [x, y, z] = grid_.coordinates(voxel);
      for_box(x, y, z, [&](std::size_t cell) {
        for (std::uint32_t k = first_[cell]; k < first_[cell + 1]; ++k)
          count_[point_[k]] += static_cast<std::uint32_t>(sign);
      });
    }
  }

 private:
  template <class Visit>
  void for_box(int x, int y, int z, Visit&& visit) const {
    for (int dz = -kCoverageRadius; dz <= kCoverageRadius; ++dz)
      for (int dy = -kCoverageRadius; dy <= kCoverageRadius; ++dy)
        for (int dx = -kCoverageRadius; dx <= kCoverageRadius; ++dx)
          if (grid_.inside(x + dx, y + dy, z + dz)) visit(grid_.index(x + dx, y + dy, z + dz));
  }
  const VoxelGrid& grid_;
  std::vector<std::uint32_t> first_, point_;  // the points of voxel i: point_[first_[i] .. first_[i + 1])
  std::vector<std::uint32_t> count_;          // per point: occupied voxels within the radius
};

/// The voxels of a window that an operation flipped: those it emptied, those it filled.
void flipped_voxels(const voxel::VoxelWindow& window, const VoxelGrid& grid, std::vector<std::uint32_t>& emptied,
                    std::vector<std::uint32_t>& filled) {
  emptied.clear();
  filled.clear();
  const auto& size = window.size();
  const auto& origin = window.origin();
  for (int k = 0; k < size[2]; ++k)
    for (int j = 0; j < size[1]; ++j)
      for (int w = 0; w < window.words(); ++w)
        for (std::uint64_t flipped = window.row(j, k)[w] ^ window.loaded_row(j, k)[w]; flipped != 0;
             flipped &= flipped - 1) {
          const int bit = std::countr_zero(flipped);
          const int x = origin[0] + 64 * w + bit, y = origin[1] + j, z = origin[2] + k;
          if (!grid.inside(x, y, z)) continue;
          const auto i = static_cast<std::uint32_t>(grid.index(x, y, z));
          ((window.row(j, k)[w] >> bit) & 1 ? filled : emptied).push_back(i);
        }
}

/// One thread's window, buffers and memo.
class WindowEvaluator {
 public:
  /// The better of a homotopic opening and closing of `radius` layers in `box`, if it
  /// lowers E_p by more than the threshold; the grid is not changed.
  WindowDecision evaluate(const VoxelGrid& grid, const voxel::PackedVoxels& packed, const VoxelBox& box, int radius,
                          std::span<const double> vertex_distance, const std::vector<std::uint8_t>& reference,
                          const PolycubeOptimizationOptions& options, const CoverageGuard* guard) {
    WindowDecision decision;
    decision.evaluated = true;
    if (!window_.load(packed, box)) return decision;
    const std::uint8_t known = memo_.find(window_, radius);
    std::uint8_t unchanged = known;
    // An operation that changes nothing changes no energy.
    EnergyChange open_change, close_change;
    bool open_refused = false;
    if (!(known & UnchangedMemo::kOpeningUnchanged)) {
      window_.open(radius);
      if (window_.changed()) {
        open_change = energy_change(window_, grid, vertex_distance, reference);
        // Only an opening that would be chosen is worth the guard's look.
        if (guard && open_change.total(options.alpha) < -options.threshold) {
          flipped_voxels(window_, grid, emptied_, filled_);
          open_refused = !guard->allows(emptied_, scratch_);
        }
      } else {
        unchanged |= UnchangedMemo::kOpeningUnchanged;
      }
      window_.reset();
    }
    if (!(known & UnchangedMemo::kClosingUnchanged)) {
      window_.close(radius);
      if (window_.changed())
        close_change = energy_change(window_, grid, vertex_distance, reference);
      else
        unchanged |= UnchangedMemo::kClosingUnchanged;
      window_.reset();
    }
    if (known == 0) memo_.insert(window_, radius, unchanged);
    const double alpha = options.alpha;
    const double open_total = open_change.total(alpha), close_total = close_change.total(alpha);
    const bool open_lowers = !open_refused && -open_total > options.threshold + open_change.noise(alpha);
    const bool close_lowers = -close_total > options.threshold + close_change.noise(alpha);
    decision.opening_refused = open_refused;
    if (open_lowers && (!close_lowers || open_total <= close_total))
      decision.operation = WindowDecision::kOpen;
    else if (close_lowers)
      decision.operation = WindowDecision::kClose;
    return decision;
  }
  /// Carries out an operation `evaluate` chose; returns the number of changed voxels
  /// and the box they span.
  /// With a `guard`, an opening it refuses is not carried out (returns 0): the guard's
  /// counts may have changed since the evaluation, by operations committed before.
  std::size_t apply(VoxelGrid& grid, voxel::PackedVoxels& packed, const VoxelBox& box, int radius,
                    WindowDecision::Operation operation, VoxelBox& changed, CoverageGuard* guard) {
    if (!window_.load(packed, box)) return 0;
    if (operation == WindowDecision::kOpen)
      window_.open(radius);
    else
      window_.close(radius);
    if (guard) {
      flipped_voxels(window_, grid, emptied_, filled_);
      if (!emptied_.empty() && !guard->allows(emptied_, scratch_)) {
        ++refused_at_commit_;
        return 0;
      }
      guard->update(emptied_, -1);
      guard->update(filled_, +1);
    }
    return window_.store(grid, &changed, &packed);
  }

 private:
  voxel::VoxelWindow window_;
  UnchangedMemo memo_;
  std::vector<std::uint32_t> emptied_, filled_;
  CoverageGuard::Scratch scratch_;

 public:
  std::size_t refused_at_commit_ = 0;  // openings apply() refused
};

}  // namespace

PolycubeEnergy polycube_energy(const VoxelGrid& grid, std::span<const double> vertex_distance, double alpha,
                               const VoxelGrid* reference) {
  check_distances(grid, vertex_distance, "polycube_energy");
  if (reference && reference->dims != grid.dims)
    throw InputError("polycube_energy: the reference voxels have other dimensions than the grid");
  PolycubeEnergy energy;
  voxel::for_each_vertex_block(grid, [&](int vx, int vy, int vz, unsigned block) {
    if (!voxel::block_is_boundary(block)) return;
    energy.corners += voxel::block_is_corner(block);
    energy.deviation += vertex_distance[grid.vertex_index(vx, vy, vz)];
  });
  if (reference)
    for (int z = 0; z < grid.dims[2]; ++z)
      for (int y = 0; y < grid.dims[1]; ++y)
        for (int x = 0; x < grid.dims[0]; ++x)
          if (grid.at(x, y, z) != reference->at(x, y, z))
            energy.deviation += voxel_weight(grid, vertex_distance, x, y, z);
  energy.total = static_cast<double>(energy.corners) + alpha * energy.deviation;
  return energy;
}

PolycubeOptimizationResult optimize_polycube(VoxelGrid& grid, std::span<const double> vertex_distance,
                                             const PolycubeOptimizationOptions& options,
                                             std::span<const Vec3> covered_points) {
  if (!(options.alpha >= 0) || !std::isfinite(options.alpha))
    throw InputError("optimize_polycube: alpha must be a finite number >= 0, not " + std::to_string(options.alpha));
  if (!(options.threshold >= 0) || !std::isfinite(options.threshold))
    throw InputError("optimize_polycube: the threshold must be a finite number >= 0, not " +
                     std::to_string(options.threshold));
  if (options.max_window < 1)
    throw InputError("optimize_polycube: the largest window radius must be at least 1, not " +
                     std::to_string(options.max_window));
  if (grid.occupied.size() > std::numeric_limits<std::uint32_t>::max())
    throw InputError("optimize_polycube: a grid of " + std::to_string(grid.occupied.size()) +
                     " voxels is too large for 32-bit voxel indices");
  PolycubeOptimizationResult result;
  result.before = polycube_energy(grid, vertex_distance, options.alpha);
  // The volume term of E_g is measured against the voxels as they come in (Q's voxelization).
  const VoxelGrid reference_grid = grid;
  const std::vector<std::uint8_t>& reference = reference_grid.occupied;

  constexpr std::uint32_t kNever = std::numeric_limits<std::uint32_t>::max();
  tbb::enumerable_thread_specific<WindowEvaluator> evaluators;
  WindowEvaluator& committer = evaluators.local();
  TileVersions tiles(grid);
  voxel::PackedVoxels packed(grid);
  std::optional<CoverageGuard> guard;
  if (!covered_points.empty()) guard.emplace(grid, covered_points);
  std::size_t refused = 0;
  std::uint32_t version = 0;  // accepted operations so far
  const int nx = grid.dims[0], ny = grid.dims[1];
  for (int radius = options.max_window; radius >= 1; --radius) {
    const auto radius_start = std::chrono::steady_clock::now();
    const auto window_box = [&](std::uint32_t voxel) {
      const int cx = static_cast<int>(voxel % nx), cy = static_cast<int>(voxel / nx % ny),
                cz = static_cast<int>(voxel / nx / ny);
      return VoxelBox{{cx - 2 * radius, cy - 2 * radius, cz - 2 * radius},
                      {cx + 2 * radius + 1, cy + 2 * radius + 1, cz + 2 * radius + 1}};
    };
    // The newest change among the voxels a window's outcome depends on: its box and the
    // layer around it.
    const auto newest_near = [&](const VoxelBox& box) {
      return tiles.newest({box.lo[0] - 1, box.lo[1] - 1, box.lo[2] - 1}, {box.hi[0] + 1, box.hi[1] + 1, box.hi[2] + 1});
    };
    std::vector<std::uint32_t> previous, previous_evaluated;
    std::size_t radius_sweeps = 0, radius_openings = 0, radius_closings = 0;
    for (;;) {
      // The boundary voxels now, each with the version it was last evaluated at (at
      // this radius), carried over from the previous sweep's list.
      const std::vector<std::uint32_t> boundary = boundary_voxels(grid);
      std::vector<std::uint32_t> evaluated(boundary.size(), kNever);
      for (std::size_t i = 0, p = 0; i < boundary.size(); ++i) {
        while (p < previous.size() && previous[p] < boundary[i]) ++p;
        if (p < previous.size() && previous[p] == boundary[i]) evaluated[i] = previous_evaluated[p];
      }
      ++result.sweeps;
      ++radius_sweeps;
      std::size_t accepted = 0;
      // The windows are taken in order, each on the voxels as the ones before it left
      // them. To use several threads and get the same result, a chunk of windows is
      // evaluated in parallel on the voxels as they are at the chunk's start; then, in
      // order, a window keeps its outcome unless an operation accepted earlier in the
      // chunk changed voxels near it, in which case it is evaluated again.
      std::vector<WindowDecision> decisions;
      for (std::size_t chunk = 0; chunk < boundary.size(); chunk += kChunk) {
        const std::size_t chunk_end = std::min(boundary.size(), chunk + kChunk);
        const std::uint32_t chunk_version = version;
        const auto needs_evaluation = [&](std::size_t i) {
          return evaluated[i] == kNever || newest_near(window_box(boundary[i])) > evaluated[i];
        };
        decisions.assign(chunk_end - chunk, WindowDecision{});
        tbb::parallel_for(tbb::blocked_range<std::size_t>(chunk, chunk_end, 8),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                            WindowEvaluator& evaluator = evaluators.local();
                            for (std::size_t i = range.begin(); i < range.end(); ++i)
                              if (needs_evaluation(i))
                                decisions[i - chunk] =
                                    evaluator.evaluate(grid, packed, window_box(boundary[i]), radius, vertex_distance,
                                                       reference, options, guard ? &*guard : nullptr);
                          });
        for (std::size_t i = chunk; i < chunk_end; ++i) {
          const VoxelBox box = window_box(boundary[i]);
          const std::uint32_t newest = newest_near(box);
          if (evaluated[i] != kNever && newest <= evaluated[i]) continue;
          WindowDecision decision = decisions[i - chunk];
          if (!decision.evaluated || newest > chunk_version)
            decision = committer.evaluate(grid, packed, box, radius, vertex_distance, reference, options,
                                          guard ? &*guard : nullptr);
          refused += decision.opening_refused;
          evaluated[i] = version;
          if (decision.operation == WindowDecision::kKeep) continue;
          VoxelBox changed;
          if (committer.apply(grid, packed, box, radius, decision.operation, changed, guard ? &*guard : nullptr) == 0)
            continue;
          ++version;
          tiles.stamp(changed.lo, changed.hi, version);
          ++accepted;
          ++(decision.operation == WindowDecision::kOpen ? radius_openings : radius_closings);
        }
      }
      previous = boundary;
      previous_evaluated = evaluated;
      if (accepted == 0) break;
    }
    result.openings += radius_openings;
    result.closings += radius_closings;
    if (options.progress) {
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - radius_start).count();
      char elapsed[32];
      std::snprintf(elapsed, sizeof elapsed, " (%.1f s)", seconds);
      status("polycube: window radius " + std::to_string(radius) + ": " + std::to_string(radius_sweeps) + " sweeps, " +
             std::to_string(radius_openings) + " openings, " + std::to_string(radius_closings) + " closings" +
             (guard ? ", " + std::to_string(refused + committer.refused_at_commit_) + " openings refused so far"
                    : std::string()) +
             elapsed);
    }
  }
  result.after = polycube_energy(grid, vertex_distance, options.alpha, &reference_grid);
  result.refused_openings = refused + committer.refused_at_commit_;
  return result;
}

}  // namespace structmesh
