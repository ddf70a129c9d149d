// hex_quality: statistics, inverted / invalid counts and N_h (Table 5.2) on meshes
// counted by hand.
#include "quality/test_meshes.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>

namespace structmesh {
namespace {

TEST(HexQuality, SingleCube) {
  const HexQuality q = hex_quality(test::hex_grid(1, 1, 1));
  EXPECT_EQ(q.scaled_jacobian, std::vector<double>{1.0});
  EXPECT_EQ(q.corner_scaled_jacobian, std::vector<double>{1.0});
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_EQ(q.invalid, 0u);
  EXPECT_EQ(q.dihedral_degrees.count, 12u);
  EXPECT_NEAR(q.dihedral_degrees.mean, 90.0, 1e-12);
  EXPECT_NEAR(q.dihedral_degrees.stddev, 0.0, 1e-12);
  EXPECT_EQ(q.scaled_jacobian_histogram.back(), 1u);
  // All 8 vertices are box corners: 3 boundary edges each.
  EXPECT_EQ(q.singular_boundary, 8u);
  EXPECT_EQ(q.singular_interior, 0u);
}

TEST(HexQuality, StructuredGridsOnlyHaveTheirBoxCornersSingular) {
  // N_h counts boundary vertices with != 4 boundary edges, so the 8 corners of a box
  // count (as polycube corners do in Table 5.2); nothing else in a structured grid.
  for (int n : {2, 3}) {
    const HexQuality q = hex_quality(test::hex_grid(n, n, n));
    EXPECT_EQ(q.singular_interior, 0u) << n;
    EXPECT_EQ(q.singular_boundary, 8u) << n;
    EXPECT_EQ(q.singular_vertices, 8u) << n;
    EXPECT_EQ(q.scaled_jacobian_stats.min, 1.0);
  }
}

TEST(HexQuality, ExtrudedQuadMeshedTriangleCountedByHand) {
  // One layer: all 14 vertices on the boundary. The 2 triangle centres have 3
  // boundary edges (the vertical edge between them is interior), the 6 triangle
  // corners 3 (2 horizontal + 1 vertical); the 6 edge midpoints have 4.
  const HexQuality one = hex_quality(test::extrude(test::polygon_fan(3), 1));
  EXPECT_EQ(one.singular_interior, 0u);
  EXPECT_EQ(one.singular_boundary, 8u);
  // Two layers: the middle centre is interior with 3 + 2 = 5 edges; the middle
  // corners and midpoints have 2 horizontal + 2 vertical boundary edges.
  const HexQuality two = hex_quality(test::extrude(test::polygon_fan(3), 2));
  EXPECT_EQ(two.singular_interior, 1u);
  EXPECT_EQ(two.singular_boundary, 8u);
  EXPECT_EQ(two.singular_vertices, 9u);
  EXPECT_EQ(two.inverted, 0u);
}

TEST(HexQuality, InvertedAndInvalidHexesAreCountedApart) {
  HexMesh mesh = test::hex_grid(3, 1, 1);
  // Hex 0 gets its own copy of corner 6, pushed below the bottom face: inverted.
  mesh.points.emplace_back(0.5, 0.5, -0.5);
  mesh.hexes[0][6] = static_cast<Index>(mesh.points.size() - 1);
  // Hex 2 repeats a vertex: a zero-length edge, invalid (NaN), not perfect.
  mesh.hexes[2][1] = mesh.hexes[2][0];
  const HexQuality q = hex_quality(mesh);
  EXPECT_LT(q.scaled_jacobian[0], 0.0);
  EXPECT_EQ(q.scaled_jacobian[1], 1.0);
  EXPECT_TRUE(std::isnan(q.scaled_jacobian[2]));
  EXPECT_TRUE(std::isnan(q.corner_scaled_jacobian[2]));
  EXPECT_EQ(q.inverted, 1u);
  EXPECT_EQ(q.invalid, 1u);
  EXPECT_EQ(q.scaled_jacobian_stats.count, 2u);
  EXPECT_EQ(q.corner_scaled_jacobian_stats.count, 2u);
  EXPECT_EQ(q.dihedral_degrees.count, 24u);  // the invalid hex's angles are left out
  std::uint64_t histogram_total = 0;
  for (std::uint64_t b : q.scaled_jacobian_histogram) histogram_total += b;
  EXPECT_EQ(histogram_total, 2u);
}

TEST(HexQuality, DihedralStatisticsOfAShearedHex) {
  HexMesh mesh = test::hex_grid(1, 1, 1);
  const double theta = 60 * std::numbers::pi / 180;
  for (int i = 4; i < 8; ++i)
    mesh.points[mesh.hexes[0][i]] = mesh.points[mesh.hexes[0][i - 4]] + Vec3(std::cos(theta), 0, std::sin(theta));
  const HexQuality q = hex_quality(mesh);
  // 8 right angles, two of 60 and two of 120 degrees.
  EXPECT_NEAR(q.dihedral_degrees.mean, 90.0, 1e-12);
  EXPECT_NEAR(q.dihedral_degrees.stddev, 30.0 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(q.dihedral_degrees.min, 60.0, 1e-12);
  EXPECT_NEAR(q.dihedral_degrees.max, 120.0, 1e-12);
  EXPECT_NEAR(q.scaled_jacobian[0], std::sin(theta), 1e-14);
}

TEST(HexQuality, ResultDoesNotDependOnThreadCount) {
  HexMesh mesh = test::hex_grid(30, 25, 20);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (Vec3& p : mesh.points) p += Vec3(jitter(random), jitter(random), jitter(random));
  const HexQuality parallel = hex_quality(mesh);
  HexQuality serial;
  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    serial = hex_quality(mesh);
  }
  EXPECT_EQ(parallel.scaled_jacobian, serial.scaled_jacobian);
  EXPECT_EQ(parallel.corner_scaled_jacobian, serial.corner_scaled_jacobian);
  EXPECT_EQ(std::memcmp(&parallel.dihedral_degrees, &serial.dihedral_degrees, sizeof(Statistics)), 0);
  EXPECT_EQ(std::memcmp(&parallel.scaled_jacobian_stats, &serial.scaled_jacobian_stats, sizeof(Statistics)), 0);
  EXPECT_EQ(parallel.inverted, serial.inverted);
  EXPECT_NEAR(parallel.dihedral_degrees.mean, 90.0, 0.5);
}

}  // namespace
}  // namespace structmesh
