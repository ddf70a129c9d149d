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
#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>

namespace structmesh {

namespace {

// Breaks below this interior angle are corner candidates (as in sample_partition()).
constexpr double kCornerAngle = 150.0 * std::numbers::pi / 180.0;
constexpr std::size_t kMaxCorners = 8;
// Transition layouts keep up to this many corners (the centre's valence is one more).
// Five and six were tried: on the Key no further part passed, and on the Pipe the one
// part that passes lost its layout, as six-corner layouts (fewer corners left out)
// ranked first and used up the tries.
constexpr std::size_t kMaxTransitionCorners = 4;
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

struct LoopCorner {
  std::int64_t at;
  double turn;
};

// Corners: runs of consecutive bent points (each below 170°) whose turns add up to
// more than 30° (a separator's corner is often rounded over two samples), each at
// its sharpest point, with the run's total turn; sharpest first.
std::vector<LoopCorner> loop_corners(std::span<const Vec2> ring) {
  const auto n = static_cast<std::int64_t>(ring.size());
  std::vector<LoopCorner> corners_found;
  std::vector<double> turn(static_cast<std::size_t>(n));
  for (std::int64_t i = 0; i < n; ++i)
    turn[static_cast<std::size_t>(i)] = std::numbers::pi - interior_angle(ring, static_cast<std::size_t>(i));
  std::int64_t first = 0;  // a point that starts no run: the loop is scanned from just after it
  while (first < n && turn[static_cast<std::size_t>(first)] > kBentTurn) ++first;
  if (first == n) return corners_found;
  for (std::int64_t step = 1; step <= n;) {
    const std::int64_t i = (first + step) % n;
    if (turn[static_cast<std::size_t>(i)] <= kBentTurn) {
      ++step;
      continue;
    }
    LoopCorner corner{i, 0.0};
    for (; step <= n && turn[static_cast<std::size_t>((first + step) % n)] > kBentTurn; ++step) {
      const std::int64_t j = (first + step) % n;
      corner.turn += turn[static_cast<std::size_t>(j)];
      if (turn[static_cast<std::size_t>(j)] > turn[static_cast<std::size_t>(corner.at)]) corner.at = j;
    }
    if (corner.turn > std::numbers::pi - kCornerAngle) corners_found.push_back(corner);
  }
  std::stable_sort(corners_found.begin(), corners_found.end(),
                   [](const LoopCorner& a, const LoopCorner& b) { return a.turn > b.turn; });
  return corners_found;
}

// The loop positions of the corners in `mask` (bit i: corners[i]), ascending, and
// their total turn.
std::vector<std::int64_t> corner_subset(const std::vector<LoopCorner>& corners, std::uint32_t mask, double& kept_turn) {
  std::vector<std::int64_t> positions;
  kept_turn = 0;
  for (std::size_t i = 0; i < corners.size(); ++i)
    if (mask & (1u << i)) {
      positions.push_back(corners[i].at);
      kept_turn += corners[i].turn;
    }
  std::sort(positions.begin(), positions.end());
  return positions;
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

  std::vector<LoopCorner> corners_found = loop_corners(ring);
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
  for (const LoopCorner& c : corners_found) total_turn += c.turn;
  for (std::uint32_t mask = 1; mask < (1u << m); ++mask) {
    const auto k = static_cast<std::size_t>(std::popcount(mask));
    if (k < 3 || k % 2 == 0) continue;
    double kept_turn = 0;
    const std::vector<std::int64_t> base = corner_subset(corners_found, mask, kept_turn);
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

std::vector<PolarBlocks> transition_block_candidates(const Polygon2& boundary, std::size_t max_candidates) {
  std::vector<PolarBlocks> candidates;
  if (boundary.ring_count() != 1 || max_candidates == 0) return candidates;
  const std::span<const Vec2> ring = boundary.ring(0);
  const auto n = static_cast<std::int64_t>(ring.size());
  if (n < 8 || n % 2 != 0) return candidates;
  std::vector<LoopCorner> corners_found = loop_corners(ring);
  if (corners_found.size() < 4 || corners_found.size() > kMaxCorners) return candidates;
  if (corners_found.size() > kMaxCorners - 1) corners_found.resize(kMaxCorners - 1);
  const std::size_t m = corners_found.size();
  double total_turn = 0;
  for (const LoopCorner& c : corners_found) total_turn += c.turn;

  // Every set of k = 4..kMaxTransitionCorners corners, the triangle on each of its
  // sides in turn. With the corners q_0..q_{k-1} from the triangle's side on and c_i the
  // chord of the split on side i (i >= 1), a and b the triangle's legs (the chords of
  // the splits at its ends, next to q_0 and q_1) and x its base: side i has
  // c_{i-1} + c_{i+1} segments (c_0 read as b on side 1, c_k as a on side k-1) and side
  // 0 has c_{k-1} + x + c_1. Given e = c_1 and h = c_2 the rest follows along the sides.
  // Per set and side the (e, h) of best score: the turn of the corners left out (as in
  // polar_block_candidates()), plus how far the triangle is from equilateral (its
  // legs against its base; measured on the Key, a flat triangle with short legs left
  // sheared quads, mean 0.82, where legs as long as the base gave 0.99), plus a
  // quarter of the imbalance of the chords on either side of it.
  struct Scored {
    double score;
    PolarBlocks blocks;
  };
  std::vector<Scored> scored;
  for (std::uint32_t mask = 1; mask < (1u << m); ++mask) {
    const auto k = static_cast<std::size_t>(std::popcount(mask));
    if (k < 4 || k > kMaxTransitionCorners) continue;
    double kept_turn = 0;
    const std::vector<std::int64_t> q = corner_subset(corners_found, mask, kept_turn);
    // c: the corners unwrapped; s: the side counts; cs[i] = c_i for i = 1..k-1.
    std::vector<std::int64_t> c(k + 1), s(k), cs(k), split(k + 1), corner(k + 1);
    for (std::size_t t = 0; t < k; ++t) {
      // Corners from the triangle's side on, unwrapped past the loop's end.
      for (std::size_t j = 0; j < k; ++j) c[j] = q[(t + j) % k] + (t + j >= k ? n : 0);
      c[k] = c[0] + n;
      std::int64_t longest = 0;
      for (std::size_t j = 0; j < k; ++j) s[j] = c[j + 1] - c[j], longest = std::max(longest, s[j]);
      std::optional<Scored> best;
      for (std::int64_t e = 1; e < longest; ++e)
        for (std::int64_t h = 1; h < longest; ++h) {
          cs[1] = e, cs[2] = h;
          bool positive = true;
          for (std::size_t i = 2; i + 1 < k && positive; ++i) {
            cs[i + 1] = s[i] - cs[i - 1];
            positive = cs[i + 1] >= 1;
          }
          if (!positive) continue;
          const std::int64_t a = s[k - 1] - cs[k - 2], b = s[1] - cs[2], x = s[0] - cs[k - 1] - cs[1];
          if (a < 1 || b < 1 || x < 2 || !(x < a + b && a < x + b && b < x + a)) continue;
          const double balance =
              std::abs(static_cast<double>(cs[1] - cs[k - 1])) / static_cast<double>(cs[1] + cs[k - 1]);
          const double score =
              (total_turn - kept_turn) +
              (std::abs(static_cast<double>(a - x)) + std::abs(static_cast<double>(b - x))) / static_cast<double>(x) +
              0.25 * balance;
          if (best && !(score < best->score)) continue;
          // Layout order: q_0, the triangle's corner (mid-base), q_1, ..., q_{k-1};
          // splits at q_0 + c_{k-1} and q_1 - c_1 (the base between them), then side
          // i's at q_i + c_{i-1} (b for i = 1).
          corner[0] = c[0], corner[1] = c[0] + cs[k - 1] + x / 2;
          split[0] = c[0] + cs[k - 1], split[1] = c[1] - cs[1];
          std::vector<Index> layout_chords{static_cast<Index>(a), static_cast<Index>(b)};
          for (std::size_t i = 1; i < k; ++i) {
            corner[i + 1] = c[i];
            split[i + 1] = c[i] + (i == 1 ? b : cs[i - 1]);
            layout_chords.push_back(static_cast<Index>(cs[i]));
          }
          // Rotated so the corners ascend from the smallest loop position.
          PolarBlocks blocks;
          std::size_t first = 0;
          for (std::size_t j = 1; j <= k; ++j)
            if (corner[j] % n < corner[first] % n) first = j;
          for (std::size_t j = 0; j <= k; ++j) {
            const std::size_t at = (first + j) % (k + 1);
            blocks.corners.push_back(corner[at] % n);
            blocks.splits.push_back(split[at] % n);
            blocks.chord_segments.push_back(layout_chords[at]);
            blocks.triangle.push_back(at == 1 ? 1 : 0);
          }
          best = Scored{score, std::move(blocks)};
        }
      if (best) scored.push_back(std::move(*best));
    }
  }
  std::stable_sort(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) { return a.score < b.score; });
  for (std::size_t i = 0; i < scored.size() && i < max_candidates; ++i)
    candidates.push_back(std::move(scored[i].blocks));
  return candidates;
}

}  // namespace structmesh
