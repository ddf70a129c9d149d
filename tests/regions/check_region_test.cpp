#include "mesh/planar_geometry.hpp"
#include "region_test_util.hpp"
#include "structmesh/check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace structmesh {
namespace {

using test::make_polygon;
using test::rectangle;

std::size_t count_kind(const RegionReport& report, const std::string& kind) {
  return static_cast<std::size_t>(
      std::count_if(report.problems.begin(), report.problems.end(), [&](const Problem& p) { return p.kind == kind; }));
}

const Problem* first_of(const RegionReport& report, const std::string& kind) {
  for (const Problem& p : report.problems)
    if (p.kind == kind) return &p;
  return nullptr;
}

// Sign of the orientation determinant computed exactly: every coordinate below is a
// multiple of 2^-53 below 32 in magnitude, so scaled by 2^53 it is an integer under
// 2^58 and the determinant fits in 128 bits.
int exact_orientation(const Vec2& a, const Vec2& b, const Vec2& c) {
  auto integer = [](double v) { return static_cast<std::int64_t>(std::ldexp(v, 53)); };
  const __int128 acx = integer(a.x()) - integer(c.x()), acy = integer(a.y()) - integer(c.y());
  const __int128 bcx = integer(b.x()) - integer(c.x()), bcy = integer(b.y()) - integer(c.y());
  const __int128 det = acx * bcy - acy * bcx;
  return (det > 0) - (det < 0);
}

TEST(Orient2d, MatchesExactArithmeticOnNearlyCollinearPoints) {
  // Shewchuk's classic picture: a sweeps a 64x64 grid of ulps around (0.5, 0.5),
  // b = (12, 12), c = (24, 24). The naive formula gets many of these wrong.
  const double ulp = 0x1p-53;
  int naive_wrong = 0;
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 64; ++j) {
      const Vec2 a(0.5 + i * ulp, 0.5 + j * ulp), b(12, 12), c(24, 24);
      const int expected = exact_orientation(a, b, c);
      ASSERT_EQ(detail::orient2d(a, b, c), expected) << i << " " << j;
      ASSERT_EQ(detail::orient2d(b, c, a), expected) << i << " " << j;
      ASSERT_EQ(detail::orient2d(b, a, c), -expected) << i << " " << j;
      const double naive = (a.x() - c.x()) * (b.y() - c.y()) - (a.y() - c.y()) * (b.x() - c.x());
      naive_wrong += ((naive > 0) - (naive < 0)) != expected;
    }
  }
  EXPECT_GT(naive_wrong, 100);  // the cases are hard enough to need the exact stage

  // Random nearly collinear triples with the same kind of coordinates.
  std::mt19937_64 random(7);
  std::uniform_int_distribution<std::int64_t> step(-(std::int64_t{1} << 57), std::int64_t{1} << 57);
  std::uniform_int_distribution<int> nudge(-3, 3);
  for (int trial = 0; trial < 20000; ++trial) {
    auto coordinate = [&](std::int64_t units) { return std::ldexp(static_cast<double>(units), -53); };
    const std::int64_t ax = step(random) >> 4 << 4, ay = step(random) >> 4 << 4;
    const std::int64_t bx = step(random) >> 4 << 4, by = step(random) >> 4 << 4;
    // c = midpoint of a and b (exact: multiples of 16 units), nudged by a few units.
    const Vec2 a(coordinate(ax), coordinate(ay)), b(coordinate(bx), coordinate(by));
    const Vec2 c(coordinate((ax + bx) / 2 + nudge(random)), coordinate((ay + by) / 2 + nudge(random)));
    ASSERT_EQ(detail::orient2d(a, b, c), exact_orientation(a, b, c)) << trial;
  }
}

TEST(Orient2d, SegmentContactCases) {
  using detail::segment_contact;
  using detail::SegmentContact;
  EXPECT_EQ(segment_contact({0, 0}, {2, 2}, {0, 2}, {2, 0}), SegmentContact::Cross);
  EXPECT_EQ(segment_contact({0, 0}, {2, 2}, {1, 1}, {2, 0}), SegmentContact::Touch);  // endpoint on segment
  EXPECT_EQ(segment_contact({0, 0}, {2, 0}, {2, 0}, {3, 1}), SegmentContact::Touch);  // shared endpoint
  EXPECT_EQ(segment_contact({0, 0}, {2, 0}, {1, 0}, {3, 0}), SegmentContact::Touch);  // collinear overlap
  EXPECT_EQ(segment_contact({0, 0}, {1, 0}, {2, 0}, {3, 0}), SegmentContact::None);   // collinear apart
  EXPECT_EQ(segment_contact({0, 0}, {0, 1}, {0, 2}, {0, 3}), SegmentContact::None);   // vertical apart
  EXPECT_EQ(segment_contact({0, 0}, {0, 2}, {0, 1}, {0, 3}), SegmentContact::Touch);  // vertical overlap
  EXPECT_EQ(segment_contact({0, 0}, {2, 0}, {1, 1e-300}, {1, 1}), SegmentContact::None);
  // Any double point with x == y lies exactly on the diagonal.
  EXPECT_EQ(segment_contact({0, 0}, {1, 1}, {0.3, 0.3}, {0.3, 2}), SegmentContact::Touch);
}

TEST(CheckRegion, ValidSquareWithHole) {
  const RegionReport report = check_region({make_polygon({rectangle(0, 0, 10, 10), rectangle(2, 2, 4, 4, true)})});
  EXPECT_TRUE(report.valid);
  EXPECT_TRUE(report.problems.empty());
  EXPECT_EQ(report.polygons, 1u);
  EXPECT_EQ(report.rings, 2u);
  EXPECT_EQ(report.holes, 1u);
  EXPECT_EQ(report.vertices, 8u);
  EXPECT_DOUBLE_EQ(report.area, 96);
}

TEST(CheckRegion, BowTie) {
  const RegionReport report = check_region({make_polygon({{{0, 0}, {2, 2}, {2, 0}, {0, 2}}})});
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(report.self_intersections, 1u);
  const Problem* p = first_of(report, "self-intersection");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->element, 0);
  EXPECT_NE(p->message.find("polygon 0 ring 0 (outer) segment 0-1 crosses polygon 0 ring 0 (outer) segment 2-3"),
            std::string::npos)
      << p->message;
  EXPECT_NE(p->message.find("(1, 1)"), std::string::npos) << p->message;
}

TEST(CheckRegion, HoleOutside) {
  const RegionReport report = check_region(
      {make_polygon({rectangle(0, 0, 10, 10), rectangle(1, 1, 2, 2, true), rectangle(20, 0, 21, 1, true)})});
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(report.holes_outside, 1u);
  EXPECT_EQ(report.self_intersections, 0u);
  const Problem* p = first_of(report, "hole-outside");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->element, 2);
  EXPECT_NE(p->message.find("polygon 0 ring 2"), std::string::npos) << p->message;
}

TEST(CheckRegion, OverlappingHoles) {
  const RegionReport report =
      check_region({make_polygon({rectangle(0, 0, 10, 10), rectangle(1, 1, 5, 5, true), rectangle(4, 4, 8, 8, true)})});
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(report.self_intersections, 2u);  // the two squares cross at (5,4) and (4,5)
  const Problem* p = first_of(report, "self-intersection");
  ASSERT_NE(p, nullptr);
  EXPECT_NE(p->message.find("ring 1 (hole)"), std::string::npos) << p->message;
  EXPECT_NE(p->message.find("ring 2 (hole)"), std::string::npos) << p->message;
}

TEST(CheckRegion, NestedHole) {
  const RegionReport report =
      check_region({make_polygon({rectangle(0, 0, 10, 10), rectangle(1, 1, 9, 9, true), rectangle(3, 3, 4, 4, true)})});
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(report.nested_holes, 1u);
  EXPECT_EQ(report.holes_outside, 0u);
  const Problem* p = first_of(report, "nested-hole");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->element, 2);
  EXPECT_NE(p->message.find("polygon 0 ring 2 (hole) lies inside polygon 0 ring 1 (hole)"), std::string::npos)
      << p->message;
}

TEST(CheckRegion, TouchingRings) {
  // A hole whose vertex lies on the outer ring's left edge.
  RegionReport report = check_region({make_polygon({rectangle(0, 0, 10, 10), {{0, 5}, {3, 6}, {3, 4}}})});
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(report.self_intersections, 2u);  // both hole segments at (0,5) touch the edge
  const Problem* p = first_of(report, "self-intersection");
  ASSERT_NE(p, nullptr);
  EXPECT_NE(p->message.find("touches"), std::string::npos) << p->message;
  EXPECT_NE(p->message.find("(0, 5)"), std::string::npos) << p->message;

  // Two holes sharing one vertex: 4 touching segment pairs.
  report =
      check_region({make_polygon({rectangle(0, 0, 10, 10), rectangle(1, 1, 3, 3, true), rectangle(3, 3, 5, 5, true)})});
  EXPECT_EQ(report.self_intersections, 4u);
  // A hole sharing part of an edge with another (collinear overlap).
  report =
      check_region({make_polygon({rectangle(0, 0, 10, 10), rectangle(1, 1, 3, 3, true), rectangle(3, 2, 5, 4, true)})});
  EXPECT_GE(report.self_intersections, 1u);
  EXPECT_FALSE(report.valid);
  // A ring touching itself at a vertex (a pinch).
  report = check_region({make_polygon({{{0, 0}, {4, 0}, {2, 2}, {4, 4}, {0, 4}, {2, 2}}})});
  EXPECT_EQ(report.self_intersections, 4u);
}

TEST(CheckRegion, DuplicatePoints) {
  RegionReport report = check_region({make_polygon({{{0, 0}, {1, 0}, {1, 0}, {1, 1}, {0, 1}}})});
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(report.duplicate_points, 1u);
  EXPECT_EQ(report.self_intersections, 0u);
  const Problem* p = first_of(report, "duplicate-point");
  ASSERT_NE(p, nullptr);
  EXPECT_NE(p->message.find("vertex 2 repeats vertex 1 at (1, 0)"), std::string::npos) << p->message;

  report = check_region({make_polygon({{{0, 0}, {1, 0}, {1, 1}, {0, 0}}})});  // explicitly closed
  EXPECT_EQ(report.duplicate_points, 1u);
  EXPECT_NE(first_of(report, "duplicate-point")->message.find("last vertex 3"), std::string::npos);
}

TEST(CheckRegion, ShortRings) {
  RegionReport report = check_region({make_polygon({rectangle(0, 0, 10, 10), {{1, 1}, {2, 2}}})});
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(report.short_rings, 1u);
  EXPECT_EQ(first_of(report, "short-ring")->element, 1);
  report = check_region({make_polygon({{{0, 0}, {1, 1}, {0, 0}, {1, 1}}})});
  EXPECT_EQ(report.short_rings, 1u);
  report = check_region({Polygon2{}});
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(count_kind(report, "empty-polygon"), 1u);
  EXPECT_FALSE(check_region({}).valid);
}

TEST(CheckRegion, FoldBack) {
  // Collinear triangle and a spike: rings that fold back onto themselves.
  RegionReport report = check_region({make_polygon({{{0, 0}, {2, 0}, {1, 0}}})});
  EXPECT_FALSE(report.valid);
  EXPECT_GE(report.self_intersections, 1u);
  EXPECT_NE(first_of(report, "self-intersection")->message.find("folds back"), std::string::npos);
  report = check_region({make_polygon({{{0, 0}, {4, 0}, {4, 4}, {2, 4}, {2, 6}, {2, 4}, {0, 4}}})});
  EXPECT_GE(report.self_intersections, 1u);
  // Collinear but straight on: fine.
  EXPECT_TRUE(check_region({make_polygon({{{0, 0}, {1, 0}, {2, 0}, {2, 2}, {0, 2}}})}).valid);
}

TEST(CheckRegion, PolygonsAndIslands) {
  // An island polygon in a hole is fine; one in the interior overlaps.
  std::vector<Polygon2> polygons{make_polygon({rectangle(0, 0, 10, 10), rectangle(2, 2, 8, 8, true)}),
                                 make_polygon({rectangle(3, 3, 7, 7)})};
  EXPECT_TRUE(check_region(polygons).valid);
  polygons.push_back(make_polygon({rectangle(0.5, 0.5, 1.5, 1.5)}));
  const RegionReport report = check_region(polygons);
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(count_kind(report, "polygons-overlap"), 1u);
  EXPECT_NE(first_of(report, "polygons-overlap")->message.find("polygon 2 lies inside polygon 0"), std::string::npos);
}

TEST(CheckRegion, NonFinite) {
  const RegionReport report =
      check_region({make_polygon({{{0, 0}, {1, 0}, {std::numeric_limits<double>::quiet_NaN(), 1}}})});
  EXPECT_FALSE(report.valid);
  EXPECT_EQ(count_kind(report, "non-finite"), 1u);
}

TEST(CheckRegion, ProblemsAreCappedPerKind) {
  // A zig-zag crossing a bar 50 times.
  std::vector<Vec2> ring;
  for (int i = 0; i < 50; ++i) {
    ring.emplace_back(i, 0);
    ring.emplace_back(i + 0.5, 2);
  }
  ring.emplace_back(50, -1);
  ring.emplace_back(-1, 1);  // crosses every zig-zag segment
  CheckOptions options;
  options.max_problems_per_kind = 5;
  const RegionReport report = check_region({make_polygon({ring})}, options);
  EXPECT_GT(report.self_intersections, 40u);
  EXPECT_EQ(count_kind(report, "self-intersection"), 5u);
}

// Brute force: contacts between non-adjacent segments plus fold-backs, with the same predicates.
std::size_t brute_force_intersections(const std::vector<std::vector<Vec2>>& rings) {
  struct Seg {
    Vec2 a, b;
    std::size_t ring, k, n;
  };
  std::vector<Seg> segments;
  std::size_t folds = 0;
  for (std::size_t r = 0; r < rings.size(); ++r) {
    const auto& ring = rings[r];
    const std::size_t n = ring.size();
    for (std::size_t k = 0; k < n; ++k) {
      segments.push_back({ring[k], ring[(k + 1) % n], r, k, n});
      const Vec2 &prev = ring[(k + n - 1) % n], &here = ring[k], &next = ring[(k + 1) % n];
      if (detail::orient2d(prev, here, next) == 0 &&
          (prev.x() != here.x() ? (prev.x() < here.x()) == (next.x() < here.x())
                                : (prev.y() < here.y()) == (next.y() < here.y())))
        ++folds;
    }
  }
  std::size_t contacts = 0;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    for (std::size_t j = i + 1; j < segments.size(); ++j) {
      const Seg &s = segments[i], &t = segments[j];
      if (s.ring == t.ring && ((s.k + 1) % s.n == t.k || (t.k + 1) % t.n == s.k)) continue;
      contacts += detail::segment_contact(s.a, s.b, t.a, t.b) != detail::SegmentContact::None;
    }
  }
  return contacts + folds;
}

TEST(CheckRegion, AgreesWithBruteForceOnMessyInput) {
  // Random rings on a coarse lattice (many collinear, touching and repeated points)
  // and random rings of long segments (deep grid recursion), at an offset and scale
  // where the grid arithmetic rounds.
  std::mt19937 random(11);
  for (int trial = 0; trial < 60; ++trial) {
    const bool lattice = trial % 2 == 0;
    std::uniform_int_distribution<int> cell(0, lattice ? 12 : 1000000);
    std::uniform_int_distribution<int> ring_count(1, 4), ring_size(3, lattice ? 30 : 120);
    const double offset = trial % 3 == 0 ? 1e5 : 0.0, step = trial % 3 == 0 ? 1e-3 : 0.25;
    std::vector<std::vector<Vec2>> rings(static_cast<std::size_t>(ring_count(random)));
    Polygon2 polygon;
    for (auto& ring : rings) {
      const int n = ring_size(random);
      while (static_cast<int>(ring.size()) < n) {
        const Vec2 p(offset + step * cell(random), offset + step * cell(random));
        if (!ring.empty() && p == ring.back()) continue;
        ring.push_back(p);
      }
      while (ring.size() > 3 && ring.back() == ring.front()) ring.pop_back();
      if (!detail::has_three_distinct_points(ring) || ring.back() == ring.front()) {
        ring = rectangle(offset, offset, offset + step, offset + step);
      }
      polygon.add_ring(ring);
    }
    const RegionReport report = check_region({polygon});
    EXPECT_EQ(report.self_intersections, brute_force_intersections(rings)) << "trial " << trial;
    EXPECT_EQ(report.duplicate_points, 0u);
  }
}

TEST(CheckRegion, ManySmallHolesScale) {
  // 100 x 100 holes in a square: 40k+ segments, all tests near-linear.
  Polygon2 polygon = make_polygon({rectangle(0, 0, 101, 101)});
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j) polygon.add_ring(rectangle(i + 0.6, j + 0.6, i + 1.4, j + 1.4, true));
  const RegionReport report = check_region({polygon});
  EXPECT_TRUE(report.valid);
  EXPECT_EQ(report.holes, 10000u);
  polygon.add_ring(rectangle(50.7, 50.7, 50.8, 50.8, true));  // one hole inside another
  EXPECT_EQ(check_region({polygon}).nested_holes, 1u);
}

}  // namespace
}  // namespace structmesh

namespace structmesh {
namespace {

TEST(CheckRegion, PartitionPartsMayShareBoundariesButNotCross) {
  // Two unit squares side by side (the right one with an extra vertex on the shared
  // edge, as neighbouring parts of a partition have): invalid as one region, valid
  // as a partition. Overlapping squares stay invalid either way.
  const std::vector<Polygon2> tiles{test::make_polygon({test::rectangle(0, 0, 1, 1)}),
                                    test::make_polygon({std::vector<Vec2>{{1, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 0.5}}})};
  EXPECT_FALSE(check_region(tiles).valid);
  CheckOptions partition;
  partition.shared_boundaries = true;
  const RegionReport shared = check_region(tiles, partition);
  EXPECT_TRUE(shared.valid) << (shared.problems.empty() ? "" : shared.problems.front().message);
  EXPECT_EQ(shared.self_intersections, 0u);
  const std::vector<Polygon2> overlapping{test::make_polygon({test::rectangle(0, 0, 1, 1)}),
                                          test::make_polygon({test::rectangle(0.5, 0.5, 1.5, 1.5)})};
  const RegionReport crossed = check_region(overlapping, partition);
  EXPECT_FALSE(crossed.valid);
  EXPECT_GT(crossed.self_intersections, 0u);
  // A part that is invalid on its own is still reported.
  const std::vector<Polygon2> bowtie{test::make_polygon({std::vector<Vec2>{{0, 0}, {2, 2}, {2, 0}, {0, 2}}})};
  EXPECT_FALSE(check_region(bowtie, partition).valid);
}

}  // namespace
}  // namespace structmesh
