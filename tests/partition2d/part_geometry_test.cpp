// build_part_geometry (design/partition2d.md §3.1, §3.2) on hand-built
// tessellations: rings, kept vertices, curves, junctions and loops, holes, a part
// touching itself at a vertex, and the errors for split and empty parts.
#include "partition2d/part_geometry_fixtures.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace structmesh::partition2d {
namespace {

using testing::build;
using testing::grid_faces;
using testing::HoleFixture;
using testing::make_tessellation;
using testing::quadrant_labels;
using testing::TestFrame;
using testing::unit_square;

const std::vector<Index>& curve_vertices(const Partition& partition, std::int64_t ref) {
  return partition.curves[ref >= 0 ? ref : -ref - 1].vertices;
}

// Loop ref as a vertex sequence in the direction the part walks it.
std::vector<Index> walked(const Partition& partition, std::int64_t ref) {
  std::vector<Index> vertices = curve_vertices(partition, ref);
  if (ref < 0) std::reverse(vertices.begin(), vertices.end());
  return vertices;
}

// Invariants every partition geometry must satisfy, whatever the labelling.
void expect_consistent(const Partition& partition, const Polygon2& region, double metric_region_area) {
  const std::size_t k = partition.parts.size();
  ASSERT_EQ(partition.part_loops.size(), k);
  std::vector<int> forward_uses(partition.curves.size(), 0), reverse_uses(partition.curves.size(), 0);
  double total = 0;
  for (std::size_t p = 0; p < k; ++p) {
    const Polygon2& polygon = partition.parts[p];
    ASSERT_EQ(polygon.ring_count(), partition.part_loops[p].size()) << "part " << p;
    EXPECT_GT(signed_area(polygon.ring(0)), 0) << "part " << p;
    for (std::size_t r = 1; r < polygon.ring_count(); ++r) EXPECT_LT(signed_area(polygon.ring(r)), 0);
    EXPECT_EQ(polygon.coordinates, region.coordinates);
    for (std::size_t r = 0; r < polygon.ring_count(); ++r) {
      const auto& loop = partition.part_loops[p][r];
      ASSERT_FALSE(loop.empty());
      std::vector<Vec2> ring;
      for (std::size_t i = 0; i < loop.size(); ++i) {
        const PartitionCurve& curve = partition.curves[loop[i] >= 0 ? loop[i] : -loop[i] - 1];
        (loop[i] >= 0 ? forward_uses : reverse_uses)[loop[i] >= 0 ? loop[i] : -loop[i] - 1]++;
        EXPECT_EQ(loop[i] >= 0 ? curve.left_part : curve.right_part, static_cast<std::int32_t>(p));
        const auto vertices = walked(partition, loop[i]);
        EXPECT_EQ(vertices.back(), walked(partition, loop[(i + 1) % loop.size()]).front()) << "loop breaks";
        for (std::size_t j = 0; j + 1 < vertices.size(); ++j) ring.push_back(partition.vertices[vertices[j]]);
      }
      const auto expected = polygon.ring(r);
      ASSERT_EQ(ring.size(), expected.size());
      for (std::size_t j = 0; j < ring.size(); ++j) EXPECT_EQ(ring[j], expected[j]);
    }
    total += partition.part_areas[p];
  }
  EXPECT_NEAR(total, metric_region_area, 1e-12 * metric_region_area);
  for (std::size_t c = 0; c < partition.curves.size(); ++c) {
    const PartitionCurve& curve = partition.curves[c];
    const bool separator = curve.kind == PartitionCurve::Kind::Separator;
    EXPECT_EQ(forward_uses[c], 1) << "curve " << c;
    EXPECT_EQ(reverse_uses[c], separator ? 1 : 0) << "curve " << c;
    EXPECT_EQ(separator, curve.right_part >= 0);
    if (separator) {
      EXPECT_LT(curve.left_part, curve.right_part);
    } else {
      EXPECT_GE(curve.ring, 0);
    }
    ASSERT_GE(curve.vertices.size(), 2u);
    const bool closed = curve.vertices.front() == curve.vertices.back();
    // Ends are junctions, or the loop start of a closed loop without junction.
    EXPECT_TRUE(partition.junction[curve.vertices.front()] || closed);
    EXPECT_TRUE(partition.junction[curve.vertices.back()] || closed);
    // Interior vertices: no junction; each an input vertex or a turn.
    for (std::size_t i = 1; i + 1 < curve.vertices.size(); ++i) {
      const Index v = curve.vertices[i];
      EXPECT_FALSE(partition.junction[v]);
      const Vec2 a = partition.metric_vertices[v] - partition.metric_vertices[curve.vertices[i - 1]];
      const Vec2 b = partition.metric_vertices[curve.vertices[i + 1]] - partition.metric_vertices[v];
      EXPECT_TRUE(partition.input_vertex[v] >= 0 || a.x() * b.y() - a.y() * b.x() != 0) << "vertex " << v;
    }
  }
  for (std::size_t v = 0; v < partition.vertices.size(); ++v)
    if (partition.input_vertex[v] >= 0) {
      const Vec2& input = region.points[static_cast<std::size_t>(partition.input_vertex[v])];
      EXPECT_EQ(partition.vertices[v].x(), input.x());
      EXPECT_EQ(partition.vertices[v].y(), input.y());
    }
}

TEST(PartGeometry, QuadrantsOfTheUnitSquare) {
  const Polygon2 region = unit_square();
  const Tessellation t = make_tessellation(grid_faces(4, 4, {0, 0}, 0.25), region);
  const Partition partition = build(t, quadrant_labels(), 4, region);
  expect_consistent(partition, region, 1.0);

  // Kept: 4 corners (input), the centre (4 parts) and 4 side midpoints (separator
  // meets boundary). The 16 collinear grid points on separators and sides are gone.
  ASSERT_EQ(partition.vertices.size(), 9u);
  int junctions = 0, inputs = 0;
  for (std::size_t v = 0; v < 9; ++v) {
    junctions += partition.junction[v];
    inputs += partition.input_vertex[v] >= 0;
  }
  EXPECT_EQ(junctions, 5);
  EXPECT_EQ(inputs, 4);
  for (std::size_t p = 0; p < 4; ++p) {
    EXPECT_EQ(partition.parts[p].ring_count(), 1u);
    EXPECT_EQ(partition.parts[p].points.size(), 4u);
    EXPECT_DOUBLE_EQ(partition.part_areas[p], 0.25);
    ASSERT_EQ(partition.part_loops[p].size(), 1u);
    EXPECT_EQ(partition.part_loops[p][0].size(), 3u);  // two separators and one boundary curve
    const RegionReport report = check_region({partition.parts[p]});
    EXPECT_TRUE(report.valid) << "part " << p;
  }
  // Lower-left part: exactly the square [0, 0.5]^2.
  BoundingBox2 box;
  for (const Vec2& q : partition.parts[0].points) box.extend(q);
  EXPECT_EQ(box.min, Vec2(0, 0));
  EXPECT_EQ(box.max, Vec2(0.5, 0.5));

  std::size_t separators = 0;
  for (const PartitionCurve& curve : partition.curves) {
    if (curve.kind == PartitionCurve::Kind::Separator) {
      ++separators;
      EXPECT_EQ(curve.vertices.size(), 2u);
    } else {
      EXPECT_EQ(curve.vertices.size(), 3u);  // midpoint, corner, midpoint
      EXPECT_EQ(curve.ring, 0);
    }
  }
  EXPECT_EQ(separators, 4u);
  EXPECT_EQ(partition.curves.size(), 8u);
}

TEST(PartGeometry, InputVerticesBitIdenticalAndAreasMetric) {
  // Input coordinates that are not exact in binary, a metric plane 1000x larger and
  // a normalised frame shifted and scaled: input vertices must come back
  // bit-identical, new ones through the maps, areas in metric units.
  const Vec2 origin(0.1, 0.7);
  const double size = 0.3;
  const Polygon2 region =
      testing::make_region({{origin, origin + Vec2(size, 0), origin + Vec2(size, size), origin + Vec2(0, size)}});
  const TestFrame frame{1000, {321.5, 123.25}, 37.3};
  auto faces = grid_faces(4, 4, {0, 0}, 0.25);
  for (auto& face : faces)
    for (Vec2& q : face) q = origin + size * q;
  const Tessellation t = make_tessellation(faces, region, frame);
  const Partition partition = build(t, quadrant_labels(), 4, region, frame);
  const double metric_area = size * size * 1e6;
  expect_consistent(partition, region, metric_area);
  for (std::size_t p = 0; p < 4; ++p) EXPECT_NEAR(partition.part_areas[p], metric_area / 4, 1e-9 * metric_area);
  for (std::size_t v = 0; v < partition.vertices.size(); ++v) {
    EXPECT_LT((partition.metric_vertices[v] - 1000 * partition.vertices[v]).norm(), 1e-9);
    if (partition.input_vertex[v] < 0) {
      // New vertices are at multiples of size/2 from the origin.
      const Vec2 steps = (partition.vertices[v] - origin) / (0.5 * size);
      EXPECT_NEAR(steps.x(), std::round(steps.x()), 1e-9);
      EXPECT_NEAR(steps.y(), std::round(steps.y()), 1e-9);
    }
  }
}

TEST(PartGeometry, SquareWithHoleGivesLoopsWithoutJunctions) {
  const HoleFixture fixture;
  const Tessellation t = make_tessellation(fixture.faces, fixture.region);
  const Partition partition = build(t, fixture.labels, 2, fixture.region);
  expect_consistent(partition, fixture.region, 24.0);

  // 8 input corners + the 4 corners of the separator square [1,4]^2.
  EXPECT_EQ(partition.vertices.size(), 12u);
  for (const std::uint8_t j : partition.junction) EXPECT_EQ(j, 0);
  ASSERT_EQ(partition.curves.size(), 3u);
  int rings_seen = 0;
  for (const PartitionCurve& curve : partition.curves) {
    EXPECT_EQ(curve.vertices.front(), curve.vertices.back());
    EXPECT_EQ(curve.vertices.size(), 5u);
    // The loop starts at its smallest vertex id.
    EXPECT_EQ(curve.vertices.front(), *std::min_element(curve.vertices.begin(), curve.vertices.end()));
    if (curve.kind == PartitionCurve::Kind::Boundary) rings_seen |= 1 << curve.ring;
  }
  EXPECT_EQ(rings_seen, 3);  // rings 0 and 1
  EXPECT_DOUBLE_EQ(partition.part_areas[0], 16.0);
  EXPECT_DOUBLE_EQ(partition.part_areas[1], 8.0);
  for (std::size_t p = 0; p < 2; ++p) {
    EXPECT_EQ(partition.parts[p].ring_count(), 2u);
    EXPECT_TRUE(check_region({partition.parts[p]}).valid) << "part " << p;
  }
}

TEST(PartGeometry, StaircaseSeparatorKeepsEveryStep) {
  // 4x4 grid, part 0 = cells with i + j < 4: a staircase separator from (4,1) to
  // (1,4) (in quarter units) with 5 turns; straight runs of the sides are dropped.
  const Polygon2 region = unit_square();
  const Tessellation t = make_tessellation(grid_faces(4, 4, {0, 0}, 0.25), region);
  std::vector<std::int32_t> labels;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) labels.push_back(i + j < 4 ? 0 : 1);
  const Partition partition = build(t, labels, 2, region);
  expect_consistent(partition, region, 1.0);
  EXPECT_DOUBLE_EQ(partition.part_areas[0], 10.0 / 16);
  std::size_t separators = 0;
  for (const PartitionCurve& curve : partition.curves)
    if (curve.kind == PartitionCurve::Kind::Separator) {
      ++separators;
      EXPECT_EQ(curve.vertices.size(), 7u);  // two junctions and 5 turns
    }
  EXPECT_EQ(separators, 1u);
  EXPECT_EQ(partition.parts[0].points.size(), 7u + 3u);  // the separator and the corners (0,0), (1,0), (0,1)
}

TEST(PartGeometry, PartTouchingItselfAtAVertexIsOnePiece) {
  // 3x3 grid; the centre cell is part 1, the upper right cell part 2, the rest
  // part 0, which wraps around part 1 and touches itself at (2,2).
  const Polygon2 region = testing::make_region({{{0, 0}, {3, 0}, {3, 3}, {0, 3}}});
  const Tessellation t = make_tessellation(grid_faces(3, 3, {0, 0}, 1), region);
  const std::vector<std::int32_t> labels{0, 0, 0, 0, 1, 0, 0, 0, 2};
  const Partition partition = build(t, labels, 3, region);
  expect_consistent(partition, region, 9.0);
  EXPECT_DOUBLE_EQ(partition.part_areas[0], 7.0);
  ASSERT_EQ(partition.parts[0].ring_count(), 1u);
  const auto ring = partition.parts[0].ring(0);
  EXPECT_EQ(std::count(ring.begin(), ring.end(), Vec2(2, 2)), 2);
  // The separator around part 1 starts and ends at the junction (2,2).
  const auto closed_at_junction = std::count_if(partition.curves.begin(), partition.curves.end(), [&](const auto& c) {
    return c.vertices.front() == c.vertices.back() && partition.vertices[c.vertices.front()] == Vec2(2, 2) &&
           partition.junction[c.vertices.front()];
  });
  EXPECT_EQ(closed_at_junction, 1);
}

TEST(PartGeometry, SplitPartIsAnError) {
  const Polygon2 region = testing::make_region({{{0, 0}, {3, 0}, {3, 1}, {0, 1}}});
  const Tessellation strip = make_tessellation(grid_faces(3, 1, {0, 0}, 1), region);
  try {
    build(strip, {0, 1, 0}, 2, region);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("part 0 is not connected: 2 pieces"), std::string::npos) << e.what();
  }
  // Two cells meeting only at a corner are two pieces too.
  const Polygon2 square = testing::make_region({{{0, 0}, {2, 0}, {2, 2}, {0, 2}}});
  const Tessellation checkerboard = make_tessellation(grid_faces(2, 2, {0, 0}, 1), square);
  try {
    build(checkerboard, {0, 1, 1, 0}, 2, square);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is not connected: 2 pieces"), std::string::npos) << e.what();
  }
}

TEST(PartGeometry, EmptyPartIsAnError) {
  const Polygon2 region = unit_square();
  const Tessellation t = make_tessellation(grid_faces(4, 4, {0, 0}, 0.25), region);
  try {
    build(t, quadrant_labels(), 5, region);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("part 4 is empty"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace structmesh::partition2d
