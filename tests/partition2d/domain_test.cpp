// The partitioning domain: projection, Steiner-grid triangulation, proxy boundary,
// and the METIS/MADD baseline tessellation.
#include "partition2d/partition_internal.hpp"
#include "structmesh/check.hpp"
#include "structmesh/io.hpp"
#include "structmesh/regions.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>

namespace structmesh::partition2d {
namespace {

std::filesystem::path data_root() {
  const char* env = std::getenv("STRUCTMESH_DATA");
  return env != nullptr ? std::filesystem::path(env) : std::filesystem::path(STRUCTMESH_DATA_DEFAULT);
}

Frame frame_for(const Polygon2& region, std::size_t cells) {
  Frame frame;
  const BoundingBox2 box = region.bounding_box();
  frame.center = 0.5 * (box.min + box.max);
  frame.scale = std::sqrt(std::abs(area(region)) / static_cast<double>(cells));
  return frame;
}

TEST(PartitionDomain, ProjectionRoundTripsAndKeepsAreas) {
  Projection projection;
  projection.active = true;
  projection.lat0 = 25;
  projection.lon0 = -90;
  for (const Vec2& lonlat : {Vec2(-90, 25), Vec2(-97.5, 18.1), Vec2(-80.2, 31)}) {
    const Vec2 back = projection.inverse(projection.forward(lonlat));
    EXPECT_NEAR(back.x(), lonlat.x(), 1e-9);
    EXPECT_NEAR(back.y(), lonlat.y(), 1e-9);
  }
  EXPECT_NEAR(projection.forward(Vec2(-90, 25)).norm(), 0.0, 1e-9);
  // Equal area: a 1°x1° cell at latitude 30 has the spherical area R^2 (sin 31° - sin 30°) (pi/180).
  Polygon2 cell;
  std::vector<Vec2> ring;
  const int n = 200;  // densified edges: the projected cell has curved sides
  for (int i = 0; i < n; ++i) ring.emplace_back(-91 + double(i) / n, 30);
  for (int i = 0; i < n; ++i) ring.emplace_back(-90, 30 + double(i) / n);
  for (int i = 0; i < n; ++i) ring.emplace_back(-90 - double(i) / n, 31);
  for (int i = 0; i < n; ++i) ring.emplace_back(-91, 31 - double(i) / n);
  cell.add_ring(ring);
  cell.coordinates = Polygon2::Coordinates::LonLat;
  const Projection chosen = choose_projection(cell);
  ASSERT_TRUE(chosen.active);
  const double r = 6371008.8, degree = 3.14159265358979323846 / 180;
  const double spherical = r * r * (std::sin(31 * degree) - std::sin(30 * degree)) * degree;
  EXPECT_NEAR(area(project_region(cell, chosen)) / spherical, 1.0, 1e-5);
  EXPECT_EQ(choose_projection(make_key_region(100)).active, false);
}

TEST(PartitionDomain, SteinerGridTriangulationIsConforming) {
  const Polygon2 key = make_key_region(2000);
  const Frame frame = frame_for(key, 400);
  const DomainMesh domain = build_domain_mesh(key, frame, 0.5 * frame.scale);
  EXPECT_EQ(domain.input_point_count, key.points.size());
  EXPECT_GT(domain.points.size(), key.points.size() + 400);  // the grid added interior points
  // Input points kept in order (normalised).
  for (std::size_t i = 0; i < key.points.size(); i += 97) {
    EXPECT_EQ(frame.to_metric(domain.points[i]).x(), frame.to_metric(frame.to_normalised(key.points[i])).x());
  }
  EXPECT_NEAR(domain.area * frame.scale * frame.scale / area(key), 1.0, 1e-12);
  // Neighbour relation symmetric, boundary edges exactly the input segments.
  std::size_t boundary = 0;
  for (Index t = 0; t < domain.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Index n = domain.neighbors[t][k];
      if (n == kInvalidIndex) {
        ++boundary;
        EXPECT_LT(domain.triangles[t][k], domain.input_point_count);
        continue;
      }
      int back = 0;
      for (int j = 0; j < 3; ++j) back += domain.neighbors[n][j] == t ? 1 : 0;
      EXPECT_EQ(back, 1);
    }
  }
  EXPECT_EQ(boundary, key.points.size());
  // Triangles are at most about a grid spacing across in the interior: no long slivers.
  double longest = 0;
  for (const auto& tri : domain.triangles) {
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (domain.points[tri[k]] - domain.points[tri[(k + 1) % 3]]).norm());
  }
  EXPECT_LT(longest, 2.0);
}

TEST(PartitionDomain, ProxySimplifiesAndStaysValid) {
  const Polygon2 pipe = make_pipe_region(200'000);
  const Frame frame = frame_for(pipe, 1000);
  const Polygon2 proxy = proxy_region(pipe, 0.02 * frame.scale, 0.01 * frame.scale * frame.scale);
  EXPECT_LT(proxy.points.size(), pipe.points.size() / 4);
  EXPECT_TRUE(check_region({proxy}).valid);
  EXPECT_NEAR(area(proxy) / area(pipe), 1.0, 1e-3);
  EXPECT_EQ(proxy.ring_count(), pipe.ring_count());
}

TEST(PartitionDomain, GulfProxyIsValid) {
  const auto path = data_root() / "regions" / "gulf_of_mexico.geojson";
  if (!std::filesystem::exists(path)) GTEST_FAIL() << "missing test data " << path;
  const std::vector<Polygon2> regions = read_region(path);
  ASSERT_EQ(regions.size(), 1u);
  const Polygon2 metric = project_region(regions[0], choose_projection(regions[0]));
  const Frame frame = frame_for(metric, 4000);
  const Polygon2 proxy = proxy_region(metric, 0.02 * frame.scale, 0.01 * frame.scale * frame.scale);
  EXPECT_TRUE(check_region({proxy}).valid);
  EXPECT_LE(proxy.points.size(), metric.points.size());
}

TEST(PartitionDomain, TriangleTessellationTwinsAndMaddGroups) {
  const Polygon2 pipe = make_pipe_region(4000);
  const Frame frame = frame_for(pipe, 20000);
  for (const bool madd : {false, true}) {
    const Tessellation t = triangle_tessellation(pipe, frame, 20000, madd);
    const std::vector<double> areas = face_areas(t);
    double sum = 0;
    for (const double a : areas) {
      EXPECT_GT(a, 0);
      sum += a;
    }
    EXPECT_NEAR(sum * frame.scale * frame.scale / area(pipe), 1.0, 1e-12);
    std::size_t boundary = 0;
    for (Index h = 0; h < t.twin.size(); ++h) {
      if (t.twin[h] == kInvalidIndex) {
        ++boundary;
        ASSERT_GE(t.boundary_ring[h], 0);
        EXPECT_LT(static_cast<std::size_t>(t.boundary_ring[h]), pipe.ring_count());
      } else {
        EXPECT_EQ(t.twin[t.twin[h]], h);
      }
    }
    EXPECT_GE(boundary, pipe.points.size());
    std::map<Index, int> group_size;
    for (const Index c : t.face_cell) ++group_size[c];
    EXPECT_EQ(group_size.size(), t.cell_count);
    int largest = 0;
    for (const auto& [cell, size] : group_size) largest = std::max(largest, size);
    if (madd) {
      EXPECT_LT(t.cell_count, t.face_count());
      EXPECT_LE(largest, 4);
    } else {
      EXPECT_EQ(t.cell_count, t.face_count());
    }
  }
}

}  // namespace
}  // namespace structmesh::partition2d
