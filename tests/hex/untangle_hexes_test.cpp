// untangle_hexes (joint untangling): a grid whose interior is turned inside out comes back
// valid with its fixed points where they were, and error-free degenerate calls.
#include "hex/untangle_hexes.hpp"
#include "quality/test_meshes.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace structmesh {
namespace {

std::size_t inverted_hexes(const HexMesh& mesh) {
  std::size_t inverted = 0;
  for (const auto& h : mesh.hexes) {
    std::array<Vec3, 8> p;
    for (int i = 0; i < 8; ++i) p[i] = mesh.points[h[i]];
    const std::optional<double> sj = hex_scaled_jacobian(p);
    inverted += !sj || *sj <= 0 ? 1 : 0;
  }
  return inverted;
}

// A 4x4x4 unit grid whose 27 interior points are mirrored through the plane x = 2: every
// hex touching the x = 0 or x = 4 side is inverted, and no single interior point can be
// moved back on its own without inverting others.
TEST(UntangleHexes, MirroredInteriorComesBackValid) {
  HexMesh mesh = test::hex_grid(4, 4, 4);
  std::vector<Index> interior;
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    const Vec3& p = mesh.points[v];
    if (p.minCoeff() > 0.5 && p.maxCoeff() < 3.5) interior.push_back(static_cast<Index>(v));
  }
  ASSERT_EQ(interior.size(), 27u);
  for (const Index v : interior) mesh.points[v].x() = 4 - mesh.points[v].x() + 0.3;
  const std::vector<Vec3> before = mesh.points;
  ASSERT_GT(inverted_hexes(mesh), 10u);

  const hex_detail::HexUntangleResult result = hex_detail::untangle_hexes(mesh.points, mesh.hexes, interior, 1.0);
  EXPECT_LT(result.min_det_before, 0);
  EXPECT_GT(result.min_det_after, 0);
  EXPECT_EQ(inverted_hexes(mesh), 0u);
  std::vector<std::uint8_t> is_free(mesh.points.size(), 0);
  for (const Index v : interior) is_free[v] = 1;
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    if (!is_free[v]) {
      EXPECT_EQ(mesh.points[v], before[v]) << v;
    }
}

TEST(UntangleHexes, NothingFreeOrZeroSizeLeavesThePointsAlone) {
  HexMesh mesh = test::hex_grid(2, 2, 2);
  const std::vector<Vec3> before = mesh.points;
  const std::vector<Index> none;
  EXPECT_EQ(hex_detail::untangle_hexes(mesh.points, mesh.hexes, none, 1.0).outer_iterations, 0);
  const std::vector<Index> centre{13};
  EXPECT_EQ(hex_detail::untangle_hexes(mesh.points, mesh.hexes, centre, 0.0).outer_iterations, 0);
  EXPECT_EQ(mesh.points, before);
}

}  // namespace
}  // namespace structmesh

namespace structmesh {
namespace {

double worst_scaled_jacobian(const HexMesh& mesh) {
  double worst = 1;
  for (const auto& h : mesh.hexes) {
    std::array<Vec3, 8> p;
    for (int i = 0; i < 8; ++i) p[i] = mesh.points[h[i]];
    worst = std::min(worst, hex_scaled_jacobian(p).value_or(-2.0));
  }
  return worst;
}

// polish_hexes: the 27 interior points of a 4x4x4 grid, displaced at random, move together
// to raise the worst hex; the boundary stays, and the reported values are the mesh's.
TEST(PolishHexes, RaisesTheWorstHexOfADistortedGrid) {
  HexMesh mesh = test::hex_grid(4, 4, 4);
  std::vector<Index> interior;
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    if (mesh.points[v].minCoeff() > 0.5 && mesh.points[v].maxCoeff() < 3.5) interior.push_back(static_cast<Index>(v));
  ASSERT_EQ(interior.size(), 27u);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> offset(-0.3, 0.3);
  for (const Index v : interior) mesh.points[v] += Vec3(offset(random), offset(random), offset(random));
  const double before = worst_scaled_jacobian(mesh);
  ASSERT_GT(before, 0.0);
  ASSERT_LT(before, 0.8);
  const std::vector<Vec3> start = mesh.points;
  const hex_detail::HexPolishResult result = hex_detail::polish_hexes(mesh.points, mesh.hexes, interior);
  EXPECT_DOUBLE_EQ(result.worst_before, before);
  EXPECT_DOUBLE_EQ(result.worst_after, worst_scaled_jacobian(mesh));
  EXPECT_GT(result.worst_after, before + 0.1) << before << " -> " << result.worst_after;
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    if (std::find(interior.begin(), interior.end(), static_cast<Index>(v)) == interior.end()) {
      EXPECT_EQ(mesh.points[v], start[v]) << v;
    }
}

// A perfect grid cannot get better: nothing moves.
TEST(PolishHexes, LeavesAPerfectGridAlone) {
  HexMesh mesh = test::hex_grid(3, 3, 3);
  std::vector<Index> interior;
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    if (mesh.points[v].minCoeff() > 0.5 && mesh.points[v].maxCoeff() < 2.5) interior.push_back(static_cast<Index>(v));
  const std::vector<Vec3> start = mesh.points;
  const hex_detail::HexPolishResult result = hex_detail::polish_hexes(mesh.points, mesh.hexes, interior);
  EXPECT_DOUBLE_EQ(result.worst_before, 1.0);
  EXPECT_DOUBLE_EQ(result.worst_after, 1.0);
  EXPECT_EQ(mesh.points, start);
}

std::vector<double> hex_scores(const HexMesh& mesh) {
  std::vector<double> scores;
  for (const auto& h : mesh.hexes) {
    std::array<Vec3, 8> p;
    for (int i = 0; i < 8; ++i) p[i] = mesh.points[h[i]];
    scores.push_back(hex_scaled_jacobian(p).value_or(-2.0));
  }
  return scores;
}

// A 6x6x6 grid whose interior points are displaced at random (none inverted): the joint
// ascent raises the sum of the scaled Jacobians, keeps every hex above its floor (0.1 below
// its start, or the start for the worst hexes) and moves only the free points.
TEST(RaiseMeanScaledJacobian, RaisesTheMeanAndKeepsEveryHexAboveItsFloor) {
  HexMesh mesh = test::hex_grid(6, 6, 6);
  std::vector<Index> interior;
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    if (mesh.points[v].minCoeff() > 0.5 && mesh.points[v].maxCoeff() < 5.5) interior.push_back(static_cast<Index>(v));
  ASSERT_EQ(interior.size(), 125u);
  std::mt19937 random(9);
  std::uniform_real_distribution<double> offset(-0.2, 0.2);
  for (const Index v : interior) mesh.points[v] += Vec3(offset(random), offset(random), offset(random));
  const std::vector<double> before = hex_scores(mesh);
  const double worst = *std::min_element(before.begin(), before.end());
  ASSERT_GT(worst, 0.0);
  std::vector<double> floor(before.size());
  for (std::size_t h = 0; h < before.size(); ++h)
    floor[h] = before[h] < worst + 0.1 ? before[h] - 1e-9 : before[h] - 0.1;
  double sum_before = 0;
  for (const double s : before) sum_before += s;
  const std::vector<Vec3> start = mesh.points;

  const hex_detail::HexMeanAscentResult result =
      hex_detail::raise_mean_scaled_jacobian(mesh.points, mesh.hexes, interior, floor, 300);
  const std::vector<double> after = hex_scores(mesh);
  double sum_after = 0;
  for (const double s : after) sum_after += s;
  EXPECT_NEAR(result.score_sum_before, sum_before, 1e-9);
  EXPECT_NEAR(result.score_sum_after, sum_after, 1e-9);
  EXPECT_GT(sum_after / static_cast<double>(after.size()), sum_before / static_cast<double>(before.size()) + 0.02)
      << sum_before / static_cast<double>(before.size()) << " -> " << sum_after / static_cast<double>(after.size());
  for (std::size_t h = 0; h < after.size(); ++h) EXPECT_GT(after[h], floor[h]) << h;
  EXPECT_GE(*std::min_element(after.begin(), after.end()), worst - 1e-9);
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    if (std::find(interior.begin(), interior.end(), static_cast<Index>(v)) == interior.end()) {
      EXPECT_EQ(mesh.points[v], start[v]) << v;
    }
}

// Free points with a normal pay a spring for leaving their place along it: the top face's
// points of a perturbed grid, free with normal z and bumped off their plane, keep their
// height under stiff springs (within a thousandth of an edge) while they slide sideways and
// the mean rises; without the springs the ascent flattens the bumps.
TEST(RaiseMeanScaledJacobian, NormalSpringsHoldBoundaryPointsAlongTheNormal) {
  HexMesh mesh = test::hex_grid(6, 6, 6);
  std::vector<Index> free;
  std::vector<Vec3> normal;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> offset(-0.2, 0.2);
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    Vec3& p = mesh.points[v];
    if (p.x() < 0.5 || p.x() > 5.5 || p.y() < 0.5 || p.y() > 5.5 || p.z() < 0.5) continue;
    const bool top = p.z() > 5.5;
    p += Vec3(offset(random), offset(random), offset(random));
    free.push_back(static_cast<Index>(v));
    normal.push_back(top ? Vec3(0, 0, 1) : Vec3::Zero());
  }
  ASSERT_EQ(free.size(), 150u);
  const std::vector<double> before = hex_scores(mesh);
  const std::vector<double> floor(before.size(), *std::min_element(before.begin(), before.end()) - 1e-9);
  const auto height_change = [&](const std::vector<Vec3>& points, const std::vector<Vec3>& start) {
    double most = 0, slid = 0;
    for (std::size_t k = 0; k < free.size(); ++k)
      if (normal[k].squaredNorm() > 0) {
        const Vec3 move = points[free[k]] - start[free[k]];
        most = std::max(most, std::abs(move.z()));
        slid = std::max(slid, move.head<2>().norm());
      }
    return std::pair{most, slid};
  };
  std::vector<Vec3> loose = mesh.points;
  hex_detail::raise_mean_scaled_jacobian(loose, mesh.hexes, free, floor, 300, normal, 0);
  EXPECT_GT(height_change(loose, mesh.points).first, 0.02);

  const std::vector<Vec3> start = mesh.points;
  const hex_detail::HexMeanAscentResult result =
      hex_detail::raise_mean_scaled_jacobian(mesh.points, mesh.hexes, free, floor, 300, normal, 1e6);
  EXPECT_GT(result.score_sum_after, result.score_sum_before + 0.02 * static_cast<double>(before.size()));
  const auto [height, slid] = height_change(mesh.points, start);
  EXPECT_LT(height, 1e-3);
  EXPECT_GT(slid, 0.05);
}

// A start below a floor, or floors that do not match the hexes, leave the points alone.
TEST(RaiseMeanScaledJacobian, LeavesThePointsAloneWhenAHexStartsBelowItsFloor) {
  HexMesh mesh = test::hex_grid(3, 3, 3);
  std::vector<Index> interior;
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    if (mesh.points[v].minCoeff() > 0.5 && mesh.points[v].maxCoeff() < 2.5) interior.push_back(static_cast<Index>(v));
  mesh.points[interior[0]] += Vec3(0.3, -0.2, 0.1);
  const std::vector<Vec3> start = mesh.points;
  std::vector<double> floor(mesh.hexes.size(), 0.0);
  floor[3] = 1.0;  // no hex reaches 1 here
  hex_detail::HexMeanAscentResult result =
      hex_detail::raise_mean_scaled_jacobian(mesh.points, mesh.hexes, interior, floor, 100);
  EXPECT_EQ(mesh.points, start);
  EXPECT_EQ(result.score_sum_after, result.score_sum_before);
  floor.pop_back();
  result = hex_detail::raise_mean_scaled_jacobian(mesh.points, mesh.hexes, interior, floor, 100);
  EXPECT_EQ(mesh.points, start);
}

}  // namespace
}  // namespace structmesh
