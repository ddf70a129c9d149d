// smooth_hex_mesh(): the post-processing of §5.3, "Untangle and Jacobian metric of [119]":
// Knupp's untangling (each point of an inverted hex moves to raise the smallest corner
// Jacobian determinant around it), then smoothing sweeps that move a point only when the
// worst Verdict scaled Jacobian of its hexes does not drop, so a valid hex never inverts.
//
// Both stages move one point at a time with everything else fixed. Points sharing a hex get
// different colours (greedy colouring in index order), and the points of one colour move in
// parallel: none of them reads a position or writes a hex another one touches, so a colour
// gives the same result as moving its points one after the other, whatever the thread count.
#include "hex/untangle_hexes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/quality.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

namespace structmesh {

namespace {

// The score of a hex Verdict calls invalid (a zero-length edge or axis): below every scaled
// Jacobian, which lies in [-1, 1], and counted as inverted.
constexpr double kInvalidScore = -2.0;

// Verdict's corner samples and the node signs of its centre sample (quality.hpp).
using hex_jacobian_sample::kAxisSigns;
using hex_jacobian_sample::kCorners;

// Untangling: the corner determinants around a point, divided by the cube of the mean
// length of its edges (1 for a unit cube's corners, whatever the mesh's size), are pushed
// towards this level: the point moves by Gauss-Newton steps on
//   sum over samples of max(0, kTarget - q)^2,
// a convex function since each determinant is affine in the position of any one of its points.
constexpr double kUntangleTarget = 0.2;
// Rounds over the points of the inverted hexes; each round is cheap (only those points move),
// and a round that moves nothing ends the untangling.
constexpr int kUntangleRounds = 100;
// A mesh with more inverted hexes than this is tangled in bulk: its untangling rounds stop
// when they stall, its attempts when one removes under 2%, and it gets no joint untangling
// and no smoothing sweeps (smooth_hex_mesh below).
constexpr std::size_t kBulkTangle = 50;
// Untangling rounds without a new fewest count of inverted hexes before an attempt stops.
constexpr int kUntangleStall = 30;
constexpr int kUntangleSteps = 5;        // Gauss-Newton steps per point and round
constexpr int kLineSearchHalvings = 10;  // backtracking: 1, 1/2, ... 1/1024 of the step
constexpr double kMinimumGain = 1e-12;   // of the normalised worst determinant
// Smoothing candidates: the Laplacian centroid and the steps of 1/2 ... 1/16 towards it. The
// short steps matter: untangling leaves valid folds where every step of 1/4 or more lowers
// some hex below the current worst (on a 40^3 grid perturbed by 0.45, stopping at 1/4 kept
// the worst scaled Jacobian at 0.35, 1/16 reached 0.99 in as many sweeps).
constexpr std::array<double, 6> kSmoothingSteps{1.6, 1.0, 0.5, 0.25, 0.125, 0.0625};
// Ascent steps along a score gradient: 1/4 of the mean edge length around the point, halved
// down to 1/100 of it.
constexpr double kAscentFirstStep = 0.25, kAscentLastStep = 0.01;
// Samples this close to the worst one around a point are raised together.
constexpr double kActiveTolerance = 0.05;
constexpr std::size_t kGrain = 256;
// The smoothing sweeps stop when this many sweeps together gained too little.
constexpr std::size_t kStallWindow = 5;
// The polish after the sweeps (polish_worst, polish_hexes.cpp): the hexes within kPolishMargin
// of the worst score and the interior points within kPolishRings rings of them move
// together, then up to kSweepsAfterPolish sweeps of the whole mesh; at most kPolishRounds
// rounds, while the worst hex gains kPolishMinimumGain. Fertility at 18k hexes: 0.280 ->
// 0.303 in 8 rounds (with 2 rings and a softer minimum, 0.296; with the sweeps only within 3
// or 8 rings of the polished points, 0.294).
constexpr int kPolishRounds = 10, kPolishRings = 3, kSweepsAfterPolish = 10;
constexpr double kPolishMargin = 0.05, kPolishMinimumGain = 1e-4;
// Joint untangling frees the points within this many hex rings of the inverted hexes.
constexpr int kRegionRings = 4;
// Fresh starts (restart_worst below): the points within 1 to kRestartRings rings of the hexes
// below max(kRestartBelow, worst + kPolishMargin) go back, and the sweeps after them move
// only those and the points within kFocusRings more rings (unfocused, they were 100 sweeps of
// the whole mesh: 10.7 s on the dog against 0.6 s), at most kRestartSweeps of them.
// A second series of tries starts from kCentroidResetSteps Jacobi steps towards the
// neighbours' centroids instead (fertility at 12k hexes: no start from the map's positions
// beat its 0.245; with 40 steps, 0.245 -> 0.371 -> 0.583 in two rounds; 10 or 100 steps
// raised nothing there either).
constexpr int kRestartRings = 4, kFocusRings = 3, kRestartSweeps = 100, kCentroidResetSteps = 40;
constexpr double kRestartBelow = 0.3;
// The ascent of the mean (Smoother::raise_mean): the points of the hexes within
// kMeanFrozenMargin of the worst stay put, every other hex stays kMeanFloorMargin above the
// worst; kMeanIterations L-BFGS iterations per round, then up to kBoundaryMeanSweeps sweeps
// of the boundary points; at most kMeanRounds rounds, while a round gains kMeanMinimumGain.
// Fertility at 18k hexes: 0.932 -> 0.942 after one round of 100 iterations (50: 0.941; 400:
// 0.942). The closed dog at 10k asked: 0.919 -> 0.940 in 7 rounds, 1 s each; it stopped at
// 0.9397 after 5 when a round had to gain 1e-3. The bunny at 80k hexes: 0.944 -> 0.949 in 6 s
// of a 62 s run (so the default mean_below, 0.94, leaves it alone).
constexpr double kMeanFrozenMargin = 0.1, kMeanFloorMargin = 0.05, kMeanMinimumGain = 3e-4;
constexpr int kMeanRounds = 8, kMeanIterations = 100;
// The springs that hold the boundary points near the surface during the joint ascent: a point
// a tenth of a hex edge off the surface costs 0.01 of a hex's score. On the closed dog
// stiffness 1 reached a mean of 0.9408 in 8 rounds, 10 reached 0.9405 and 100 0.9395 (the
// points gain by leaving the surface for a while, more than putting them back loses).
constexpr double kMeanNormalStiffness = 1.0;
constexpr int kBoundaryMeanSweeps = 10;
constexpr double kBoundarySweepGain = 2e-5;
// A boundary move of that ascent must raise the sum of its hexes' scores by this much.
constexpr double kMinimumSumGain = 1e-9;
// ... and refuses a placement that moves a point by more than this many mean edge lengths.
constexpr double kMaxJointMove = 6.0;
// How far untangle_point() may take a boundary point from where the smoothing found it, in
// mean boundary edge lengths.
constexpr double kMaxBoundaryDrift = 3.0;

// Verdict's principal axes of a hex (the edges of its centre sample): X, Y, Z with the node
// signs of kAxisSigns.
std::array<Vec3, 3> principal_axes(const std::array<Vec3, 8>& p) {
  return {(p[1] + p[2] + p[5] + p[6]) - (p[0] + p[3] + p[4] + p[7]),
          (p[2] + p[3] + p[6] + p[7]) - (p[0] + p[1] + p[4] + p[5]),
          (p[4] + p[5] + p[6] + p[7]) - (p[0] + p[1] + p[2] + p[3])};
}

// The normal of a boundary quad, twice its area vector (the cross product of its diagonals).
Vec3 quad_normal(const std::vector<Vec3>& points, const std::array<Index, 4>& q) {
  return (points[q[2]] - points[q[0]]).cross(points[q[3]] - points[q[1]]);
}

// A determinant q(x) = q + g . (x - x0) around the point's position x0 (affine in x).
struct Sample {
  double q;
  Vec3 g;
};

// Appends the samples of a hex that depend on its node l (normalised by `scale`): the
// corners at l and at l's three hex neighbours, and the centre sample. The gradient of
// det(a, b, c) is b x c, c x a or a x b for the point that ends a, b or c, and minus their sum
// for the corner point itself.
void append_samples(const std::array<Vec3, 8>& p, int l, double scale, std::vector<Sample>& out) {
  for (const auto& [o, i, j, k] : kCorners) {
    const Vec3 a = p[i] - p[o], b = p[j] - p[o], c = p[k] - p[o];
    const Vec3 bc = b.cross(c), ca = c.cross(a), ab = a.cross(b);
    Vec3 g;
    if (l == o)
      g = -(bc + ca + ab);
    else if (l == i)
      g = bc;
    else if (l == j)
      g = ca;
    else if (l == k)
      g = ab;
    else
      continue;
    out.push_back({a.dot(bc) * scale, g * scale});
  }
  // The principal axes are sums of four edges: 64 times a corner determinant for a cube.
  const auto [x, y, z] = principal_axes(p);
  const Vec3 yz = y.cross(z), zx = z.cross(x), xy = x.cross(y);
  const auto& s = kAxisSigns[l];
  out.push_back({x.dot(yz) * scale / 64, (s[0] * yz + s[1] * zx + s[2] * xy) * scale / 64});
}

struct ScoreStatistics {
  std::size_t inverted = 0, valid = 0;
  double min = std::numeric_limits<double>::infinity(), sum = 0;
  double mean() const { return valid == 0 ? 0.0 : sum / static_cast<double>(valid); }
};

// Statistics of the hex scores, summed in fixed blocks so that the total does not depend
// on how TBB splits the range.
ScoreStatistics score_statistics(const std::vector<double>& score) {
  constexpr std::size_t kBlock = std::size_t{1} << 14;
  const std::size_t blocks = (score.size() + kBlock - 1) / kBlock;
  std::vector<ScoreStatistics> partial(blocks);
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    ScoreStatistics& s = partial[b];
    for (std::size_t h = b * kBlock; h < std::min(score.size(), (b + 1) * kBlock); ++h) {
      s.inverted += score[h] <= 0;
      if (score[h] == kInvalidScore) continue;
      ++s.valid;
      s.min = std::min(s.min, score[h]);
      s.sum += score[h];
    }
  });
  ScoreStatistics total;
  for (const ScoreStatistics& s : partial) {
    total.inverted += s.inverted;
    total.valid += s.valid;
    total.min = std::min(total.min, s.min);
    total.sum += s.sum;
  }
  if (total.valid == 0) total.min = 0;
  return total;
}

// Rows of point -> points along the edges of the boundary quads.
CompressedRows surface_neighbours(const std::vector<std::array<Index, 4>>& quads, std::size_t point_count) {
  std::vector<std::pair<Index, Index>> pairs;
  pairs.reserve(quads.size() * 8);
  for (const auto& q : quads)
    for (int i = 0; i < 4; ++i) {
      pairs.emplace_back(q[i], q[(i + 1) % 4]);
      pairs.emplace_back(q[(i + 1) % 4], q[i]);
    }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  CompressedRows rows;
  rows.offsets.assign(point_count + 1, 0);
  for (const auto& [a, b] : pairs) ++rows.offsets[a + 1];
  for (std::size_t v = 0; v < point_count; ++v) rows.offsets[v + 1] += rows.offsets[v];
  rows.items.reserve(pairs.size());
  for (const auto& [a, b] : pairs) rows.items.push_back(b);
  return rows;
}

// The 4 corner samples of a hex that do not use point l (the complement of
// hex_jacobian_sample::kCornersUsing[l]).
constexpr std::array<std::array<int, 4>, 8> kCornersNotUsing = [] {
  std::array<std::array<int, 4>, 8> table{};
  for (std::size_t l = 0; l < 8; ++l) {
    std::size_t n = 0;
    for (int c = 0; c < 8; ++c) {
      bool used = false;
      for (const int u : hex_jacobian_sample::kCornersUsing[l]) used = used || u == c;
      if (!used) table[l][n++] = c;
    }
  }
  return table;
}();

// Per-thread buffers of a point's tries (Smoother::prepare_tries, try_position).
struct MoveScratch {
  std::vector<double> scores;       // the new score of each hex of the point
  std::vector<double> fixed;        // per hex: the worst sample the point does not change
  std::vector<std::uint8_t> local;  // per hex: where the point is in it
};

class Smoother {
 public:
  Smoother(HexMesh& mesh, const HintedProjection& project, bool move_boundary, double feature_angle_degrees)
      : mesh_(mesh), project_(project) {
    const std::size_t n = mesh.points.size();
    point_hexes_ = build_vertex_elements(std::span<const std::array<Index, 8>>(mesh.hexes), n);
    neighbours_ = build_vertex_neighbors(build_edges(mesh), n);
    quads_ = hex_boundary_quads(mesh);
    const std::vector<std::array<Index, 4>>& quads = quads_;
    point_quads_ = build_vertex_elements(std::span<const std::array<Index, 4>>(quads), n);
    surface_neighbours_ = surface_neighbours(quads, n);
    boundary_.assign(n, 0);
    released_.assign(n, 0);
    hint_triangle_.assign(n, kInvalidIndex);
    double edge_sum = 0;
    for (const auto& q : quads)
      for (int i = 0; i < 4; ++i) {
        boundary_[q[i]] = 1;
        edge_sum += (mesh.points[q[i]] - mesh.points[q[(i + 1) % 4]]).norm();
      }
    release_limit_ = quads.empty() ? 0 : edge_sum / (4.0 * static_cast<double>(quads.size()));
    origin_ = mesh.points;
    std::vector<std::uint8_t> movable(n, 0);
    for (std::size_t v = 0; v < n; ++v) movable[v] = !point_hexes_.row(v).empty() && (move_boundary || !boundary_[v]);
    // Feature points (§4.5.3): where two boundary quads around a point meet at more than
    // the feature angle, the point is on a sharp edge or corner of the surface, and sliding
    // it to its neighbours' centroid and back onto the surface would round that feature off.
    if (move_boundary && feature_angle_degrees > 0) {
      const CompressedRows& point_quads = point_quads_;
      const double limit = std::cos(feature_angle_degrees * std::numbers::pi / 180);
      std::vector<Vec3> normal(quads.size());
      for (std::size_t q = 0; q < quads.size(); ++q) normal[q] = quad_normal(mesh.points, quads[q]).normalized();
      for (std::size_t v = 0; v < n; ++v) {
        const auto around = point_quads.row(v);
        for (std::size_t a = 0; a < around.size() && movable[v]; ++a)
          for (std::size_t b = a + 1; b < around.size(); ++b)
            if (normal[around[a]].dot(normal[around[b]]) < limit) {
              movable[v] = 0;
              ++feature_points_;
              break;
            }
      }
    }
    colour_points(movable);
    movable_ = std::move(movable);
    score_.resize(mesh.hexes.size());
    rescore_all();
  }

  const std::vector<double>& scores() const { return score_; }
  std::size_t feature_points() const { return feature_points_; }

  /// Puts the points back where they were (positions saved from the mesh earlier).
  void restore_points(const std::vector<Vec3>& points) {
    mesh_.points = points;
    rescore_all();
  }

  // One round of untangling over the movable points of the inverted hexes; true if a
  // point moved. A point that cannot raise its smallest determinant alone (its neighbours
  // hold it where it is best for them too) tries the smoothing move, whose measure (the
  // scaled Jacobian, normalised per corner) often still improves there: on a 100^3 grid
  // perturbed by 0.45, untangling alone left 2 of 254600 inverted hexes, with it none.
  bool untangle_round() {
    std::vector<std::uint8_t> active(mesh_.points.size(), 0);
    for (std::size_t h = 0; h < mesh_.hexes.size(); ++h)
      if (score_[h] <= 0)
        for (const Index v : mesh_.hexes[h]) active[v] = 1;
    std::atomic<bool> moved{false};
    for (const std::vector<Index>& colour : colours_) {
      std::vector<Index> points;
      for (const Index v : colour)
        if (active[v]) points.push_back(v);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), kGrain), [&](const auto& range) {
        std::vector<Sample> samples;
        MoveScratch scratch;
        for (std::size_t k = range.begin(); k != range.end(); ++k)
          if (untangle_point(points[k], samples) || smooth_point(points[k], scratch))
            moved.store(true, std::memory_order_relaxed);
      });
    }
    return moved.load();
  }

  // One smoothing sweep over every movable point; returns the number of moves. With
  // `skip_settled`, a point whose last try failed is tried again only once a point of its
  // hexes has moved since (its try would fail the same way): the late sweeps move few points.
  std::size_t smoothing_sweep(bool skip_settled = false) {
    std::atomic<std::size_t> moves{0};
    if (moved_at_.empty()) moved_at_.assign(mesh_.points.size(), 0), tried_at_.assign(mesh_.points.size(), 0);
    for (const std::vector<Index>& colour : colours_) {
      // Epochs count colours, so that "moved since v's try" is the same on any thread count.
      const std::uint32_t epoch = ++epoch_;
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, colour.size(), kGrain), [&](const auto& range) {
        MoveScratch scratch;
        std::size_t local = 0;
        for (std::size_t k = range.begin(); k != range.end(); ++k) {
          const Index v = colour[k];
          if (!focus_.empty() && !focus_[v]) continue;
          if (!skip_settled) {
            local += smooth_point(v, scratch);
            continue;
          }
          // Only these sweeps keep the stamps: nothing else moves points between them (the
          // untangling, which does, comes before).
          if (settled(v)) continue;
          tried_at_[v] = epoch;
          if (smooth_point(v, scratch)) moved_at_[v] = epoch, ++local;
        }
        moves.fetch_add(local, std::memory_order_relaxed);
      });
    }
    return moves.load();
  }

 private:
  // The points of hex h, and where v is among them.
  int hex_points(Index h, Index v, std::array<Vec3, 8>& p) const {
    int local = 0;
    for (int i = 0; i < 8; ++i) {
      p[i] = mesh_.points[mesh_.hexes[h][i]];
      if (mesh_.hexes[h][i] == v) local = i;
    }
    return local;
  }

  // Whether v's last try failed and no point of its hexes moved since.
  bool settled(Index v) const {
    if (tried_at_[v] == 0 || moved_at_[v] == tried_at_[v]) return false;
    for (const Index h : point_hexes_.row(v))
      for (const Index u : mesh_.hexes[h])
        if (moved_at_[u] > tried_at_[v]) return false;
    return true;
  }

  double hex_score(std::size_t h) const {
    std::array<Vec3, 8> p;
    for (int i = 0; i < 8; ++i) p[i] = mesh_.points[mesh_.hexes[h][i]];
    const std::optional<double> sj = hex_scaled_jacobian(p);
    return sj ? *sj : kInvalidScore;
  }

  void rescore_all() {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh_.hexes.size(), kGrain), [&](const auto& range) {
      for (std::size_t h = range.begin(); h != range.end(); ++h) score_[h] = hex_score(h);
    });
  }

  void rescore(Index v) {
    for (const Index h : point_hexes_.row(v)) score_[h] = hex_score(h);
  }

  // Greedy colouring in ascending point order: a point takes the smallest colour not used by
  // a movable point of its hexes. Fixed points never move and need no colour.
  void colour_points(const std::vector<std::uint8_t>& movable) {
    std::vector<int> colour(mesh_.points.size(), -1);
    std::vector<std::size_t> seen_by;  // per colour: 1 + the last point that found it in use
    for (std::size_t v = 0; v < mesh_.points.size(); ++v) {
      if (!movable[v]) continue;
      for (const Index h : point_hexes_.row(v))
        for (const Index u : mesh_.hexes[h])
          if (colour[u] >= 0) seen_by[colour[u]] = v + 1;
      std::size_t c = 0;
      while (c < colours_.size() && seen_by[c] == v + 1) ++c;
      if (c == colours_.size()) {
        colours_.emplace_back();
        seen_by.push_back(0);
      }
      colour[v] = static_cast<int>(c);
      colours_[c].push_back(static_cast<Index>(v));
    }
  }

  // A boundary point goes back onto the surface; a released one may stay off it, but by at
  // most one mean boundary edge (released points drifted away unbounded on the screwdriver).
  Vec3 put_back(Index v, const Vec3& x) const {
    if (!boundary_[v]) return x;
    // The triangle of the last projection made for v is near this one. Only the thread that
    // moves v reads and writes its slot (the sweeps' colouring).
    const Vec3 on_surface = project_(x, &hint_triangle_[v]);
    if (!released_[v]) return on_surface;
    const Vec3 offset = x - on_surface;
    const double distance = offset.norm();
    return distance <= release_limit_ ? x : Vec3(on_surface + offset * (release_limit_ / distance));
  }

 public:
  // Joint untangling (untangle_hexes.cpp) of the points within kRegionRings hex rings of the
  // inverted hexes: a fold whose points all hold each other in place (each single move
  // lowers some determinant) needs them to move together. With `free_boundary`, boundary
  // points of the region move too and stop being put back on the surface. The new
  // placement is kept only if fewer hexes of the region are inverted, or as many with a
  // larger worst score. Returns whether it was kept.
  bool untangle_regions(bool free_boundary) {
    const std::size_t n = mesh_.points.size();
    std::vector<std::uint8_t> in_region(n, 0);
    std::vector<Index> region;
    double edge_sum = 0;
    std::size_t edge_count = 0;
    for (std::size_t h = 0; h < mesh_.hexes.size(); ++h) {
      if (score_[h] > 0) continue;
      const auto& c = mesh_.hexes[h];
      for (int i = 0; i < 4; ++i) {
        edge_sum += (mesh_.points[c[i]] - mesh_.points[c[(i + 1) % 4]]).norm() +
                    (mesh_.points[c[i + 4]] - mesh_.points[c[(i + 1) % 4 + 4]]).norm() +
                    (mesh_.points[c[i]] - mesh_.points[c[i + 4]]).norm();
        edge_count += 3;
      }
      for (const Index v : c)
        if (!in_region[v]) in_region[v] = 1, region.push_back(v);
    }
    if (region.empty() || !(edge_sum > 0)) return false;
    grow_region(region, in_region, kRegionRings);
    std::vector<Index> free;
    for (const Index v : region)
      if (movable_[v] && (!boundary_[v] || released_[v] || free_boundary)) free.push_back(v);
    std::vector<std::array<Index, 8>> hexes;
    std::vector<Index> hex_ids;
    hexes_using(free, hex_ids, hexes);
    const auto summary = [&] {
      std::pair<std::size_t, double> inverted_and_min{0, std::numeric_limits<double>::infinity()};
      for (const Index h : hex_ids) {
        inverted_and_min.first += score_[h] <= 0 ? 1 : 0;
        inverted_and_min.second = std::min(inverted_and_min.second, score_[h]);
      }
      return inverted_and_min;
    };
    const auto before = summary();
    std::vector<Vec3> saved(free.size());
    for (std::size_t k = 0; k < free.size(); ++k) saved[k] = mesh_.points[free[k]];
    const double size = edge_sum / static_cast<double>(edge_count);
    hex_detail::untangle_hexes(mesh_.points, hexes, free, size);
    for (const Index h : hex_ids) score_[h] = hex_score(h);
    const auto after = summary();
    // The barrier keeps the hexes positive, not the points near the surface: with the
    // boundary free a region can swell away (the screwdriver's tip flew off by hundreds of
    // sizes). A placement that moves a point by more than kMaxJointMove sizes is refused.
    double moved = 0;
    for (std::size_t k = 0; k < free.size(); ++k) moved = std::max(moved, (mesh_.points[free[k]] - saved[k]).norm());
    if (moved <= kMaxJointMove * size &&
        (after.first < before.first || (after.first == before.first && after.second > before.second))) {
      for (const Index v : free)
        if (boundary_[v]) released_[v] = 1, any_released_ = true;
      return true;
    }
    for (std::size_t k = 0; k < free.size(); ++k) mesh_.points[free[k]] = saved[k];
    for (const Index h : hex_ids) score_[h] = hex_score(h);
    return false;
  }

  // The points of the hexes whose score passes `keep`, each once; flagged in `in_region`
  // (resized to the point count).
  template <class Keep>
  std::vector<Index> points_of_hexes(Keep keep, std::vector<std::uint8_t>& in_region) const {
    in_region.assign(mesh_.points.size(), 0);
    std::vector<Index> region;
    for (std::size_t h = 0; h < mesh_.hexes.size(); ++h)
      if (keep(score_[h]))
        for (const Index v : mesh_.hexes[h])
          if (!in_region[v]) in_region[v] = 1, region.push_back(v);
    return region;
  }

  // Adds to `region` (its points flagged in `in_region`) the points of their hexes, `rings`
  // times over.
  void grow_region(std::vector<Index>& region, std::vector<std::uint8_t>& in_region, int rings) const {
    for (int ring = 0; ring < rings; ++ring) {
      const std::size_t end = region.size();
      for (std::size_t k = 0; k < end; ++k)
        for (const Index h : point_hexes_.row(region[k]))
          for (const Index v : mesh_.hexes[h])
            if (!in_region[v]) in_region[v] = 1, region.push_back(v);
    }
  }

  // The hexes that use a point of `free`, each once: their ids and their points.
  void hexes_using(const std::vector<Index>& free, std::vector<Index>& hex_ids,
                   std::vector<std::array<Index, 8>>& hexes) const {
    std::vector<std::uint8_t> touched(mesh_.hexes.size(), 0);
    for (const Index v : free)
      for (const Index h : point_hexes_.row(v))
        if (!touched[h]) touched[h] = 1, hex_ids.push_back(h), hexes.push_back(mesh_.hexes[h]);
  }

  // Joint ascent of the worst hexes (polish_hexes): the hexes within `margin` of the worst
  // score, and the interior points within `rings` rings of them, move together. Kept if the
  // worst score of the hexes involved rose. Returns whether it was kept.
  bool polish_worst(double margin, int rings) {
    const ScoreStatistics now = score_statistics(score_);
    if (now.inverted > 0 || !std::isfinite(now.min)) return false;
    std::vector<std::uint8_t> in_region;
    std::vector<Index> region = points_of_hexes([&](double score) { return score <= now.min + margin; }, in_region);
    grow_region(region, in_region, rings);
    std::vector<Index> free;
    for (const Index v : region)
      if (movable_[v] && !boundary_[v]) free.push_back(v);
    std::vector<std::array<Index, 8>> hexes;
    std::vector<Index> hex_ids;
    hexes_using(free, hex_ids, hexes);
    const hex_detail::HexPolishResult polished = hex_detail::polish_hexes(mesh_.points, hexes, free);
    if (!(polished.worst_after > polished.worst_before)) return false;
    for (const Index h : hex_ids) score_[h] = hex_score(h);
    // The points moved: their neighbours are no longer settled for the next sweeps.
    if (!moved_at_.empty()) {
      const std::uint32_t epoch = ++epoch_;
      for (const Index v : free) moved_at_[v] = epoch;
    }
    return true;
  }

  // Where the points are, and which boundary points are released: what a fresh start of a
  // cluster (reset_worst) puts back when it did not pay.
  struct Snapshot {
    std::vector<Vec3> points;
    std::vector<std::uint8_t> released;
    bool any_released = false;
  };
  Snapshot snapshot() const { return {mesh_.points, released_, any_released_}; }
  void restore(const Snapshot& snapshot) {
    released_ = snapshot.released;
    any_released_ = snapshot.any_released;
    restore_points(snapshot.points);
  }

  // The start of a fresh try at the worst cluster: the points within `rings` rings of the
  // hexes below `below` go back to where the smoothing found them (the map's positions), to
  // be untangled and smoothed again, now with smooth surroundings; with `centroids`, they
  // then move towards their neighbours' centroids. Returns how many points went back.
  std::size_t reset_worst(double below, int rings, bool centroids) {
    std::vector<std::uint8_t> in_region;
    std::vector<Index> region = points_of_hexes([&](double score) { return score < below; }, in_region);
    if (region.empty()) return 0;
    grow_region(region, in_region, rings);
    const std::size_t reset_end = region.size();
    grow_region(region, in_region, kFocusRings);
    focus_ = std::move(in_region);
    // The sweeps after it skip settled points: these are not.
    if (moved_at_.empty()) moved_at_.assign(mesh_.points.size(), 0), tried_at_.assign(mesh_.points.size(), 0);
    const std::uint32_t epoch = ++epoch_;
    std::size_t reset = 0;
    for (std::size_t k = 0; k < reset_end; ++k)
      if (const Index v = region[k]; movable_[v]) mesh_.points[v] = origin_[v], moved_at_[v] = epoch, ++reset;
    // Or from there, kCentroidResetSteps Jacobi steps towards the neighbours' centroid (on
    // the surface for boundary points): a smooth start that needs no untangling, or less.
    if (centroids) {
      std::vector<Vec3> next(reset_end);
      for (int step = 0; step < kCentroidResetSteps; ++step) {
        for (std::size_t k = 0; k < reset_end; ++k) {
          const Index v = region[k];
          next[k] = mesh_.points[v];
          if (!movable_[v]) continue;
          const auto ring = boundary_[v] ? surface_neighbours_.row(v) : neighbours_.row(v);
          if (!ring.empty()) next[k] = put_back(v, centroid_of(ring));
        }
        for (std::size_t k = 0; k < reset_end; ++k) mesh_.points[region[k]] = next[k];
      }
    }
    rescore_all();
    return reset;
  }
  // Back to sweeps over the whole mesh.
  void clear_focus() { focus_.clear(); }

  // Joint ascent of the mean (raise_mean_scaled_jacobian.cpp), with every hex kept at least
  // kMeanFloorMargin above the worst hex of the mesh. The points of the hexes within
  // kMeanFrozenMargin of the worst stay put: those hexes are what the sweeps and the polish
  // balanced, and a barrier this close to them would cut every step of the joint line search
  // short. The boundary points move too, held near the surface by springs along its normal
  // (kMeanNormalStiffness), and go back onto it afterwards; where that takes a hex below the
  // floor, the points of that hex go back to where they were, until none is. With the
  // interior points alone the ascent stalled under 0.94 on the dogs, a quarter of whose hexes
  // touch the boundary and hold half of the mean's shortfall (the closed dog: 0.9393 after 8
  // rounds; with the boundary, 0.9408). `worst` is the mesh's worst score. Returns whether the
  // points moved.
  bool raise_mean(double worst) {
    if (!(worst > 0)) return false;
    std::vector<std::uint8_t> frozen(mesh_.points.size(), 0);
    for (std::size_t h = 0; h < mesh_.hexes.size(); ++h)
      if (score_[h] < worst + kMeanFrozenMargin)
        for (const Index v : mesh_.hexes[h]) frozen[v] = 1;
    std::vector<Index> free;
    for (std::size_t v = 0; v < mesh_.points.size(); ++v)
      if (movable_[v] && !frozen[v]) free.push_back(static_cast<Index>(v));
    std::vector<std::array<Index, 8>> hexes;
    std::vector<Index> hex_ids;
    hexes_using(free, hex_ids, hexes);
    // Every hex here has a free point, so none is within kMeanFrozenMargin of the worst.
    const double floor = worst + kMeanFloorMargin;
    std::vector<Vec3> normal(free.size(), Vec3::Zero());  // zero: an interior point, no spring
    std::vector<Vec3> saved(free.size());
    for (std::size_t k = 0; k < free.size(); ++k) {
      saved[k] = mesh_.points[free[k]];
      if (boundary_[free[k]]) normal[k] = surface_normal(free[k]);
    }
    double sum_before = 0;
    for (const Index h : hex_ids) sum_before += score_[h];
    const hex_detail::HexMeanAscentResult ascent =
        hex_detail::raise_mean_scaled_jacobian(mesh_.points, hexes, free, std::vector<double>(hexes.size(), floor),
                                               kMeanIterations, normal, kMeanNormalStiffness);
    if (!(ascent.score_sum_after > ascent.score_sum_before)) return false;
    std::vector<Index> slot(mesh_.points.size(), kInvalidIndex);
    for (std::size_t k = 0; k < free.size(); ++k) {
      slot[free[k]] = static_cast<Index>(k);
      if (boundary_[free[k]]) mesh_.points[free[k]] = put_back(free[k], mesh_.points[free[k]]);
    }
    for (const Index h : hex_ids) score_[h] = hex_score(h);
    for (bool restored = true; restored;) {
      restored = false;
      std::vector<Index> moved_back;
      for (const Index h : hex_ids)
        if (!(score_[h] > floor))
          for (const Index v : mesh_.hexes[h])
            if (slot[v] != kInvalidIndex && mesh_.points[v] != saved[slot[v]])
              mesh_.points[v] = saved[slot[v]], moved_back.push_back(v), restored = true;
      for (const Index v : moved_back) rescore(v);
    }
    double sum_after = 0;
    for (const Index h : hex_ids) sum_after += score_[h];
    if (sum_after > sum_before) return true;
    for (std::size_t k = 0; k < free.size(); ++k) mesh_.points[free[k]] = saved[k];
    for (const Index h : hex_ids) score_[h] = hex_score(h);
    return false;
  }

  // One sweep over the movable boundary points, each moved (along the gradient of the sum of
  // its hexes' scores, else towards its neighbours' centroid, and back onto the surface)
  // where that raises the sum, no hex falls below the worst one around the point or below
  // `floor`. The joint ascent leaves these points where the sweeps for the worst hex put
  // them. Returns the number of moves.
  std::size_t boundary_mean_sweep(double floor) {
    std::atomic<std::size_t> moves{0};
    for (const std::vector<Index>& colour : colours_) {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, colour.size(), kGrain), [&](const auto& range) {
        MoveScratch scratch;
        std::size_t local = 0;
        for (std::size_t k = range.begin(); k != range.end(); ++k)
          if (boundary_[colour[k]]) local += raise_sum_at(colour[k], floor, scratch);
        moves.fetch_add(local, std::memory_order_relaxed);
      });
    }
    return moves.load();
  }

  // Boundary points of the hexes still inverted stop being put back on the surface: where
  // the surface folds tighter than a hex, no point on it unfolds the hex, and a valid mesh a
  // little off the surface there beats an inverted one on it. Returns how many were released.
  std::size_t release_boundary_of_inverted() {
    std::size_t released = 0;
    released_.resize(mesh_.points.size(), 0);
    for (std::size_t h = 0; h < mesh_.hexes.size(); ++h)
      if (score_[h] <= 0)
        for (const Index v : mesh_.hexes[h])
          if (boundary_[v] && !released_[v]) released_[v] = 1, ++released;
    any_released_ = any_released_ || released > 0;
    return released;
  }

 private:
  // Knupp's untangling of one point: Gauss-Newton steps towards kUntangleTarget for every
  // normalised determinant that depends on the point, each accepted only if the smallest of
  // them grows (after projection for a boundary point).
  bool untangle_point(Index v, std::vector<Sample>& samples) {
    const Vec3 start = mesh_.points[v];
    const auto ring = neighbours_.row(v);
    double length = 0;
    for (const Index u : ring) length += (mesh_.points[u] - start).norm();
    if (ring.empty() || !(length > 0)) return false;
    length /= static_cast<double>(ring.size());
    const double scale = 1 / (length * length * length);
    samples.clear();
    for (const Index h : point_hexes_.row(v)) {
      std::array<Vec3, 8> p;
      const int local = hex_points(h, v, p);
      append_samples(p, local, scale, samples);
    }
    const auto worst = [&](const Vec3& x) {
      double smallest = std::numeric_limits<double>::infinity();
      for (const Sample& s : samples) smallest = std::min(smallest, s.q + s.g.dot(x - start));
      return smallest;
    };
    // Once boundary points are released, raising the worst sample must not turn a positive
    // one negative: a fold was pushed into its valid neighbours, and that cascaded on the
    // bunny from 25 inverted hexes to 50,000. Before, the freedom to do so is what untangles
    // most folds (fertility: 1 inverted hex left with it, 88 without).
    const auto inverts_a_positive_sample = [&](const Vec3& x) {
      if (!any_released_) return false;
      for (const Sample& s : samples)
        if (s.q > 0 && s.q + s.g.dot(x - start) <= 0) return true;
      return false;
    };
    Vec3 position = start;
    double current = worst(position);
    bool moved = false;
    for (int step = 0; step < kUntangleSteps && current < kUntangleTarget; ++step) {
      Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
      Vec3 rhs = Vec3::Zero();
      for (const Sample& s : samples) {
        const double shortfall = kUntangleTarget - (s.q + s.g.dot(position - start));
        if (shortfall <= 0) continue;
        normal += s.g * s.g.transpose();
        rhs += shortfall * s.g;
      }
      const double trace = normal.trace();
      if (!(trace > 0)) break;
      // A little damping for the directions no short sample constrains (one sample gives a
      // rank-one system), and a step of at most one edge length.
      normal.diagonal().array() += 1e-6 * trace;
      Vec3 direction = normal.ldlt().solve(rhs);
      if (!direction.allFinite()) break;
      if (const double norm = direction.norm(); norm > length) direction *= length / norm;
      bool accepted = false;
      double t = 1;
      for (int halving = 0; halving <= kLineSearchHalvings && !accepted; ++halving, t *= 0.5) {
        const Vec3 candidate = put_back(v, position + t * direction);
        // The determinants grow with the hexes: on the surface, nothing else holds a point
        // that stretches its hexes, and step by step it can walk across the solid (the
        // bunny's: 1.3 units, half the diagonal; its quads then spanned the solid, D_g
        // 0.16). Boundary points stay within kMaxBoundaryDrift boundary edges of their start.
        if (boundary_[v] && (candidate - origin_[v]).norm() > kMaxBoundaryDrift * release_limit_) continue;
        const double value = worst(candidate);
        if (value > current + kMinimumGain && !inverts_a_positive_sample(candidate)) {
          position = candidate;
          current = value;
          accepted = true;
        }
      }
      if (!accepted) break;
      moved = true;
    }
    if (moved) {
      mesh_.points[v] = position;
      rescore(v);
    }
    return moved;
  }

  // Before a point's tries: for each of its hexes, where the point is in it and the worst of
  // the 4 corner samples that do not use the point (kInvalidScore if one is degenerate). A
  // try then evaluates the other 5 samples only (6 tries per point on the bunny at 80k hexes:
  // 34 samples per point instead of 54).
  void prepare_tries(Index v, MoveScratch& scratch) const {
    const auto hexes = point_hexes_.row(v);
    scratch.local.clear();
    scratch.fixed.clear();
    for (const Index h : hexes) {
      std::array<Vec3, 8> p;
      const int l = hex_points(h, v, p);
      double fixed = std::numeric_limits<double>::infinity();
      for (const int c : kCornersNotUsing[static_cast<std::size_t>(l)]) {
        const std::optional<double> sample = hex_jacobian_sample::corner(p, c);
        if (!sample) {
          fixed = kInvalidScore;
          break;
        }
        fixed = std::min(fixed, *sample);
      }
      scratch.local.push_back(static_cast<std::uint8_t>(l));
      scratch.fixed.push_back(fixed);
    }
  }

  // Tries a new position for v (after prepare_tries): kept (with the scores of v's hexes) if
  // no hex of v gets below their old worst value or a valid one inverts, and the worst value
  // or the sum rises (with `sum_only`, the sum). The same decision as scoring each hex in
  // full: a sample below old_min puts its hex below old_min whatever the others are (a
  // degenerate one scores kInvalidScore, below every sample).
  bool try_position(Index v, const Vec3& candidate, double old_min, double old_sum, MoveScratch& scratch,
                    bool sum_only = false) {
    const auto hexes = point_hexes_.row(v);
    mesh_.points[v] = candidate;
    scratch.scores.clear();
    double new_min = std::numeric_limits<double>::infinity(), new_sum = 0;
    for (std::size_t k = 0; k < hexes.size(); ++k) {
      const Index h = hexes[k];
      std::array<Vec3, 8> p;
      for (std::size_t i = 0; i < 8; ++i) p[i] = mesh_.points[mesh_.hexes[h][i]];
      double s = scratch.fixed[k];
      if (s != kInvalidScore) {
        const auto raise = [&](const std::optional<double>& sample) {
          if (!sample) return s = kInvalidScore, false;
          s = std::min(s, *sample);
          return *sample >= old_min;
        };
        if (!raise(hex_jacobian_sample::centre(p))) {
          if (s != kInvalidScore) return false;
        } else {
          for (const int c : hex_jacobian_sample::kCornersUsing[scratch.local[k]])
            if (!raise(hex_jacobian_sample::corner(p, c))) {
              if (s != kInvalidScore) return false;
              break;
            }
        }
      }
      if (s < old_min || (score_[h] > 0 && s <= 0)) return false;
      new_min = std::min(new_min, s);
      new_sum += s;
      scratch.scores.push_back(s);
    }
    if (sum_only ? !(new_sum > old_sum + kMinimumSumGain) : !(new_min > old_min || new_sum > old_sum)) return false;
    for (std::size_t k = 0; k < hexes.size(); ++k) score_[hexes[k]] = scratch.scores[k];
    return true;
  }

  // Two ascent directions for v: one that raises every Verdict sample (scaled Jacobian of a
  // corner or of the centre's principal axes) that depends on v and is within
  // kActiveTolerance of the worst of them, and the gradient of the sum of the scores of v's
  // hexes (each hex's worst sample, where that one depends on v). The scaled Jacobian
  // s = det(a, b, d) / (|a| |b| |d|) has ds/da = (b x d) / (|a| |b| |d|) - s a / |a|², and so
  // on for b and d.
  std::pair<Vec3, Vec3> ascent_directions(Index v, std::vector<std::pair<double, Vec3>>& samples) const {
    samples.clear();
    Vec3 sum_gradient = Vec3::Zero();
    for (const Index h : point_hexes_.row(v)) {
      std::array<Vec3, 8> p;
      const int l = hex_points(h, v, p);
      double hex_worst = std::numeric_limits<double>::infinity();
      Vec3 hex_gradient = Vec3::Zero();
      // A sample [a b d] whose edges change by wa, wb, wd times v's displacement.
      const auto sample = [&](const Vec3& a, const Vec3& b, const Vec3& d, double wa, double wb, double wd) {
        const double la = a.norm(), lb = b.norm(), ld = d.norm();
        const double lengths = la * lb * ld;
        if (!(lengths > 0)) return;
        const Vec3 bd = b.cross(d), da = d.cross(a), ab = a.cross(b);
        const double s = a.dot(bd) / lengths;
        const Vec3 gradient = wa * (bd / lengths - s * a / (la * la)) + wb * (da / lengths - s * b / (lb * lb)) +
                              wd * (ab / lengths - s * d / (ld * ld));
        samples.emplace_back(s, gradient);
        if (s < hex_worst) hex_worst = s, hex_gradient = gradient;
      };
      for (const auto& [o, i, j, k] : kCorners) {
        if (l != o && l != i && l != j && l != k) continue;
        const auto weight = [&](int end) { return l == end ? 1.0 : l == o ? -1.0 : 0.0; };
        sample(p[i] - p[o], p[j] - p[o], p[k] - p[o], weight(i), weight(j), weight(k));
      }
      const auto [x, y, z] = principal_axes(p);
      sample(x, y, z, kAxisSigns[l][0], kAxisSigns[l][1], kAxisSigns[l][2]);
      // Only where the hex's score is this sample: else moving v does not change it.
      if (hex_worst <= score_[h] + 1e-12) sum_gradient += hex_gradient;
    }
    if (samples.empty()) return {Vec3::Zero(), sum_gradient};
    // A point on the surface moves in its tangent plane (then back onto the surface): the
    // gradients' normal parts would only be projected away.
    if (boundary_[v] && !released_[v]) {
      if (const Vec3 normal = surface_normal(v); normal.squaredNorm() > 0) {
        for (auto& sample : samples) sample.second -= normal.dot(sample.second) * normal;
        sum_gradient -= normal.dot(sum_gradient) * normal;
      }
    }
    // The steepest ascent of the smallest of the active samples is the point of least norm
    // in the convex hull of their gradients (Freitag and Plassmann's optimisation-based
    // smoothing); found by Gilbert's algorithm. The worst one's gradient alone zigzags
    // between two samples that limit each other.
    const double worst = std::min_element(samples.begin(), samples.end(), [](const auto& a, const auto& b) {
                           return a.first < b.first;
                         })->first;
    std::erase_if(samples, [&](const auto& s) { return s.first > worst + kActiveTolerance; });
    Vec3 direction = samples.front().second;
    for (int iteration = 0; iteration < 50; ++iteration) {
      const auto lowest = std::min_element(samples.begin(), samples.end(), [&](const auto& a, const auto& b) {
        return a.second.dot(direction) < b.second.dot(direction);
      });
      const Vec3 towards = lowest->second - direction;
      const double gap = -direction.dot(towards);
      if (!(gap > 1e-9 * direction.squaredNorm()) || !(towards.squaredNorm() > 0)) break;
      direction += std::min(1.0, gap / towards.squaredNorm()) * towards;
    }
    return {direction, sum_gradient};
  }

  // The unit normal of the surface at boundary point v: the area-weighted mean of its
  // boundary quads' normals (zero if they cancel).
  Vec3 surface_normal(Index v) const {
    Vec3 normal = Vec3::Zero();
    for (const Index q : point_quads_.row(v)) normal += quad_normal(mesh_.points, quads_[q]);
    return normal.squaredNorm() > 0 ? Vec3(normal.normalized()) : Vec3::Zero();
  }

  // The worst and the sum of the scores of v's hexes.
  std::pair<double, double> scores_around(Index v) const {
    double worst = std::numeric_limits<double>::infinity(), sum = 0;
    for (const Index h : point_hexes_.row(v)) {
      worst = std::min(worst, score_[h]);
      sum += score_[h];
    }
    return {worst, sum};
  }

  // The centroid of the points `ring`; their mean distance from `from`.
  Vec3 centroid_of(std::span<const Index> ring) const {
    Vec3 centroid = Vec3::Zero();
    for (const Index u : ring) centroid += mesh_.points[u];
    return centroid / static_cast<double>(ring.size());
  }
  double mean_distance(std::span<const Index> ring, const Vec3& from) const {
    double length = 0;
    for (const Index u : ring) length += (mesh_.points[u] - from).norm();
    return length / static_cast<double>(ring.size());
  }

  // A move of boundary_mean_sweep(): kept if the sum of v's hex scores rises and none falls
  // below min(their worst, floor).
  bool raise_sum_at(Index v, double floor, MoveScratch& scratch) {
    const auto [old_min, old_sum] = scores_around(v);
    const auto ring = surface_neighbours_.row(v);
    if (!(old_min > 0) || ring.empty()) return false;
    const double lowest = std::min(old_min, floor);
    const Vec3 start = mesh_.points[v];
    const Vec3 centroid = centroid_of(ring);
    const double length = mean_distance(ring, start);
    prepare_tries(v, scratch);
    thread_local std::vector<std::pair<double, Vec3>> samples;
    const Vec3 gradient = ascent_directions(v, samples).second;
    if (const double norm = gradient.norm(); norm > 0 && std::isfinite(norm))
      for (double step = kAscentFirstStep * length; step > kAscentLastStep * length; step *= 0.5) {
        const Vec3 candidate = put_back(v, start + step / norm * gradient);
        if (candidate != start && try_position(v, candidate, lowest, old_sum, scratch, true)) return true;
      }
    for (const double fraction : kSmoothingSteps) {
      if (fraction > 1) continue;
      const Vec3 candidate = put_back(v, start + fraction * (centroid - start));
      if (candidate != start && try_position(v, candidate, lowest, old_sum, scratch, true)) return true;
    }
    mesh_.points[v] = start;
    return false;
  }

  // One smoothing move: the first of the steps towards the Laplacian centroid, then up the
  // score gradients, that try_position() keeps. A boundary point's centroid is that of its
  // neighbours on the boundary (its inner neighbour would only pull it off the surface), and
  // its candidates are projected.
  bool smooth_point(Index v, MoveScratch& scratch) {
    const auto [old_min, old_sum] = scores_around(v);
    if (old_min >= 1) return false;  // only perfect cubes: nothing to improve
    const auto ring = boundary_[v] ? surface_neighbours_.row(v) : neighbours_.row(v);
    if (ring.empty()) return false;
    const Vec3 centroid = centroid_of(ring);
    const Vec3 start = mesh_.points[v];
    prepare_tries(v, scratch);
    for (const double fraction : kSmoothingSteps) {
      if (fraction > 1 && boundary_[v]) continue;
      const Vec3 candidate = put_back(v, start + fraction * (centroid - start));
      if (candidate != start && try_position(v, candidate, old_min, old_sum, scratch)) return true;
    }
    mesh_.points[v] = start;
    if (old_min <= 0) return false;
    // Then steps up the gradient of the worst scaled Jacobian samples around v, and of the
    // sum of the scores of v's hexes: the centroid does not know which hex is worst, and
    // stalls where it would pull any point off its best place (docs/design/hex.md: on the
    // hand at 10k hexes, worst hex 0.18 with the centroid moves alone, 0.70 with these).
    const double length = mean_distance(ring, start);
    thread_local std::vector<std::pair<double, Vec3>> samples;
    const auto [worst_gradient, sum_gradient] = ascent_directions(v, samples);
    for (const Vec3& gradient : {worst_gradient, sum_gradient}) {
      const double norm = gradient.norm();
      if (!(norm > 0) || !std::isfinite(norm)) continue;
      const Vec3 direction = gradient / norm;
      for (double step = kAscentFirstStep * length; step > kAscentLastStep * length; step *= 0.5) {
        const Vec3 candidate = put_back(v, start + step * direction);
        if (candidate != start && try_position(v, candidate, old_min, old_sum, scratch)) return true;
      }
      mesh_.points[v] = start;
    }
    return false;
  }

  HexMesh& mesh_;
  const HintedProjection& project_;
  // Per point: the surface triangle put_back() last projected it to (kInvalidIndex: none).
  mutable std::vector<Index> hint_triangle_;
  CompressedRows point_hexes_, neighbours_, surface_neighbours_;
  std::vector<std::array<Index, 4>> quads_;  // the boundary quads
  CompressedRows point_quads_;               // point -> its boundary quads
  std::vector<std::uint8_t> boundary_;
  std::vector<std::vector<Index>> colours_;  // movable points of each colour, ascending
  std::vector<double> score_;                // Verdict scaled Jacobian per hex
  std::size_t feature_points_ = 0;
  std::vector<std::uint8_t> released_;  // boundary points no longer put back on the surface
  std::vector<std::uint8_t> movable_;   // neither fixed boundary nor feature points
  double release_limit_ = 0;            // how far a released point may leave the surface
  std::vector<Vec3> origin_;            // where the points were before the smoothing
  bool any_released_ = false;
  // Smoothing sweeps: the colour epoch at which each point last moved and was last tried.
  std::vector<std::uint32_t> moved_at_, tried_at_;
  std::uint32_t epoch_ = 0;
  // If not empty, the only points the smoothing sweeps move (reset_worst's region and rings).
  std::vector<std::uint8_t> focus_;
};

}  // namespace

// The untangling: rounds of one-point moves, attempts that release boundary points, then
// joint untangling of what is left. Returns the scores' statistics after it; adds the
// boundary points it let off the surface to `released`.
ScoreStatistics untangle(Smoother& smoother, HexMesh& mesh, const HexSmoothingOptions& options, ScoreStatistics current,
                         std::size_t& released) {
  // Untangling rounds on the surface first. Then, for stuck clusters (points whose hexes all
  // hold each other in place), the boundary points of the hexes still inverted are let go,
  // and from the second such attempt on a smoothing sweep moves the valid neighbours first.
  for (int attempt = 0; attempt <= 8 && current.inverted > 0; ++attempt) {
    const std::size_t inverted_before_attempt = current.inverted;
    if (attempt > 0) {
      if (!options.move_boundary) break;
      released += smoother.release_boundary_of_inverted();
      if (attempt > 1) smoother.smoothing_sweep();
    }
    // The rounds lower each point's worst determinant, which can raise the count of
    // inverted hexes for dozens of rounds (the dog's first polycube: 583 after 11 rounds,
    // 7,388 after 100). While more than kBulkTangle are inverted, kUntangleStall rounds
    // without a new fewest end the attempt, and the points go back to where the count was
    // fewest.
    std::size_t fewest = current.inverted;
    std::vector<Vec3> fewest_points;
    if (fewest > kBulkTangle) fewest_points = mesh.points;
    for (int round = 0, since_fewest = 0; round < kUntangleRounds && current.inverted > 0; ++round) {
      const bool moved = smoother.untangle_round();
      current = score_statistics(smoother.scores());
      if (options.progress)
        status("hex smoothing: untangling round " + std::to_string(round + 1) + ", " +
               std::to_string(current.inverted) + " inverted hexes");
      if (current.inverted < fewest) {
        fewest = current.inverted;
        since_fewest = 0;
        if (fewest > kBulkTangle)
          fewest_points = mesh.points;
        else
          fewest_points.clear();
      }
      if (!moved) break;
      // Only in bulk: a few stuck hexes can come free after many rounds (stopped after
      // 30, the bunny kept 2 inverted and needed the unmerged retry: 206 s against 95 s).
      if (fewest > kBulkTangle && ++since_fewest >= kUntangleStall) break;
    }
    if (current.inverted > fewest && !fewest_points.empty()) {
      smoother.restore_points(fewest_points);
      current = score_statistics(smoother.scores());
    }
    // A mesh tangled in bulk (thousands of hexes, as where a part of the polycube is one
    // voxel thick) gains a handful per attempt at minutes each: the caller's retry on
    // another polycube does better than eight more.
    if (attempt > 0 && current.inverted > kBulkTangle &&
        static_cast<double>(current.inverted) > 0.98 * static_cast<double>(inverted_before_attempt))
      break;
  }

  // Folds the one-point moves leave: joint untangling of their regions, first with the
  // boundary on the surface, then with it free, each followed by the one-point rounds.
  // Not for a mesh tangled in bulk: the regions merge into one the joint solve takes
  // minutes on (the dog's first polycube: 4,600 inverted hexes, 100 s, none fewer). On the
  // 12 bench models it was kept only where 1 to 13 hexes were left; at the dog's 121 and 163
  // it was refused four times, 25 s in all.
  for (const bool free_boundary : {false, true}) {
    if (current.inverted == 0 || current.inverted > kBulkTangle || (free_boundary && !options.move_boundary)) break;
    if (!smoother.untangle_regions(free_boundary)) continue;
    current = score_statistics(smoother.scores());
    for (int round = 0; round < kUntangleRounds && current.inverted > 0; ++round) {
      const bool moved = smoother.untangle_round();
      current = score_statistics(smoother.scores());
      if (!moved) break;
    }
    if (options.progress)
      status("hex smoothing: joint untangling" + std::string(free_boundary ? " with the boundary free" : "") + ", " +
             std::to_string(current.inverted) + " inverted hexes");
  }

  return current;
}

// Joint ascents of the worst hexes (polish_worst), each followed by sweeps of the whole mesh,
// while they raise the worst hex and it is below options.polish_below. Counts the rounds in
// `rounds`; returns the scores' statistics after them.
ScoreStatistics polish(Smoother& smoother, const HexSmoothingOptions& options, ScoreStatistics current, int& rounds) {
  for (int round = 0; round < kPolishRounds && current.inverted == 0 && current.min < options.polish_below; ++round) {
    if (!smoother.polish_worst(kPolishMargin, kPolishRings)) break;
    for (int sweep = 0; sweep < kSweepsAfterPolish; ++sweep)
      if (smoother.smoothing_sweep(true) == 0) break;
    const double before = current.min;
    current = score_statistics(smoother.scores());
    ++rounds;
    if (!(current.min > before + kPolishMinimumGain)) break;
  }
  return current;
}

// Fresh starts of the worst cluster (Smoother::reset_worst), while the worst hex is below
// options.polish_below: its points go back to the map's positions and are untangled and swept
// again, now amid smooth hexes, which takes them down another path; a try is kept only if it
// raises the worst hex by kPolishMinimumGain. Why: the sweeps end in whichever local optimum
// the untangling led a cluster to, and rounding differences alone change which one (the
// closed dog at 10k hexes: worst hex 0.54 with OpenBLAS's AVX2 kernels, 0.14 with its AVX-512
// ones; a fresh start took the 0.14 to 0.40 in 0.6 s). The rings around the cluster that go
// back are tried from 1 to kRestartRings, from the map's positions, then from the centroids;
// the first try that pays is kept.
ScoreStatistics restart_worst(Smoother& smoother, HexMesh& mesh, const HexSmoothingOptions& options,
                              ScoreStatistics current, HexSmoothingResult& result) {
  HexSmoothingOptions quiet = options;
  quiet.progress = false;
  // Also for a few hexes the untangling left inverted (the repaired TOSCA dog0 with the
  // AVX-512 kernels: 1): a fresh start of their cluster is kept if it leaves fewer inverted.
  const auto better = [](const ScoreStatistics& a, const ScoreStatistics& b) {
    return a.inverted < b.inverted || (a.inverted == b.inverted && a.min > b.min + kPolishMinimumGain);
  };
  for (int round = 0; round < options.restart_rounds && current.inverted <= kBulkTangle &&
                      (current.inverted > 0 || current.min < options.polish_below);
       ++round) {
    if (options.progress) status("hex smoothing: fresh start of the worst hexes, round " + std::to_string(round + 1));
    bool kept = false;
    for (int attempt = 0; attempt < 2 * kRestartRings && !kept; ++attempt) {
      const int rings = 1 + attempt % kRestartRings;
      const bool centroids = attempt >= kRestartRings;
      const Smoother::Snapshot saved = smoother.snapshot();
      if (smoother.reset_worst(std::max(kRestartBelow, current.min + kPolishMargin), rings, centroids) == 0) {
        smoother.clear_focus();
        break;
      }
      ++result.restarts_tried;
      std::size_t released = 0;
      ScoreStatistics fresh = untangle(smoother, mesh, quiet, score_statistics(smoother.scores()), released);
      if (fresh.inverted <= current.inverted) {
        for (int sweep = 0; sweep < kRestartSweeps; ++sweep)
          if (smoother.smoothing_sweep(true) == 0) break;
        fresh = score_statistics(smoother.scores());
      }
      smoother.clear_focus();
      kept = better(fresh, current);
      if (kept) {
        current = fresh;
        result.released_boundary_points += released;
        ++result.restarts;
      } else {
        smoother.restore(saved);
      }
    }
    if (!kept) break;
  }
  return current;
}

HexSmoothingResult smooth_hex_mesh(HexMesh& mesh, const HintedProjection& project, const HexSmoothingOptions& options) {
  for (std::size_t h = 0; h < mesh.hexes.size(); ++h) {
    std::array<Index, 8> sorted = mesh.hexes[h];
    std::sort(sorted.begin(), sorted.end());
    if (sorted.back() >= mesh.points.size())
      throw InputError("smooth_hex_mesh: hex " + std::to_string(h) + " refers to point " +
                       std::to_string(sorted.back()) + " of " + std::to_string(mesh.points.size()));
    // A collapsed hex stays collapsed however its points move.
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      throw InputError("smooth_hex_mesh: hex " + std::to_string(h) + " uses a point twice");
  }
  if (options.move_boundary && !project)
    throw InputError("smooth_hex_mesh: move_boundary needs a projection onto the surface");
  HexSmoothingResult result;
  if (mesh.hexes.empty()) return result;

  Smoother smoother(mesh, project, options.move_boundary, options.feature_angle_degrees);
  result.feature_points = smoother.feature_points();
  const ScoreStatistics before = score_statistics(smoother.scores());
  result.inverted_before = before.inverted;
  result.min_scaled_jacobian_before = before.min;
  result.mean_scaled_jacobian_before = before.mean();

  std::size_t released = 0;
  ScoreStatistics current = untangle(smoother, mesh, options, before, released);
  result.released_boundary_points = released;

  // Nor smoothing for a mesh still tangled in bulk: the caller retries on another polycube.
  result.sweeps_held_back = current.inverted > 0 && current.inverted <= kBulkTangle && options.sweeps_only_if_untangled;
  const int sweeps = current.inverted > kBulkTangle || result.sweeps_held_back ? 0 : options.iterations;
  std::optional<Progress> progress;
  if (options.progress && sweeps > 0) progress.emplace("hex smoothing sweeps", static_cast<std::uint64_t>(sweeps));
  // The worst and mean scaled Jacobian after each sweep, to judge the gains over a window.
  std::vector<std::pair<double, double>> history{{current.min, current.mean()}};
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    const std::size_t moves = smoother.smoothing_sweep(true);
    ++result.sweeps;
    current = score_statistics(smoother.scores());
    history.emplace_back(current.min, current.mean());
    if (progress) progress->advance();
    // Go on while the worst or the mean scaled Jacobian still gains min_improvement per sweep
    // over the last kStallWindow sweeps: a single sweep may raise the worst hex while the
    // mean dips, or the other way round (kitten_40k stopped at a mean of 0.932 after a dip
    // on one sweep, while it was still gaining 5e-4 per sweep).
    if (moves == 0) break;
    if (history.size() > kStallWindow) {
      const auto& [old_min, old_mean] = history[history.size() - 1 - kStallWindow];
      const double window = static_cast<double>(kStallWindow) * options.min_improvement;
      if (current.mean() - old_mean < window && current.min - old_min < window) break;
    }
  }
  if (progress) progress->finish();
  if (sweeps > 0) {
    current = restart_worst(smoother, mesh, options, current, result);
    current = polish(smoother, options, current, result.polish_rounds);
  }
  // Last, the mean: joint ascents of the interior points, each followed by sweeps of the
  // boundary points, with the worst hex held, while the mean is below options.mean_below
  // (docs/design/hex.md: fertility at 18k hexes, mean 0.932 -> 0.942 in 1.5 s).
  result.mean_scaled_jacobian_before_ascent = current.mean();
  for (int round = 0; round < kMeanRounds && sweeps > 0 && current.inverted == 0 && current.mean() < options.mean_below;
       ++round) {
    if (options.progress) status("hex smoothing: joint ascent of the mean, round " + std::to_string(round + 1));
    const double before = current.mean();
    const bool moved = smoother.raise_mean(current.min);
    // The boundary sweeps stop when one gains less than kBoundarySweepGain of the mean.
    double mean = score_statistics(smoother.scores()).mean();
    for (int sweep = 0; sweep < kBoundaryMeanSweeps; ++sweep) {
      if (smoother.boundary_mean_sweep(current.min + kMeanFloorMargin) == 0) break;
      const double swept = score_statistics(smoother.scores()).mean();
      if (!(swept > mean + kBoundarySweepGain)) break;
      mean = swept;
    }
    current = score_statistics(smoother.scores());
    ++result.mean_ascent_rounds;
    if (!moved || !(current.mean() > before + kMeanMinimumGain)) break;
  }

  result.inverted_after = current.inverted;
  result.min_scaled_jacobian_after = current.min;
  result.mean_scaled_jacobian_after = current.mean();
  return result;
}

}  // namespace structmesh
