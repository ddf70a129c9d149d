// mapped_mesh(): exact grids on analytic shapes, quality on curved and graded sides,
// no inverted quad where interpolation folds, conformity, input errors, determinism.
#include "quad2d/mapped_mesh.hpp"
#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

namespace structmesh {
namespace {

/// A four-sided part: the loop and its corner positions.
struct Part {
  Polygon2 polygon;
  std::array<std::size_t, 4> corners{};
};

/// `count` + 1 points of the curve f on [0, 1] at the parameters t_k.
std::vector<Vec2> sample(const std::function<Vec2(double)>& f, const std::vector<double>& t) {
  std::vector<Vec2> points;
  for (const double s : t) points.push_back(f(s));
  return points;
}
std::vector<double> uniform(std::size_t segments) {
  std::vector<double> t;
  for (std::size_t k = 0; k <= segments; ++k) t.push_back(static_cast<double>(k) / static_cast<double>(segments));
  return t;
}
/// Segment lengths growing by `ratio` from one to the next.
std::vector<double> graded(std::size_t segments, double ratio) {
  std::vector<double> t{0};
  double length = 1;
  for (std::size_t k = 0; k < segments; ++k, length *= ratio) t.push_back(t.back() + length);
  for (double& s : t) s /= t.back();
  return t;
}
std::function<Vec2(double)> line(Vec2 a, Vec2 b) {
  return [a, b](double t) { return Vec2((1 - t) * a + t * b); };
}

/// The part bounded by four sides, each from its start corner to the next corner
/// (counter-clockwise; the last point of a side is the first of the next).
Part four_sided(const std::array<std::vector<Vec2>, 4>& sides) {
  Part part;
  std::vector<Vec2> ring;
  for (int s = 0; s < 4; ++s) {
    part.corners[s] = ring.size();
    ring.insert(ring.end(), sides[s].begin(), sides[s].end() - 1);
  }
  part.polygon.add_ring(ring);
  return part;
}

Part rectangle(double w, double h, std::size_t m, std::size_t n) {
  return four_sided({sample(line({0, 0}, {w, 0}), uniform(m)), sample(line({w, 0}, {w, h}), uniform(n)),
                     sample(line({w, h}, {0, h}), uniform(m)), sample(line({0, h}, {0, 0}), uniform(n))});
}

Part quarter_annulus(std::size_t radial, std::size_t around) {
  const auto arc = [](double r, double from, double to) {
    return [=](double t) { return Vec2(r * std::cos(from + t * (to - from)), r * std::sin(from + t * (to - from))); };
  };
  const double q = std::numbers::pi / 2;
  return four_sided({sample(line({1, 0}, {2, 0}), uniform(radial)), sample(arc(2, 0, q), uniform(around)),
                     sample(line({0, 2}, {0, 1}), uniform(radial)), sample(arc(1, q, 0), uniform(around))});
}

/// Unit square whose top side is one full sine wave of amplitude 0.1.
Part wavy(std::size_t m, std::size_t n) {
  const auto top = [](double t) {
    const double x = 1 - t;
    return Vec2(x, 1 + 0.1 * std::sin(2 * std::numbers::pi * x));
  };
  return four_sided({sample(line({0, 0}, {1, 0}), uniform(m)), sample(line({1, 0}, {1, 1}), uniform(n)),
                     sample(top, uniform(m)), sample(line({0, 1}, {0, 0}), uniform(n))});
}

/// Square [0,3]^2 with a slot of height 1 cut from the right side `depth` deep: a C
/// open to the right, its four corners those of the square.
Part c_shape(double depth) {
  const double d = 3 - depth;
  std::vector<Vec2> right;
  const std::vector<Vec2> path{{3, 0}, {3, 1}, {d, 1}, {d, 2}, {3, 2}, {3, 3}};
  for (std::size_t s = 0; s + 1 < path.size(); ++s) {
    const double length = (path[s + 1] - path[s]).norm();
    const auto steps = static_cast<std::size_t>(std::lround(length / 0.125));
    for (std::size_t k = 0; k < steps; ++k)
      right.push_back(path[s] + (path[s + 1] - path[s]) * static_cast<double>(k) / static_cast<double>(steps));
  }
  right.push_back(path.back());
  const std::size_t n = right.size() - 1;
  return four_sided({sample(line({0, 0}, {3, 0}), uniform(24)), right, sample(line({3, 3}, {0, 3}), uniform(24)),
                     sample(line({0, 3}, {0, 0}), uniform(n))});
}

struct Measured {
  double min = 1, avg = 0;
  std::size_t singular = 0;
};

double twice_area(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  return (c - a).x() * (d - b).y() - (c - a).y() * (d - b).x();
}

/// Every promise of the contract; returns the quality figures.
Measured check_mesh(const Part& in, const PavedPart& out) {
  const Polygon2& poly = in.polygon;
  const std::size_t n = poly.points.size();
  EXPECT_GE(out.points.size(), n);
  for (std::size_t i = 0; i < n && i < out.points.size(); ++i) {
    EXPECT_EQ(out.points[i].x(), poly.points[i].x()) << "input point " << i << " moved";
    EXPECT_EQ(out.points[i].y(), poly.points[i].y()) << "input point " << i << " moved";
  }
  const std::size_t m = in.corners[1] - in.corners[0], k = in.corners[2] - in.corners[1];
  EXPECT_EQ(out.quads.size(), m * k);
  EXPECT_EQ(out.points.size(), (m + 1) * (k + 1));
  QuadMesh mesh;
  for (const Vec2& p : out.points) mesh.points.emplace_back(p.x(), p.y(), 0);
  mesh.quads = out.quads;
  const QuadQuality quality = quad_quality(mesh);
  EXPECT_EQ(quality.inverted, 0u);
  Measured r;
  r.singular = quality.singular_vertices;
  r.min = quality.scaled_jacobian_stats.min;
  r.avg = quality.scaled_jacobian_stats.mean;
  const Vec3 up(0, 0, 1);
  double total = 0;
  for (const auto& q : out.quads) {
    std::array<Vec3, 4> c;
    for (int j = 0; j < 4; ++j) c[j] = mesh.points[q[j]];
    EXPECT_GT(quad_scaled_jacobian(c, &up), 0) << "inverted quad";
    total += 0.5 * twice_area(out.points[q[0]], out.points[q[1]], out.points[q[2]], out.points[q[3]]);
  }
  const double a = area(poly);
  EXPECT_NEAR(total, a, 1e-9 * std::abs(a)) << "quads do not tile the part";
  // Conformity: an edge between consecutive loop points is in exactly one quad, any
  // other edge in exactly two.
  const EdgeAdjacency edges = build_edges(mesh);
  std::size_t boundary_edges = 0;
  for (std::size_t e = 0; e < edges.edges.size(); ++e) {
    const auto [a0, a1] = edges.edges[e];
    const bool on_boundary = a1 < n && (a1 == a0 + 1 || (a0 == 0 && a1 == n - 1));
    boundary_edges += on_boundary ? 1 : 0;
    EXPECT_EQ(edges.edge_elements.row(e).size(), on_boundary ? 1u : 2u) << "edge " << a0 << "-" << a1;
  }
  EXPECT_EQ(boundary_edges, n);
  return r;
}

TEST(MappedMesh, UnitSquareIsAPerfectGrid) {
  const Part part = rectangle(1, 1, 9, 9);  // 10 points per side
  const auto out = mapped_mesh(part.polygon, part.corners);
  ASSERT_TRUE(out.has_value());
  const Measured m = check_mesh(part, *out);
  EXPECT_EQ(m.singular, 0u);
  const Vec3 up(0, 0, 1);
  for (const auto& q : out->quads) {
    std::array<Vec3, 4> c;
    for (int j = 0; j < 4; ++j) c[j] = Vec3(out->points[q[j]].x(), out->points[q[j]].y(), 0);
    EXPECT_NEAR(quad_scaled_jacobian(c, &up), 1.0, 1e-12);
  }
  // The interior points are the lattice (i/9, j/9), row by row.
  for (std::size_t j = 1; j < 9; ++j)
    for (std::size_t i = 1; i < 9; ++i) {
      const Vec2& p = out->points[36 + (j - 1) * 8 + (i - 1)];
      EXPECT_NEAR(p.x(), static_cast<double>(i) / 9, 1e-13);
      EXPECT_NEAR(p.y(), static_cast<double>(j) / 9, 1e-13);
    }
}

TEST(MappedMesh, ASideSpikeTooSharpForTheThresholdGivesNoGrid) {
  // A side point of a 20 x 20 square pulled out: its interior angle is split between
  // two quads of the grid, each needing at least asin(0.6) = 36.9 degrees. A spike of
  // 22.6 degrees (the point 5 out) cannot reach 0.6 whatever the interior points; a
  // bump of 146 degrees (0.3 out) can.
  for (const double out : {5.0, 0.3}) {
    Part part = rectangle(20, 20, 20, 20);
    ASSERT_EQ(part.corners[0], 0u);
    part.polygon.points[10] = Vec2(10, -out);
    const auto grid = mapped_mesh(part.polygon, part.corners, {.min_scaled_jacobian = 0.6});
    if (out > 1) {
      EXPECT_FALSE(grid.has_value());
    } else {
      ASSERT_TRUE(grid.has_value());
      EXPECT_GE(check_mesh(part, *grid).min, 0.6);
    }
  }
}

TEST(MappedMesh, LoopStartAnywhere) {
  // The same wavy part with its loop starting in the middle of a side: the side that
  // crosses the loop's start is meshed like any other.
  const Part base = wavy(16, 12);
  const std::size_t n = base.polygon.points.size();
  for (const std::size_t shift : {std::size_t{5}, std::size_t{20}, n - 3}) {
    Part part;
    std::vector<Vec2> ring;
    for (std::size_t i = 0; i < n; ++i) ring.push_back(base.polygon.points[(i + shift) % n]);
    part.polygon.add_ring(ring);
    for (int c = 0; c < 4; ++c) part.corners[c] = (base.corners[c] + n - shift) % n;
    std::sort(part.corners.begin(), part.corners.end());
    const auto out = mapped_mesh(part.polygon, part.corners);
    ASSERT_TRUE(out.has_value()) << "shift " << shift;
    const Measured m = check_mesh(part, *out);
    EXPECT_GE(m.avg, 0.9) << "shift " << shift;
  }
}

TEST(MappedMesh, GradedRectangle) {
  // Bottom side graded (segments growing 10% each), top uniform: the lines between
  // them lean, the interior still valid.
  const Part part =
      four_sided({sample(line({0, 0}, {30, 0}), graded(30, 1.1)), sample(line({30, 0}, {30, 10}), uniform(10)),
                  sample(line({30, 10}, {0, 10}), uniform(30)), sample(line({0, 10}, {0, 0}), uniform(10))});
  const auto out = mapped_mesh(part.polygon, part.corners);
  ASSERT_TRUE(out.has_value());
  const Measured m = check_mesh(part, *out);
  std::printf("graded rectangle: min SJ %.4f, avg %.4f\n", m.min, m.avg);
  EXPECT_GE(m.min, 0.5);
}

TEST(MappedMesh, GradingCarriesIntoTheInterior) {
  // Both long sides graded alike: the interpolated grid has straight vertical lines
  // (uniform parameters would slant them), so every quad is a rectangle, and the
  // control functions keep it so (plain Winslow would even out the spacing inside).
  const Part part =
      four_sided({sample(line({0, 0}, {30, 0}), graded(30, 1.1)), sample(line({30, 0}, {30, 10}), uniform(10)),
                  sample(line({30, 10}, {0, 10}), graded(30, 1 / 1.1)), sample(line({0, 10}, {0, 0}), uniform(10))});
  const mapped::StructuredGrid grid = mapped::transfinite_grid(part.polygon, part.corners);
  EXPECT_NEAR(mapped::min_scaled_jacobian(grid), 1.0, 1e-12);
  const auto out = mapped_mesh(part.polygon, part.corners);
  ASSERT_TRUE(out.has_value());
  const Measured m = check_mesh(part, *out);
  EXPECT_GE(m.min, 0.99);
}

TEST(MappedMesh, SmoothingStopsWhenConverged) {
  // The square's interpolated grid already solves the Winslow equations: one sweep.
  const Part square = rectangle(1, 1, 9, 9);
  mapped::StructuredGrid grid = mapped::transfinite_grid(square.polygon, square.corners);
  EXPECT_EQ(mapped::winslow_smooth(grid, 1, 1e-11, true), mapped::Smoothing::Converged);
  // The annulus needs many sweeps; 5 are not enough, 5000 are.
  const Part annulus = quarter_annulus(10, 20);
  grid = mapped::transfinite_grid(annulus.polygon, annulus.corners);
  EXPECT_EQ(mapped::winslow_smooth(grid, 5, 1e-11, true), mapped::Smoothing::IterationLimit);
  EXPECT_EQ(mapped::winslow_smooth(grid, 5000, 1e-11, true), mapped::Smoothing::Converged);
  EXPECT_GE(mapped::min_scaled_jacobian(grid), 0.95);
  grid = mapped::transfinite_grid(annulus.polygon, annulus.corners);
  EXPECT_EQ(mapped::laplace_smooth(grid, 5000, 1e-11), mapped::Smoothing::Converged);
}

TEST(MappedMesh, WinslowSolvesTheInverseOfAHarmonicMap) {
  // xi = x and eta = x y are harmonic, so x = xi, y = eta / xi solves the Winslow
  // equations with a non-zero cross term (beta = -eta / xi^3): the converged grid
  // matches it up to the O(h^2) discretisation error, a wrong stencil by far more.
  const std::size_t m = 20;
  const auto exact = [&](std::size_t i, std::size_t j) {
    const double xi = 1 + static_cast<double>(i) / m, eta = static_cast<double>(j) / m;
    return Vec2(xi, eta / xi);
  };
  std::array<std::vector<Vec2>, 4> sides;
  for (std::size_t k = 0; k <= m; ++k) {
    sides[0].push_back(exact(k, 0));
    sides[1].push_back(exact(m, k));
    sides[2].push_back(exact(m - k, m));
    sides[3].push_back(exact(0, m - k));
  }
  const Part part = four_sided(sides);
  mapped::StructuredGrid grid = mapped::transfinite_grid(part.polygon, part.corners);
  ASSERT_EQ(mapped::winslow_smooth(grid, 20000, 1e-13, false), mapped::Smoothing::Converged);
  double error = 0;
  for (std::size_t j = 0; j <= m; ++j)
    for (std::size_t i = 0; i <= m; ++i) {
      const std::size_t k = grid.node(i, j);
      error = std::max(error, (Vec2(grid.x[k], grid.y[k]) - exact(i, j)).norm());
    }
  std::printf("Winslow vs exact: largest error %.3g\n", error);
  EXPECT_LT(error, 2e-4);
}

TEST(MappedMesh, QuarterAnnulus) {
  const Part part = quarter_annulus(10, 20);
  const auto out = mapped_mesh(part.polygon, part.corners);
  ASSERT_TRUE(out.has_value());
  const Measured m = check_mesh(part, *out);
  std::printf("quarter annulus: min SJ %.4f, avg %.4f\n", m.min, m.avg);
  EXPECT_GE(m.avg, 0.95);
  EXPECT_EQ(m.singular, 0u);
}

TEST(MappedMesh, WavySide) {
  const Part part = wavy(20, 20);
  const auto out = mapped_mesh(part.polygon, part.corners);
  ASSERT_TRUE(out.has_value());
  const Measured m = check_mesh(part, *out);
  std::printf("wavy side: min SJ %.4f, avg %.4f\n", m.min, m.avg);
  EXPECT_GE(m.avg, 0.9);
}

TEST(MappedMesh, SixtyDegreeParallelogramAndTrapezoid) {
  const double s = std::sin(std::numbers::pi / 3), c = std::cos(std::numbers::pi / 3);
  {
    // An affine image of the square grid: every quad has the corner angles 60° and 120°.
    const Vec2 a(0, 0), b(2, 0), d(c, s), e = b + d;
    const Part part = four_sided({sample(line(a, b), uniform(12)), sample(line(b, e), uniform(8)),
                                  sample(line(e, d), uniform(12)), sample(line(d, a), uniform(8))});
    const auto out = mapped_mesh(part.polygon, part.corners);
    ASSERT_TRUE(out.has_value());
    const Measured m = check_mesh(part, *out);
    std::printf("parallelogram: min SJ %.6f, avg %.6f\n", m.min, m.avg);
    EXPECT_NEAR(m.min, s, 1e-9);
    EXPECT_NEAR(m.avg, s, 1e-9);
  }
  {
    // Base angles 60°: the corner quads have 60° and 120° corners, the others lie
    // between a 60° quad and a rectangle.
    const Vec2 a(0, 0), b(4, 0), e(4 - 2 * c, 2 * s), d(2 * c, 2 * s);
    const Part part = four_sided({sample(line(a, b), uniform(16)), sample(line(b, e), uniform(8)),
                                  sample(line(e, d), uniform(16)), sample(line(d, a), uniform(8))});
    const auto out = mapped_mesh(part.polygon, part.corners);
    ASSERT_TRUE(out.has_value());
    const Measured m = check_mesh(part, *out);
    std::printf("trapezoid: min SJ %.6f, avg %.6f\n", m.min, m.avg);
    EXPECT_NEAR(m.min, s, 0.03);
  }
}

TEST(MappedMesh, CShapeNeverInverted) {
  for (const double depth : {2.0, 2.5, 2.75}) {
    const Part part = c_shape(depth);
    // The interpolated grid folds here (that is what the test is about) ...
    const mapped::StructuredGrid grid = mapped::transfinite_grid(part.polygon, part.corners);
    EXPECT_LE(mapped::min_scaled_jacobian(grid), 0) << "depth " << depth;
    MappedMeshOptions raw;
    raw.smoothing_iterations = 0;
    EXPECT_FALSE(mapped_mesh(part.polygon, part.corners, raw).has_value()) << "depth " << depth;
    // ... and the smoothed one is either valid or refused.
    const auto out = mapped_mesh(part.polygon, part.corners);
    std::printf("C-shape depth %.2f: %s", depth, out ? "meshed" : "refused\n");
    if (out) {
      const Measured m = check_mesh(part, *out);
      std::printf(", min SJ %.4f, avg %.4f\n", m.min, m.avg);
      EXPECT_GE(m.min, MappedMeshOptions{}.min_scaled_jacobian) << "depth " << depth;
    }
  }
}

TEST(MappedMesh, ThresholdRefuses) {
  const Part part = quarter_annulus(10, 20);
  MappedMeshOptions strict;
  strict.min_scaled_jacobian = 0.999;
  EXPECT_FALSE(mapped_mesh(part.polygon, part.corners, strict).has_value());
  strict.min_scaled_jacobian = 0.5;
  EXPECT_TRUE(mapped_mesh(part.polygon, part.corners, strict).has_value());
}

TEST(MappedMesh, SingleQuadAndSingleRow) {
  const Part quad = rectangle(2, 1, 1, 1);
  const auto one = mapped_mesh(quad.polygon, quad.corners);
  ASSERT_TRUE(one.has_value());
  check_mesh(quad, *one);
  const Part row = rectangle(5, 1, 5, 1);
  const auto five = mapped_mesh(row.polygon, row.corners);
  ASSERT_TRUE(five.has_value());
  check_mesh(row, *five);
}

TEST(MappedMesh, InconsistentInputIsAnInputError) {
  const Part part = rectangle(3, 2, 6, 4);  // corners 0, 6, 10, 16; 20 points
  const Polygon2& p = part.polygon;
  EXPECT_NO_THROW(mapped_mesh(p, {0, 6, 10, 16}));
  EXPECT_THROW(mapped_mesh(p, {0, 6, 10, 15}), InputError);   // 6 vs 5 and 4 vs 5
  EXPECT_THROW(mapped_mesh(p, {0, 6, 10, 14}), InputError);   // 6 vs 4
  EXPECT_THROW(mapped_mesh(p, {6, 0, 10, 16}), InputError);   // unsorted
  EXPECT_THROW(mapped_mesh(p, {0, 6, 6, 16}), InputError);    // repeated
  EXPECT_THROW(mapped_mesh(p, {4, 10, 14, 20}), InputError);  // out of range
  Polygon2 holed = p;
  holed.add_ring(std::vector<Vec2>{{1, 0.5}, {1, 1.5}, {2, 1.5}, {2, 0.5}});
  EXPECT_THROW(mapped_mesh(holed, {0, 6, 10, 16}), InputError);
  Polygon2 clockwise;
  std::vector<Vec2> reversed(p.points.rbegin(), p.points.rend());
  clockwise.add_ring(reversed);
  EXPECT_THROW(mapped_mesh(clockwise, {3, 9, 13, 19}), InputError);
  EXPECT_THROW(mapped_mesh(Polygon2{}, {0, 1, 2, 3}), InputError);
  MappedMeshOptions negative;
  negative.smoothing_iterations = -1;
  EXPECT_THROW(mapped_mesh(p, {0, 6, 10, 16}, negative), InputError);
}

TEST(MappedMesh, Deterministic) {
  const Part part = wavy(30, 20);
  const auto first = mapped_mesh(part.polygon, part.corners);
  const auto second = mapped_mesh(part.polygon, part.corners);
  ASSERT_TRUE(first.has_value() && second.has_value());
  ASSERT_EQ(first->points.size(), second->points.size());
  for (std::size_t i = 0; i < first->points.size(); ++i) {
    EXPECT_EQ(first->points[i].x(), second->points[i].x());
    EXPECT_EQ(first->points[i].y(), second->points[i].y());
  }
  EXPECT_EQ(first->quads, second->quads);
}

TEST(MappedMesh, LargeGridTime) {
  for (const std::size_t size : {std::size_t{200}, std::size_t{400}}) {
    const Part part = quarter_annulus(size, size);
    const auto start = std::chrono::steady_clock::now();
    const auto out = mapped_mesh(part.polygon, part.corners);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(out.has_value());
    std::printf("%zu x %zu quarter annulus: %zu quads in %.3f s\n", size, size, out->quads.size(), seconds);
  }
}

}  // namespace
}  // namespace structmesh
