// polar_block_candidates(): polar block layouts (polar_mesh()) for a part whose
// boundary counts are already fixed.
//
// The interval assignment (sample_partition()) plans blocks only for parts it can
// reward within its node limit, and a planned layout can still fail polar_mesh()'s
// quality check. Either way the part used to be paved, and a paved part of about 2k
// quads carries some 50 interior singular vertices against the one centre of a polar
// layout (the Key in 32 parts: 11 paved parts held 530 of its 560). With the counts
// fixed, a layout still exists for most choices of corners: around a centre with k
// corners, side i (corner i to corner i+1) must have r_{i-1} + r_{i+1} segments, r
// the chords' counts. For odd k that system has exactly one solution; for k = 3 it is
// r_i = n/2 - s_{i+1} (s the side counts, n their even sum), so any three corners
// that leave every side shorter than half the loop work. So the corners are taken
// from the part's sharpest breaks, and moved by a segment where the chords' counts
// come out as half-integers.
#include "structmesh/quad2d.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

namespace structmesh {

namespace {

// Breaks below this interior angle are corner candidates (as in sample_partition()).
constexpr double kCornerAngle = 150.0 * std::numbers::pi / 180.0;
constexpr std::size_t kMaxCorners = 8;
// A point bent by more than this may be part of a rounded corner.
constexpr double kBentTurn = 10.0 * std::numbers::pi / 180.0;

// Interior angle of a counter-clockwise loop at point i (pi on a straight side,
// below pi at a convex corner).
double interior_angle(std::span<const Vec2> ring, std::size_t i) {
  const std::size_t n = ring.size();
  const Vec2 in = ring[i] - ring[(i + n - 1) % n], out = ring[(i + 1) % n] - ring[i];
  const double turn = std::atan2(in.x() * out.y() - in.y() * out.x(), in.dot(out));
  return std::numbers::pi - turn;
}

// The chord counts of a layout with these corners (ascending loop positions), or an
// empty vector when they are not positive integers.
std::vector<Index> chord_counts(const std::vector<std::int64_t>& corners, std::int64_t n) {
  const std::size_t k = corners.size();
  Eigen::VectorXd sides(static_cast<Eigen::Index>(k));
  for (std::size_t i = 0; i < k; ++i) {
    const std::int64_t next = i + 1 < k ? corners[i + 1] : corners[0] + n;
    sides[static_cast<Eigen::Index>(i)] = static_cast<double>(next - corners[i]);
  }
  // s_i = r_{i-1} + r_{i+1}: regular for odd k (the circulant's eigenvalues
  // 2 cos(4 pi j / k) vanish only for even k).
  Eigen::MatrixXd system = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
  for (std::size_t i = 0; i < k; ++i) {
    system(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>((i + k - 1) % k)) += 1.0;
    system(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>((i + 1) % k)) += 1.0;
  }
  const Eigen::VectorXd r = system.colPivHouseholderQr().solve(sides);
  if (!((system * r - sides).norm() < 1e-6)) return {};
  std::vector<Index> counts;
  for (std::size_t i = 0; i < k; ++i) {
    const double value = r[static_cast<Eigen::Index>(i)];
    const double rounded = std::round(value);
    if (std::abs(value - rounded) > 1e-6 || rounded < 1) return {};
    counts.push_back(static_cast<Index>(rounded));
  }
  return counts;
}

}  // namespace

std::vector<PolarBlocks> polar_block_candidates(const Polygon2& boundary, std::size_t max_candidates) {
  std::vector<PolarBlocks> candidates;
  if (boundary.ring_count() != 1 || max_candidates == 0) return candidates;
  const std::span<const Vec2> ring = boundary.ring(0);
  const auto n = static_cast<std::int64_t>(ring.size());
  if (n < 6 || n % 2 != 0) return candidates;
  double perimeter = 0;
  for (std::int64_t i = 0; i < n; ++i)
    perimeter += (ring[static_cast<std::size_t>((i + 1) % n)] - ring[static_cast<std::size_t>(i)]).norm();
  const double size = perimeter / static_cast<double>(n);

  // Corners: runs of consecutive bent points (each below 170°) whose turns add up to
  // more than 30° (a separator's corner is often rounded over two samples), each at
  // its sharpest point, with the run's total turn.
  std::vector<double> turn(static_cast<std::size_t>(n));
  for (std::int64_t i = 0; i < n; ++i)
    turn[static_cast<std::size_t>(i)] = std::numbers::pi - interior_angle(ring, static_cast<std::size_t>(i));
  std::int64_t first = 0;  // a point that starts no run: the loop is scanned from just after it
  while (first < n && turn[static_cast<std::size_t>(first)] > kBentTurn) ++first;
  if (first == n) return candidates;
  struct Corner {
    std::int64_t at;
    double turn;
  };
  std::vector<Corner> corners_found;
  for (std::int64_t step = 1; step <= n;) {
    const std::int64_t i = (first + step) % n;
    if (turn[static_cast<std::size_t>(i)] <= kBentTurn) {
      ++step;
      continue;
    }
    Corner corner{i, 0.0};
    for (; step <= n && turn[static_cast<std::size_t>((first + step) % n)] > kBentTurn; ++step) {
      const std::int64_t j = (first + step) % n;
      corner.turn += turn[static_cast<std::size_t>(j)];
      if (turn[static_cast<std::size_t>(j)] > turn[static_cast<std::size_t>(corner.at)]) corner.at = j;
    }
    if (corner.turn > std::numbers::pi - kCornerAngle) corners_found.push_back(corner);
  }
  std::stable_sort(corners_found.begin(), corners_found.end(),
                   [](const Corner& a, const Corner& b) { return a.turn > b.turn; });
  if (corners_found.size() > kMaxCorners) return candidates;
  if (corners_found.size() > kMaxCorners - 1) corners_found.resize(kMaxCorners - 1);
  const std::size_t m = corners_found.size();
  if (m < 3) return candidates;

  // Every odd subset of at least 3 of them, each as it is or with one corner moved by
  // one point (half-integer chord counts become integers), scored by the turn its
  // dropped corners leave on block sides plus the chords' relative deviation from
  // their straight length to the mean of the loop's points (near polar_mesh()'s area centroid).
  struct Scored {
    double score;
    PolarBlocks blocks;
  };
  std::vector<Scored> scored;
  const Vec2 centre = [&] {
    Vec2 sum = Vec2::Zero();
    for (const Vec2& p : ring) sum += p;
    return Vec2(sum / static_cast<double>(n));
  }();
  double total_turn = 0;
  for (const Corner& c : corners_found) total_turn += c.turn;
  for (std::uint32_t mask = 1; mask < (1u << m); ++mask) {
    const auto k = static_cast<std::size_t>(std::popcount(mask));
    if (k < 3 || k % 2 == 0) continue;
    std::vector<std::int64_t> base;
    double kept_turn = 0;
    for (std::size_t i = 0; i < m; ++i)
      if (mask & (1u << i)) {
        base.push_back(corners_found[i].at);
        kept_turn += corners_found[i].turn;
      }
    std::sort(base.begin(), base.end());
    std::vector<std::vector<std::int64_t>> variants{base};
    for (std::size_t j = 0; j < k; ++j)
      for (const std::int64_t shift : {std::int64_t{1}, std::int64_t{-1}}) {
        std::vector<std::int64_t> moved = base;
        moved[j] = (moved[j] + shift + n) % n;
        std::sort(moved.begin(), moved.end());
        if (std::adjacent_find(moved.begin(), moved.end()) == moved.end()) variants.push_back(std::move(moved));
      }
    for (const std::vector<std::int64_t>& corners : variants) {
      const std::vector<Index> chords = chord_counts(corners, n);
      if (chords.empty()) continue;
      PolarBlocks blocks;
      blocks.corners = corners;
      blocks.chord_segments = chords;
      double deviation = 0;
      for (std::size_t i = 0; i < k; ++i) {
        blocks.splits.push_back((corners[i] + static_cast<std::int64_t>(chords[(i + k - 1) % k])) % n);
        const double ideal =
            std::max(1.0, (ring[static_cast<std::size_t>(blocks.splits.back())] - centre).norm() / size);
        deviation += std::abs(static_cast<double>(chords[i]) - ideal) / ideal;
      }
      scored.push_back({(total_turn - kept_turn) + deviation / static_cast<double>(k), std::move(blocks)});
      break;  // one layout per corner set: its first variant that has one
    }
  }
  std::stable_sort(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) { return a.score < b.score; });
  for (std::size_t i = 0; i < scored.size() && i < max_candidates; ++i) {
    candidates.push_back(std::move(scored[i].blocks));
  }
  return candidates;
}

}  // namespace structmesh
