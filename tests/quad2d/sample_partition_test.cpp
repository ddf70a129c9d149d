#include "structmesh/error.hpp"
#include "structmesh/partition2d.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/regions.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

namespace structmesh {
namespace {

Polygon2 rectangle(double width, double height) {
  Polygon2 polygon;
  const std::vector<Vec2> ring{{0, 0}, {width, 0}, {width, height}, {0, height}};
  polygon.add_ring(ring);
  return polygon;
}

std::size_t boundary_point_count(const SampledPartition& sampled, std::size_t part) {
  std::size_t count = 0;
  for (const auto& loop : sampled.part_loops[part]) count += loop.size();
  return count;
}

// Every loop is a closed chain of distinct points; consecutive points are about
// `size` apart; every part has an even number of boundary points.
void expect_valid_sampling(const SampledPartition& sampled, double size) {
  for (std::size_t p = 0; p < sampled.part_loops.size(); ++p) {
    EXPECT_EQ(boundary_point_count(sampled, p) % 2, 0U) << "part " << p;
    for (const auto& loop : sampled.part_loops[p]) {
      ASSERT_GE(loop.size(), 3U);
      std::set<Index> distinct(loop.begin(), loop.end());
      EXPECT_EQ(distinct.size(), loop.size()) << "part " << p << " visits a point twice";
      for (std::size_t i = 0; i < loop.size(); ++i) {
        const double length = (sampled.points[loop[(i + 1) % loop.size()]] - sampled.points[loop[i]]).norm();
        EXPECT_GT(length, 0.0);
        EXPECT_LT(length, 2.5 * size) << "part " << p;  // the assignment allows half the ideal count
      }
    }
  }
}

TEST(SamplePartition, RectangleInThreePartsSharesSeparatorsAndKeepsCorners) {
  PartitionOptions options;
  options.parts = 3;
  options.cells = 300;
  const Partition partition = partition_region(rectangle(3, 1), options);
  const double size = 0.1;
  const SampledPartition sampled = sample_partition(partition, size);
  ASSERT_EQ(sampled.part_loops.size(), 3U);
  expect_valid_sampling(sampled, size);

  // Separator samples are used by two parts (junctions by more), region boundary
  // samples by at least one; every sample is used.
  std::vector<std::set<std::size_t>> users(sampled.points.size());
  for (std::size_t p = 0; p < 3; ++p)
    for (const auto& loop : sampled.part_loops[p])
      for (const Index i : loop) users[i].insert(p);
  for (std::size_t i = 0; i < sampled.points.size(); ++i) {
    ASSERT_FALSE(users[i].empty()) << "unused sample " << i;
    if (!sampled.on_region_boundary[i]) {
      EXPECT_GE(users[i].size(), 2U) << "separator sample " << i;
    }
    EXPECT_EQ(sampled.fixed[i], sampled.on_region_boundary[i]);
  }
  // No two samples at the same place (shared by index, not duplicated).
  std::set<std::pair<double, double>> places;
  for (const Vec2& p : sampled.points) places.emplace(p.x(), p.y());
  EXPECT_EQ(places.size(), sampled.points.size());
  // The rectangle's corners are samples, and region boundary samples lie on its sides.
  for (const Vec2& corner : {Vec2(0, 0), Vec2(3, 0), Vec2(3, 1), Vec2(0, 1)})
    EXPECT_EQ(places.count({corner.x(), corner.y()}), 1U) << corner.transpose();
  for (std::size_t i = 0; i < sampled.points.size(); ++i) {
    if (!sampled.on_region_boundary[i]) continue;
    const Vec2& p = sampled.points[i];
    const double distance = std::min({std::abs(p.x()), std::abs(p.x() - 3), std::abs(p.y()), std::abs(p.y() - 1)});
    EXPECT_LT(distance, 1e-12);
  }
}

TEST(SamplePartition, EveryPartOfTheKeyIsEvenAtManySizes) {
  PartitionOptions options;
  options.parts = 16;
  options.cells = 1000;
  const Partition partition = partition_region(make_key_region(1000), options);
  double perimeter = 0;
  const Polygon2 key = make_key_region(1000);
  for (std::size_t r = 0; r < key.ring_count(); ++r) {
    const auto ring = key.ring(r);
    for (std::size_t i = 0; i < ring.size(); ++i) perimeter += (ring[(i + 1) % ring.size()] - ring[i]).norm();
  }
  for (const double factor : {0.7, 1.0, 1.37, 2.0, 3.1, 5.0}) {
    const double size = factor * perimeter / 1000;
    const SampledPartition sampled = sample_partition(partition, size);
    SCOPED_TRACE(factor);
    expect_valid_sampling(sampled, size);
    // Loop 0 of each part is counter-clockwise, holes clockwise.
    for (std::size_t p = 0; p < sampled.part_loops.size(); ++p) {
      const auto [polygon, map] = part_boundary(sampled, p);
      ASSERT_EQ(map.size(), boundary_point_count(sampled, p));
      EXPECT_GT(signed_area(polygon.ring(0)), 0) << "part " << p;
      for (std::size_t r = 1; r < polygon.ring_count(); ++r) EXPECT_LT(signed_area(polygon.ring(r)), 0);
      for (std::size_t k = 0; k < map.size(); ++k) EXPECT_EQ(polygon.points[k], sampled.points[map[k]]);
    }
  }
}

TEST(SamplePartition, RejectsNonPositiveSize) {
  PartitionOptions options;
  options.parts = 1;
  const Partition partition = partition_region(rectangle(1, 1), options);
  EXPECT_THROW(sample_partition(partition, 0.0), InputError);
  EXPECT_THROW(sample_partition(partition, -1.0), InputError);
  const SampledPartition sampled = sample_partition(partition, 0.25);
  EXPECT_EQ(boundary_point_count(sampled, 0), 16U);
  EXPECT_THROW(part_boundary(sampled, 1), InputError);
}

}  // namespace
}  // namespace structmesh

namespace structmesh {
namespace {

// Four-sided parts get equal counts on opposite sides; the corners are real corners.
void expect_consistent_corners(const SampledPartition& sampled, std::size_t& mapped) {
  mapped = 0;
  ASSERT_EQ(sampled.part_corners.size(), sampled.part_loops.size());
  for (std::size_t p = 0; p < sampled.part_loops.size(); ++p) {
    const auto& c = sampled.part_corners[p];
    if (c[0] < 0) continue;
    ++mapped;
    ASSERT_EQ(sampled.part_loops[p].size(), 1U);
    const auto n = static_cast<std::int64_t>(sampled.part_loops[p][0].size());
    ASSERT_TRUE(0 <= c[0] && c[0] < c[1] && c[1] < c[2] && c[2] < c[3] && c[3] < n) << "part " << p;
    EXPECT_EQ(c[1] - c[0], c[3] - c[2]) << "part " << p;
    EXPECT_EQ(c[2] - c[1], n - c[3] + c[0]) << "part " << p;
  }
}

TEST(SamplePartition, RectanglePartsBecomeMappableWithMatchingSides) {
  PartitionOptions options;
  options.parts = 4;
  options.cells = 400;
  Polygon2 rectangle;
  const std::vector<Vec2> ring{{0, 0}, {4, 0}, {4, 1}, {0, 1}};
  rectangle.add_ring(ring);
  const Partition partition = partition_region(rectangle, options);
  const SampledPartition sampled = sample_partition(partition, 0.05);
  std::size_t mapped = 0;
  expect_consistent_corners(sampled, mapped);
  // Four strips of a 4 x 1 rectangle cut by near-vertical separators are all four-sided.
  EXPECT_EQ(mapped, 4U);
  for (std::size_t p = 0; p < 4; ++p) {
    std::size_t count = 0;
    for (const auto& loop : sampled.part_loops[p]) count += loop.size();
    EXPECT_EQ(count % 2, 0U);
  }
}

// Separators shorter than `length` with an end off the region's boundary.
std::size_t tiny_separators(const Partition& partition, double length) {
  std::set<Index> boundary;
  for (const PartitionCurve& curve : partition.curves)
    if (curve.kind == PartitionCurve::Kind::Boundary) boundary.insert(curve.vertices.begin(), curve.vertices.end());
  std::size_t count = 0;
  for (const PartitionCurve& curve : partition.curves) {
    if (curve.kind != PartitionCurve::Kind::Separator || curve.vertices.front() == curve.vertices.back()) continue;
    double total = 0;
    for (std::size_t i = 1; i < curve.vertices.size(); ++i)
      total += (partition.metric_vertices[curve.vertices[i]] - partition.metric_vertices[curve.vertices[i - 1]]).norm();
    if (total < length && !(boundary.count(curve.vertices.front()) && boundary.count(curve.vertices.back()))) ++count;
  }
  return count;
}

TEST(CollapseTinySeparators, KeyJunctionsAHairApartBecomeOne) {
  // The Key in 32 parts as quad2d partitions it: two junctions 0.0034 element sizes
  // apart, joined by a separator that sampling would keep as an edge of that length.
  PartitionOptions options;
  options.parts = 32;
  options.cells = 768;
  Partition partition = partition_region(make_key_region(2000), options);
  const double size = 0.0156755;
  const std::size_t tiny = tiny_separators(partition, 0.1 * size);
  ASSERT_GE(tiny, 1U);
  Partition untouched = partition;
  EXPECT_EQ(collapse_tiny_separators(untouched, 0.0), 0U);
  EXPECT_EQ(untouched.curves.size(), partition.curves.size());
  const std::size_t curves = partition.curves.size();
  EXPECT_EQ(collapse_tiny_separators(partition, 0.1 * size), tiny);
  EXPECT_EQ(partition.curves.size(), curves - tiny);
  EXPECT_EQ(tiny_separators(partition, 0.1 * size), 0U);
  // Every loop is still a closed chain of curves.
  for (std::size_t p = 0; p < partition.part_loops.size(); ++p)
    for (const auto& loop : partition.part_loops[p]) {
      ASSERT_GE(loop.size(), 1U);
      const auto end = [&](std::int64_t ref, bool last) {
        const PartitionCurve& curve = partition.curves[static_cast<std::size_t>(ref >= 0 ? ref : -ref - 1)];
        return (ref >= 0) == last ? curve.vertices.back() : curve.vertices.front();
      };
      for (std::size_t i = 0; i < loop.size(); ++i)
        EXPECT_EQ(end(loop[i], true), end(loop[(i + 1) % loop.size()], false)) << "part " << p;
    }
  // Sampled, no part boundary has an edge shorter than a tenth of the size off the
  // region's boundary, and every part is still even.
  const SampledPartition sampled = sample_partition(partition, size);
  for (std::size_t p = 0; p < sampled.part_loops.size(); ++p) {
    EXPECT_EQ(boundary_point_count(sampled, p) % 2, 0U);
    for (const auto& loop : sampled.part_loops[p])
      for (std::size_t i = 0; i < loop.size(); ++i) {
        const Index a = loop[i], b = loop[(i + 1) % loop.size()];
        if (sampled.on_region_boundary[a] && sampled.on_region_boundary[b]) continue;
        EXPECT_GE((sampled.points[a] - sampled.points[b]).norm(), 0.1 * size) << "part " << p;
      }
  }
}

TEST(SamplePartition, KeyPartsCornersAreConsistent) {
  PartitionOptions options;
  options.parts = 32;
  options.cells = 800;  // enough for 32 parts; keeps the sanitizer run short
  const Partition partition = partition_region(make_key_region(2000), options);
  const SampledPartition sampled = sample_partition(partition, 0.0157);
  std::size_t mapped = 0;
  expect_consistent_corners(sampled, mapped);
  std::printf("Key, 32 parts: %zu four-sided parts with matching sides\n", mapped);
  EXPECT_GT(mapped, 0U);
}

}  // namespace
}  // namespace structmesh

namespace structmesh {
namespace {

bool segments_cross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const auto orient = [](const Vec2& p, const Vec2& q, const Vec2& r) {
    return (q.x() - p.x()) * (r.y() - p.y()) - (q.y() - p.y()) * (r.x() - p.x());
  };
  if (a == c || a == d || b == c || b == d) return false;
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  return ((o1 < 0) != (o2 < 0)) && ((o3 < 0) != (o4 < 0));
}

TEST(SamplePartition, CoarseSamplesNeverCutThroughAnIsland) {
  // A wiggly coast (wavelength ~0.16) with small islands in its crests, sampled at
  // 0.3: arc-length chords of the coast would cut through the islands.
  Polygon2 region;
  std::vector<Vec2> coast, island;
  for (int i = 0; i < 4000; ++i) {  // fine enough that no vertex turns by 25 degrees
    const double t = 2 * std::numbers::pi * i / 4000;
    const double r = 1 + 0.06 * std::sin(40 * t);
    coast.emplace_back(r * std::cos(t), r * std::sin(t));
  }
  region.add_ring(coast);
  // Small islands near the crests (sin(40 t) = 1), where the coast's chords cut across.
  for (int k = 0; k < 40; k += 2) {
    const double crest = std::numbers::pi / 80 + k * 2 * std::numbers::pi / 40;
    island.clear();
    for (int i = 0; i < 12; ++i) {
      const double t = -2 * std::numbers::pi * i / 12;  // clockwise hole
      island.emplace_back(1.035 * std::cos(crest) + 0.01 * std::cos(t), 1.035 * std::sin(crest) + 0.01 * std::sin(t));
    }
    region.add_ring(island);
  }
  PartitionOptions options;
  options.parts = 1;
  const Partition partition = partition_region(region, options);
  for (const double size : {0.11, 0.23, 0.3, 0.37}) {
    SCOPED_TRACE(size);
    const SampledPartition sampled = sample_partition(partition, size);
    std::vector<std::pair<Vec2, Vec2>> segments;
    std::size_t count = 0;
    for (const auto& loop : sampled.part_loops[0]) {
      count += loop.size();
      for (std::size_t i = 0; i < loop.size(); ++i)
        segments.emplace_back(sampled.points[loop[i]], sampled.points[loop[(i + 1) % loop.size()]]);
    }
    EXPECT_EQ(count % 2, 0U);
    const auto& outer = sampled.part_loops[0][0];
    for (std::size_t l = 1; l < sampled.part_loops[0].size(); ++l) {
      const Vec2& p = sampled.points[sampled.part_loops[0][l][0]];
      bool in = false;
      for (std::size_t i = 0, j = outer.size() - 1; i < outer.size(); j = i++) {
        const Vec2& a = sampled.points[outer[i]];
        const Vec2& b = sampled.points[outer[j]];
        if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
          in = !in;
      }
      EXPECT_TRUE(in) << "hole " << l << " lies outside the sampled outer loop";
    }
    for (std::size_t i = 0; i < segments.size(); ++i)
      for (std::size_t j = i + 1; j < segments.size(); ++j)
        ASSERT_FALSE(segments_cross(segments[i].first, segments[i].second, segments[j].first, segments[j].second))
            << "segments " << i << " and " << j << " cross";
  }
}

TEST(SamplePartition, CoastFinerThanTheElementsIsThinnedAndPaves) {
  // A unit square whose bottom side is a sawtooth of 400 teeth (period 0.0025,
  // amplitude 0.01, so every vertex turns by far more than 25 degrees) with a
  // needle-like spit 0.15 long and 0.004 wide, meshed at 0.05: kept as is, every
  // tooth would be a sample and the spit a pair of 2-degree corners no quad of that
  // size can follow. Thinned, samples are input vertices at least a quarter size
  // apart, the region deviates by at most the teeth, and the part paves.
  std::vector<Vec2> ring;
  for (int i = 0; i <= 400; ++i) {
    const double x = i / 400.0;
    if (i == 200) {
      ring.emplace_back(x - 0.002, 0.0);
      ring.emplace_back(x, -0.15);
      ring.emplace_back(x + 0.002, 0.0);
      continue;
    }
    ring.emplace_back(x, i % 2 == 0 ? 0.0 : -0.01);
  }
  ring.emplace_back(1.0, 1.0);
  ring.emplace_back(0.0, 1.0);
  Polygon2 region;
  region.add_ring(ring);
  PartitionOptions options;
  options.parts = 1;
  const Partition partition = partition_region(region, options);
  const double size = 0.05;
  const SampledPartition sampled = sample_partition(partition, size);
  expect_valid_sampling(sampled, size);
  const auto& loop = sampled.part_loops[0][0];
  EXPECT_LT(loop.size(), 100U);  // 4 sides of about 20 samples, not 400 teeth
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Vec2& p = sampled.points[loop[i]];
    EXPECT_GT(p.y(), -0.0101) << "sample " << i << " is on the spit";
    EXPECT_GT((sampled.points[loop[(i + 1) % loop.size()]] - p).norm(), 0.25 * size) << "sample " << i;
  }
  const auto [boundary, point_of] = part_boundary(sampled, 0);
  EXPECT_NEAR(std::abs(area(boundary)), std::abs(area(region)), 0.01);
  const PavedPart part = pave(boundary, PavingOptions{.size = size});
  for (const auto& q : part.quads) {
    const Vec2 &a = part.points[q[0]], &b = part.points[q[1]], &c = part.points[q[2]], &d = part.points[q[3]];
    const auto corner = [](const Vec2& u, const Vec2& v, const Vec2& w) {
      const Vec2 e = w - v, f = u - v;
      return e.x() * f.y() - e.y() * f.x();
    };
    EXPECT_GT(corner(d, a, b), 0.0);
    EXPECT_GT(corner(a, b, c), 0.0);
    EXPECT_GT(corner(b, c, d), 0.0);
    EXPECT_GT(corner(c, d, a), 0.0);
  }
}

TEST(SamplePartition, NeedleOfACoarseBoundaryIsDropped) {
  // A boundary as coarse as the elements keeps its vertices, but the tip of a spit
  // 0.3 long on a base of 0.01 (a 2-degree needle no quad of size 0.1 can follow)
  // goes; the square's corners and the rest stay input vertices.
  std::vector<Vec2> ring;
  for (int i = 0; i < 10; ++i) {
    ring.emplace_back(0.1 * i, 0.0);
    if (i == 4) {
      ring.emplace_back(0.44, 0.0);
      ring.emplace_back(0.445, -0.3);
      ring.emplace_back(0.45, 0.0);
    }
  }
  for (int i = 0; i < 10; ++i) ring.emplace_back(1.0, 0.1 * i);
  for (int i = 0; i < 10; ++i) ring.emplace_back(1.0 - 0.1 * i, 1.0);
  for (int i = 0; i < 10; ++i) ring.emplace_back(0.0, 1.0 - 0.1 * i);
  Polygon2 region;
  region.add_ring(ring);
  PartitionOptions options;
  options.parts = 1;
  const Partition partition = partition_region(region, options);
  const SampledPartition sampled = sample_partition(partition, 0.1);
  expect_valid_sampling(sampled, 0.1);
  for (const Index i : sampled.part_loops[0][0]) EXPECT_GE(sampled.points[i].y(), 0.0) << "a sample on the needle";
  const auto [boundary, point_of] = part_boundary(sampled, 0);
  EXPECT_NEAR(std::abs(area(boundary)), 1.0, 1e-9);
}

}  // namespace
}  // namespace structmesh
