// L_p-CVT energy (3.12) and its exact gradient (design/partition2d.md §1.7, §2.3),
// the initial grid and the L-BFGS optimisation (§2.5).
#include "partition2d/partition_internal.hpp"
#include "structmesh/error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace structmesh::partition2d {
namespace {

Polygon2 unit_square() {
  Polygon2 region;
  region.add_ring(std::vector<Vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  return region;
}

// A small non-convex region (an L) with a square hole.
Polygon2 l_with_hole() {
  Polygon2 region;
  region.add_ring(std::vector<Vec2>{{0, 0}, {4, 0}, {4, 1.5}, {1.7, 1.5}, {1.7, 4}, {0, 4}});
  region.add_ring(std::vector<Vec2>{{0.4, 0.3}, {0.4, 1.1}, {1.2, 1.1}, {1.2, 0.3}});
  return region;
}

std::vector<Vec2> sites_in_l(unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> coordinate(0, 4);
  std::vector<Vec2> sites;
  while (sites.size() < 12) {
    const Vec2 s(coordinate(random), coordinate(random));
    if (s.x() < 1.7 || s.y() < 1.5) sites.push_back(s);
  }
  return sites;
}

TEST(LpCvt, AnalyticValuesOnUnitSquare) {
  const DomainMesh domain = build_domain_mesh(unit_square(), Frame{}, 0.3);
  const std::vector<Vec2> site{{0.5, 0.5}};
  std::vector<double> gradient;
  // p = 2: 2 * int_{-1/2}^{1/2} x^2 dx = 1/6.
  EXPECT_NEAR(lp_energy(domain, site, 2, &gradient), 1.0 / 6.0, 1e-14);
  EXPECT_NEAR(gradient[0], 0, 1e-14);
  EXPECT_NEAR(gradient[1], 0, 1e-14);
  // p = 8: 2 * int_{-1/2}^{1/2} x^8 dx = 2 * 2 (1/2)^9 / 9 = 1/1152.
  EXPECT_NEAR(lp_energy(domain, site, 8, &gradient), 1.0 / 1152.0, 1e-15);
  EXPECT_NEAR(gradient[0], 0, 1e-14);
  // Off centre, p = 8: sum over both axes of int_0^1 (y - s)^8 dy.
  const std::vector<Vec2> moved{{0.3, 0.6}};
  const auto axis = [](double s) { return (std::pow(1 - s, 9) + std::pow(s, 9)) / 9; };
  EXPECT_NEAR(lp_energy(domain, moved, 8, nullptr), axis(0.3) + axis(0.6), 1e-14);
  EXPECT_THROW(lp_energy(domain, site, 3, nullptr), InputError);
}

TEST(LpCvt, GradientMatchesFiniteDifferences) {
  const DomainMesh domain = build_domain_mesh(l_with_hole(), Frame{}, 0.45);
  const std::vector<Vec2> sites = sites_in_l(11);
  for (const int p : {2, 4, 8, 12}) {
    std::vector<double> gradient;
    lp_energy(domain, sites, p, &gradient);
    double norm = 0;
    for (const double g : gradient) norm = std::max(norm, std::abs(g));
    ASSERT_GT(norm, 0);
    const double step = 1e-6;
    for (std::size_t k = 0; k < gradient.size(); ++k) {
      std::vector<Vec2> plus = sites, minus = sites;
      plus[k / 2][k % 2] += step;
      minus[k / 2][k % 2] -= step;
      const double difference =
          (lp_energy(domain, plus, p, nullptr) - lp_energy(domain, minus, p, nullptr)) / (2 * step);
      EXPECT_NEAR(gradient[k], difference, 1e-5 * norm) << "p = " << p << ", coordinate " << k;
    }
  }
}

TEST(LpCvt, P2GradientIsTwiceMassTimesCentroidOffset) {
  const DomainMesh domain = build_domain_mesh(l_with_hole(), Frame{}, 0.45);
  const std::vector<Vec2> sites = sites_in_l(3);
  std::vector<double> gradient;
  lp_energy(domain, sites, 2, &gradient);
  const Tessellation t = restricted_voronoi(domain, sites);
  std::vector<double> mass(sites.size(), 0.0);
  std::vector<Vec2> moment(sites.size(), Vec2::Zero());
  for (Index f = 0; f < t.face_count(); ++f) {
    const Index begin = t.face_offsets[f], end = t.face_offsets[f + 1];
    const Vec2& o = t.vertices[t.face_vertices[begin]];
    for (Index h = begin + 1; h + 1 < end; ++h) {
      const Vec2& a = t.vertices[t.face_vertices[h]];
      const Vec2& b = t.vertices[t.face_vertices[h + 1]];
      const double area = 0.5 * ((a - o).x() * (b - o).y() - (a - o).y() * (b - o).x());
      mass[t.face_cell[f]] += area;
      moment[t.face_cell[f]] += area * (o + a + b) / 3;
    }
  }
  for (std::size_t i = 0; i < sites.size(); ++i) {
    ASSERT_GT(mass[i], 0);
    const Vec2 expected = 2 * (mass[i] * sites[i] - moment[i]);
    EXPECT_NEAR(gradient[2 * i], expected.x(), 1e-12);
    EXPECT_NEAR(gradient[2 * i + 1], expected.y(), 1e-12);
  }
}

TEST(LpCvt, EmptyCellDetected) {
  const DomainMesh domain = build_domain_mesh(unit_square(), Frame{}, 0);
  const std::vector<Vec2> sites{{0.25, 0.25}, {0.75, 0.3}, {0.5, 0.8}, {3, -2}};
  std::vector<double> gradient;
  std::size_t empty = 0;
  const double energy = lp_energy(domain, sites, 8, &gradient, &empty);
  EXPECT_GT(energy, 0);
  EXPECT_EQ(empty, 1u);
  EXPECT_EQ(gradient[6], 0);
  EXPECT_EQ(gradient[7], 0);
  std::size_t none = 5;
  lp_energy(domain, std::vector<Vec2>(sites.begin(), sites.begin() + 3), 8, nullptr, &none);
  EXPECT_EQ(none, 0u);
}

TEST(LpCvt, InitialGridSitesInsideAndDeterministic) {
  const Polygon2 region = l_with_hole();
  const DomainMesh domain = build_domain_mesh(region, Frame{}, 0.3);
  const std::vector<Vec2> sites = initial_grid_sites(domain, 40, 1);
  EXPECT_NEAR(static_cast<double>(sites.size()), 40.0, 6.0);
  EXPECT_EQ(sites, initial_grid_sites(domain, 40, 1));
  EXPECT_NE(sites, initial_grid_sites(domain, 40, 2));  // different jitter
  std::size_t empty = 1;
  lp_energy(domain, sites, 8, nullptr, &empty);
  EXPECT_EQ(empty, 0u);  // every grid site is inside, so owns a cell
  for (const Vec2& s : sites) {
    const bool in_hole = s.x() > 0.4 && s.x() < 1.2 && s.y() > 0.3 && s.y() < 1.1;
    EXPECT_FALSE(in_hole);
    EXPECT_TRUE(s.x() < 1.7 + 1e-9 || s.y() < 1.5 + 1e-9);
  }
}

TEST(LpCvt, EnergyDecreasesWithIterations) {
  const DomainMesh domain = build_domain_mesh(l_with_hole(), Frame{}, 0.45);
  const std::vector<Vec2> start = sites_in_l(9);
  double previous = lp_energy(domain, start, 8, nullptr);
  for (int iterations = 1; iterations <= 8; ++iterations) {
    LpCvtOptions options;
    options.max_iterations = iterations;
    const LpCvtResult result = optimise_lp_cvt(domain, start, options);
    EXPECT_EQ(result.sites.size(), start.size());
    EXPECT_NEAR(result.energy_initial, lp_energy(domain, start, 8, nullptr), 1e-15);
    EXPECT_NEAR(result.energy_final, lp_energy(domain, result.sites, 8, nullptr), 1e-15);
    EXPECT_LE(result.energy_final, previous) << iterations << " iterations";
    EXPECT_TRUE(result.stop_reason == "max iterations" || result.stop_reason == "converged" ||
                result.stop_reason == "line search stopped");
    previous = result.energy_final;
  }
  EXPECT_LT(previous, 0.8 * lp_energy(domain, start, 8, nullptr));
}

TEST(LpCvt, GradientWhenBisectorRunsAlongCdtEdge) {
  // Exact degeneracy: the bisector of the two sites is the line y = x/2, which is the
  // CDT diagonal from (0, 0) to (2, 1) of this quadrilateral (the Delaunay one: the
  // opposite angles sum to about 163 degrees). The bisector term of §1.7 must still
  // be integrated along it (it is not zero: the line is neither axis-parallel nor
  // diagonal, so f_i != f_j there).
  Polygon2 region;
  region.add_ring(std::vector<Vec2>{{0, 0}, {2.5, 0}, {2, 1}, {0.5, 1.3}});
  const DomainMesh domain = build_domain_mesh(region, Frame{}, 0);
  ASSERT_EQ(domain.triangles.size(), 2u);
  const std::vector<Vec2> sites{{1.75, 1.5}, {2.25, 0.5}};  // mirror images across y = x/2
  std::vector<double> gradient;
  lp_energy(domain, sites, 8, &gradient);
  const double step = 1e-6;
  double norm = 0;
  for (const double g : gradient) norm = std::max(norm, std::abs(g));
  for (std::size_t k = 0; k < gradient.size(); ++k) {
    std::vector<Vec2> plus = sites, minus = sites;
    plus[k / 2][k % 2] += step;
    minus[k / 2][k % 2] -= step;
    const double difference = (lp_energy(domain, plus, 8, nullptr) - lp_energy(domain, minus, 8, nullptr)) / (2 * step);
    // The bisector passes through two domain corners, where F'' jumps: the central
    // difference is only first-order accurate here, hence 2e-5.
    EXPECT_NEAR(gradient[k], difference, 2e-5 * norm) << "coordinate " << k;
  }
  const Tessellation t = restricted_voronoi(domain, sites);
  EXPECT_EQ(t.face_count(), 2u);
}

}  // namespace
}  // namespace structmesh::partition2d
