// triangulate_region (design/partition2d.md §2.1): exact area, orientation, the
// boundary kept as constrained edges with bit-identical input points, topology
// (Euler), refinement quality, and input errors.
#include "structmesh/triangulate.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/regions.hpp"
#include "test_data.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <numbers>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace structmesh {
namespace {

using test::data_dir;

Polygon2 make_polygon(std::initializer_list<std::vector<Vec2>> rings) {
  Polygon2 polygon;
  for (const auto& ring : rings) polygon.add_ring(ring);
  return polygon;
}

double cross(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

double triangle_area(const RegionTriangulation& tri, const std::array<Index, 3>& t) {
  return 0.5 * cross(tri.points[t[0]], tri.points[t[1]], tri.points[t[2]]);
}

double total_area(const RegionTriangulation& tri) {
  double sum = 0;
  for (const auto& t : tri.triangles) sum += triangle_area(tri, t);
  return sum;
}

// Independent even-odd ray casting over all rings (not the CDT's flood fill).
bool inside(const Polygon2& region, const Vec2& p) {
  bool in = false;
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const auto ring = region.ring(r);
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
      const Vec2 &a = ring[i], &b = ring[j];
      if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
        in = !in;
      }
    }
  }
  return in;
}

std::size_t segment_count(const Polygon2& region) { return region.points.size(); }

using EdgeSet = std::set<std::pair<Index, Index>>;
std::pair<Index, Index> undirected(Index a, Index b) { return {std::min(a, b), std::max(a, b)}; }

EdgeSet input_segments(const Polygon2& region) {
  EdgeSet segments;
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const Index begin = region.ring_offsets[r], end = region.ring_offsets[r + 1];
    for (Index a = begin; a < end; ++a) segments.insert(undirected(a, a + 1 == end ? begin : a + 1));
  }
  return segments;
}

// Properties every triangulation must have: input points first and bit-identical,
// valid indices, counter-clockwise positive triangles, area = area(region), Euler
// characteristic of a disk with holes, every point used, boundary edges are
// triangle edges with the region on their left.
void expect_valid(const Polygon2& region, const RegionTriangulation& tri, double area_tolerance = 1e-9) {
  ASSERT_GE(tri.points.size(), region.points.size());
  for (std::size_t i = 0; i < region.points.size(); ++i) {
    ASSERT_EQ(tri.points[i].x(), region.points[i].x()) << i;
    ASSERT_EQ(tri.points[i].y(), region.points[i].y()) << i;
  }
  std::vector<char> used(tri.points.size(), 0);
  std::set<std::pair<Index, Index>> directed;
  std::size_t non_positive = 0;
  for (const auto& t : tri.triangles) {
    for (const Index v : t) ASSERT_LT(v, tri.points.size());
    EXPECT_LT(t[0], t[1]);
    EXPECT_LT(t[0], t[2]);
    non_positive += triangle_area(tri, t) > 0 ? 0 : 1;
    for (int k = 0; k < 3; ++k) {
      used[t[k]] = 1;
      EXPECT_TRUE(directed.insert({t[k], t[(k + 1) % 3]}).second) << "edge used twice in one direction";
    }
  }
  EXPECT_EQ(non_positive, 0u);
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "unused points";
  const double expected = area(region);
  EXPECT_NEAR(total_area(tri), expected, area_tolerance * std::abs(expected));

  EdgeSet edges;
  for (const auto& [a, b] : directed) edges.insert(undirected(a, b));
  const long euler =
      static_cast<long>(tri.points.size()) - static_cast<long>(edges.size()) + static_cast<long>(tri.triangles.size());
  EXPECT_EQ(euler, 1 - static_cast<long>(region.hole_count()));

  // A boundary edge has the region on its left: its directed edge belongs to a
  // triangle and the reverse to none. Every triangle edge without a twin is one.
  std::size_t without_twin = 0;
  for (const auto& [a, b] : directed) without_twin += directed.count({b, a}) == 0 ? 1 : 0;
  EXPECT_EQ(tri.boundary_edges.size(), without_twin);
  for (const auto& [a, b] : tri.boundary_edges) {
    EXPECT_EQ(directed.count({a, b}), 1u) << a << "-" << b;
    EXPECT_EQ(directed.count({b, a}), 0u) << a << "-" << b;
  }
}

// Without refinement: no new points, and the boundary edges are exactly the input
// segments, in ring order for rings that follow the orientation convention.
void expect_boundary_is_input(const Polygon2& region, const RegionTriangulation& tri) {
  EXPECT_EQ(tri.points.size(), region.points.size());
  ASSERT_EQ(tri.boundary_edges.size(), segment_count(region));
  EdgeSet listed;
  for (const auto& [a, b] : tri.boundary_edges) listed.insert(undirected(a, b));
  EXPECT_EQ(listed, input_segments(region));
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const Index begin = region.ring_offsets[r], end = region.ring_offsets[r + 1];
    const bool forward = (r == 0) == (signed_area(region.ring(r)) > 0);
    if (!forward) continue;
    for (Index a = begin; a < end; ++a) {
      const auto& e = tri.boundary_edges[a];
      EXPECT_EQ(e[0], a);
      EXPECT_EQ(e[1], a + 1 == end ? begin : a + 1);
    }
  }
}

void expect_centroids_inside(const Polygon2& region, const RegionTriangulation& tri) {
  std::size_t outside = 0;
  for (const auto& t : tri.triangles) {
    const Vec2 c = (tri.points[t[0]] + tri.points[t[1]] + tri.points[t[2]]) / 3.0;
    outside += inside(region, c) ? 0 : 1;
  }
  EXPECT_EQ(outside, 0u);
}

double min_angle_degrees(const RegionTriangulation& tri, const std::array<Index, 3>& t) {
  double smallest = 180;
  for (int k = 0; k < 3; ++k) {
    const Vec2 u = tri.points[t[(k + 1) % 3]] - tri.points[t[k]];
    const Vec2 v = tri.points[t[(k + 2) % 3]] - tri.points[t[k]];
    smallest =
        std::min(smallest, std::atan2(std::abs(u.x() * v.y() - u.y() * v.x()), u.dot(v)) * 180 / std::numbers::pi);
  }
  return smallest;
}

const std::vector<Vec2> kUnitSquare{{0, 0}, {1, 0}, {1, 1}, {0, 1}};

TEST(Triangulate, UnitSquareIsTwoTriangles) {
  const Polygon2 square = make_polygon({kUnitSquare});
  const RegionTriangulation tri = triangulate_region(square);
  EXPECT_EQ(tri.triangles.size(), 2u);
  EXPECT_DOUBLE_EQ(total_area(tri), 1.0);
  expect_valid(square, tri);
  expect_boundary_is_input(square, tri);
}

TEST(Triangulate, SquareWithSquareHole) {
  const Polygon2 region = make_polygon({{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {{1, 1}, {1, 3}, {3, 3}, {3, 1}}});
  const RegionTriangulation tri = triangulate_region(region);
  EXPECT_EQ(total_area(tri), 12.0);  // exact: all coordinates are small integers
  EXPECT_EQ(tri.triangles.size(), 8u);
  expect_valid(region, tri);
  expect_boundary_is_input(region, tri);
  expect_centroids_inside(region, tri);
}

TEST(Triangulate, OrientationOfTheInputDoesNotMatter) {
  // Parity decides inside/outside, so a clockwise outer ring and a counter-clockwise
  // hole give the same region; boundary edges still have the region on their left.
  const Polygon2 region = make_polygon({{{0, 0}, {0, 4}, {4, 4}, {4, 0}}, {{1, 1}, {3, 1}, {3, 3}, {1, 3}}});
  const RegionTriangulation tri = triangulate_region(region);
  EXPECT_EQ(total_area(tri), 12.0);
  expect_valid(region, tri);
  expect_boundary_is_input(region, tri);
}

struct Shape {
  const char* name;
  Polygon2 (*make)(std::size_t);
};
const Shape kShapes[] = {{"key", make_key_region}, {"pipe", make_pipe_region}};

TEST(Triangulate, KeyAndPipeConstrainedDelaunay) {
  for (const Shape& shape : kShapes) {
    SCOPED_TRACE(shape.name);
    const Polygon2 region = shape.make(2000);
    const RegionTriangulation tri = triangulate_region(region);
    expect_valid(region, tri);
    expect_boundary_is_input(region, tri);
    expect_centroids_inside(region, tri);
    // A CDT of a polygon with h holes and n points has n + 2h - 2 triangles.
    EXPECT_EQ(tri.triangles.size(), region.points.size() + 2 * region.hole_count() - 2);
  }
}

TEST(Triangulate, DeterministicOutput) {
  const Polygon2 region = make_pipe_region(2000);
  const RegionTriangulation a = triangulate_region(region, {.target_triangles = 3000});
  const RegionTriangulation b = triangulate_region(region, {.target_triangles = 3000});
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.boundary_edges, b.boundary_edges);
}

TEST(Triangulate, PipeRefinedToAbout4000Triangles) {
  const Polygon2 region = make_pipe_region(2000);
  // 4000 is below the floor the angle bound forces from 2000 boundary segments
  // (measured: 5688 triangles with no size bound), so the result is that floor.
  const RegionTriangulation tri = triangulate_region(region, {.target_triangles = 4000});
  EXPECT_GE(tri.triangles.size(), 3000u);
  EXPECT_LE(tri.triangles.size(), 6000u);
  EXPECT_GT(tri.points.size(), region.points.size());
  expect_valid(region, tri);
  expect_centroids_inside(region, tri);

  // Boundary edges walk every ring from its first point through all its input
  // points in ring order (refinement only subdivides segments), and each Steiner
  // point on the boundary lies on its input segment (to rounding: CGAL constructs
  // split points in floating point).
  const std::size_t n = region.points.size();
  EdgeSet input = input_segments(region);
  std::size_t e = 0;
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const Index begin = region.ring_offsets[r];
    ASSERT_LT(e, tri.boundary_edges.size());
    EXPECT_EQ(tri.boundary_edges[e][0], begin);
    Index last_input = begin;
    for (Index expected = begin;;) {
      // Follow the chain to the next input point.
      const Index from = tri.boundary_edges[e][0];
      EXPECT_EQ(from, expected);
      Index to = tri.boundary_edges[e][1];
      ++e;
      while (to >= n) {
        ASSERT_LT(e, tri.boundary_edges.size());
        EXPECT_EQ(tri.boundary_edges[e][0], to);
        to = tri.boundary_edges[e][1];
        ++e;
      }
      EXPECT_EQ(input.count(undirected(last_input, to)), 1u) << last_input << "-" << to;
      last_input = to;
      expected = to;
      if (to == begin) break;
    }
  }
  EXPECT_EQ(e, tri.boundary_edges.size());
  for (const auto& edge : tri.boundary_edges) {
    const Index a = edge[0];
    if (a < n) continue;
    bool on_segment = false;
    for (const auto& [p, q] : input) {
      const Vec2 &s = region.points[p], &t = region.points[q];
      const double length = (t - s).norm();
      const double along = (tri.points[a] - s).dot(t - s) / (length * length);
      const double distance = std::abs(cross(s, t, tri.points[a])) / length;
      if (along > 0 && along < 1 && distance < 1e-12 * (1 + s.norm())) on_segment = true;
    }
    EXPECT_TRUE(on_segment) << "Steiner point " << a << " off the boundary";
  }

  // Quality: the mesher guarantees arcsin(sqrt(0.125)) = 20.7° except near small
  // input angles. The Pipe's rings have no corner under 90°, so all triangles qualify.
  double smallest = 180;
  for (const auto& t : tri.triangles) smallest = std::min(smallest, min_angle_degrees(tri, t));
  EXPECT_GE(smallest, 20.0);
}

TEST(Triangulate, RefinementAboveTheBoundaryFloorMeetsTheTarget) {
  for (const Shape& shape : kShapes) {
    SCOPED_TRACE(shape.name);
    const Polygon2 region = shape.make(2000);
    const RegionTriangulation tri = triangulate_region(region, {.target_triangles = 20000});
    EXPECT_GT(tri.triangles.size(), 0.8 * 20000);
    EXPECT_LT(tri.triangles.size(), 1.25 * 20000);
    expect_valid(region, tri);
    double smallest = 180;
    for (const auto& t : tri.triangles) smallest = std::min(smallest, min_angle_degrees(tri, t));
    EXPECT_GE(smallest, 20.0);
  }
}

TEST(Triangulate, GulfOfMexicoLonLatAsGiven) {
  const auto path = data_dir() / "regions" / "gulf_of_mexico.geojson";
  ASSERT_TRUE(std::filesystem::exists(path)) << "missing test data " << path << " (set STRUCTMESH_DATA)";
  const auto polygons = read_region(path);
  ASSERT_EQ(polygons.size(), 1u);
  const Polygon2& region = polygons[0];
  const RegionTriangulation tri = triangulate_region(region);
  EXPECT_EQ(tri.points.size(), region.points.size());
  EXPECT_EQ(tri.boundary_edges.size(), segment_count(region));
  const double expected = area(region);
  EXPECT_NEAR(total_area(tri), expected, 1e-9 * expected);
  EXPECT_EQ(tri.triangles.size(), region.points.size() + 2 * region.hole_count() - 2);
  std::size_t non_positive = 0;
  for (const auto& t : tri.triangles) non_positive += triangle_area(tri, t) > 0 ? 0 : 1;
  EXPECT_EQ(non_positive, 0u);
  for (std::size_t i = 0; i < region.points.size(); ++i) ASSERT_EQ(tri.points[i], region.points[i]);
}

std::string input_error(const Polygon2& region) {
  try {
    triangulate_region(region);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no InputError";
}

TEST(Triangulate, BowTieIsAnInputError) {
  const std::string message = input_error(make_polygon({{{0, 0}, {1, 1}, {1, 0}, {0, 1}}}));
  EXPECT_NE(message.find("crosses"), std::string::npos) << message;
}

TEST(Triangulate, CrossingRingsAreAnInputError) {
  const std::string message = input_error(make_polygon({kUnitSquare, {{0.5, 0.5}, {0.5, 2}, {2, 2}, {2, 0.5}}}));
  EXPECT_NE(message.find("crosses"), std::string::npos) << message;
}

TEST(Triangulate, TouchingVertexIsAnInputError) {
  // The hole's vertex (0.5, 0) lies on the outer ring's first segment.
  const std::string message = input_error(make_polygon({kUnitSquare, {{0.5, 0}, {0.25, 0.5}, {0.75, 0.5}}}));
  EXPECT_NE(message.find("lies on"), std::string::npos) << message;
}

TEST(Triangulate, RepeatedPointIsAnInputError) {
  const std::string message = input_error(make_polygon({{{0, 0}, {1, 0}, {1, 0}, {1, 1}}}));
  EXPECT_NE(message.find("coincide"), std::string::npos) << message;
}

TEST(Triangulate, RingsTouchingAtAPointWhenMerged) {
  // A triangular hole whose vertex is the outer square's corner (4, 0), as a paving
  // front touching an island's front: an InputError by default; merged, the corner
  // is one vertex, the area is exact and every segment is one oriented edge.
  const Polygon2 region = make_polygon({{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {{4, 0}, {2, 1}, {3, 2}}});
  EXPECT_NE(input_error(region).find("coincide"), std::string::npos);
  const RegionTriangulation tri = triangulate_region(region, {.merge_repeated_points = true});
  EXPECT_EQ(total_area(tri), 16.0 - 1.5);
  ASSERT_EQ(tri.boundary_edges.size(), region.points.size());
  for (const auto& t : tri.triangles)
    for (const Index v : t) EXPECT_NE(v, 4u) << "the repeated corner is vertex 1";
  for (const auto& [a, b] : tri.boundary_edges) {
    // The region is on the left: the edge's triangle has its third vertex there.
    bool found = false;
    for (const auto& t : tri.triangles)
      for (int j = 0; j < 3; ++j)
        if (t[j] == a && t[(j + 1) % 3] == b) found = true;
    EXPECT_TRUE(found) << a << "->" << b;
  }
}

TEST(Triangulate, ShortRingAndEmptyRegionAreInputErrors) {
  EXPECT_NE(input_error(make_polygon({{{0, 0}, {1, 0}}})).find("fewer than 3"), std::string::npos);
  EXPECT_NE(input_error(Polygon2{}).find("no rings"), std::string::npos);
}

}  // namespace
}  // namespace structmesh
