// pave(): validity (orientation, conformity, boundary kept bit-identical, area),
// quality and robustness on analytic shapes, random polygons and a partitioned region.
#include "structmesh/error.hpp"
#include "structmesh/partition2d.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/quality.hpp"
#include "structmesh/regions.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

namespace structmesh {
namespace {

struct Measured {
  double avg = 0, min = 1;
  std::size_t singular = 0, quads = 0;
};

Polygon2 ring_polygon(const std::vector<Vec2>& outer, const std::vector<std::vector<Vec2>>& holes = {}) {
  Polygon2 p;
  p.add_ring(outer);
  for (const auto& h : holes) p.add_ring(h);
  return p;
}

/// Every check of the contract; returns the quality figures.
Measured check_paved(const Polygon2& poly, const PavedPart& part) {
  Measured m;
  const std::size_t n = poly.points.size();
  EXPECT_GE(part.points.size(), n);
  for (std::size_t i = 0; i < n && i < part.points.size(); ++i) {
    EXPECT_EQ(part.points[i].x(), poly.points[i].x()) << "input point " << i << " moved";
    EXPECT_EQ(part.points[i].y(), poly.points[i].y()) << "input point " << i << " moved";
  }
  QuadMesh mesh;
  for (const Vec2& p : part.points) mesh.points.emplace_back(p.x(), p.y(), 0);
  mesh.quads = part.quads;
  const Vec3 up(0, 0, 1);
  double total = 0;
  for (const auto& q : part.quads) {
    for (const Index v : q) EXPECT_LT(v, part.points.size());
    std::array<Vec3, 4> c;
    for (int j = 0; j < 4; ++j) c[j] = mesh.points[q[j]];
    const double sj = quad_scaled_jacobian(c, &up);
    EXPECT_GT(sj, 0) << "inverted quad";
    m.min = std::min(m.min, sj);
    m.avg += sj;
    const auto& P = part.points;
    total +=
        0.5 * ((P[q[2]] - P[q[0]]).x() * (P[q[3]] - P[q[1]]).y() - (P[q[2]] - P[q[0]]).y() * (P[q[3]] - P[q[1]]).x());
  }
  m.quads = part.quads.size();
  if (m.quads > 0) m.avg /= static_cast<double>(m.quads);
  const double a = area(poly);
  EXPECT_NEAR(total, a, 1e-9 * std::abs(a)) << "quads do not tile the part";
  // Conformity: directed edges. An interior edge is used once in each direction; an
  // input boundary edge once, in the ring's direction; nothing else is unpaired.
  std::map<std::pair<Index, Index>, int> directed;
  for (const auto& q : part.quads)
    for (int j = 0; j < 4; ++j) ++directed[{q[j], q[(j + 1) % 4]}];
  std::map<std::pair<Index, Index>, int> boundary;
  for (std::size_t r = 0; r < poly.ring_count(); ++r) {
    const Index b = poly.ring_offsets[r], e = poly.ring_offsets[r + 1];
    for (Index i = b; i < e; ++i) boundary[{i, i + 1 == e ? b : i + 1}] = 1;
  }
  std::size_t bad = 0;
  for (const auto& [edge, count] : directed) {
    if (count != 1) ++bad;
    const bool paired = directed.count({edge.second, edge.first}) > 0;
    const bool on_boundary = boundary.count(edge) > 0;
    if (on_boundary == paired) ++bad;
  }
  for (const auto& [edge, one] : boundary)
    if (directed.count(edge) == 0) ++bad;
  EXPECT_EQ(bad, 0u) << "non-conforming edges";
  // Singular interior vertices.
  std::vector<int> valence(part.points.size(), 0);
  for (const auto& q : part.quads)
    for (const Index v : q) ++valence[v];
  for (std::size_t v = n; v < part.points.size(); ++v) {
    EXPECT_GT(valence[v], 0) << "unused point";
    if (valence[v] != 4) ++m.singular;
  }
  return m;
}

void report(const char* name, const Measured& m, const PavedPart& part) {
  std::printf(
      "[paving] %-22s quads %7zu  SJ avg %.4f min %.4f  singular %4zu  rows %zu seams %zu splits %zu "
      "templates %zu fallback %zu\n",
      name, m.quads, m.avg, m.min, m.singular, part.stats.rows, part.stats.seams, part.stats.splits,
      part.stats.templates, part.stats.fallback_loops);
}

std::vector<Vec2> rectangle(int nx, int ny, double h = 1.0) {
  std::vector<Vec2> r;
  for (int i = 0; i < nx; ++i) r.emplace_back(i * h, 0);
  for (int j = 0; j < ny; ++j) r.emplace_back(nx * h, j * h);
  for (int i = nx; i > 0; --i) r.emplace_back(i * h, ny * h);
  for (int j = ny; j > 0; --j) r.emplace_back(0, j * h);
  return r;
}

std::vector<Vec2> circle(int n, double radius, Vec2 c = {0, 0}, bool clockwise = false) {
  std::vector<Vec2> r;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n * (clockwise ? -1 : 1);
    r.emplace_back(c.x() + radius * std::cos(t), c.y() + radius * std::sin(t));
  }
  return r;
}

TEST(Paving, RectangleIsAPerfectGrid) {
  const Polygon2 poly = ring_polygon(rectangle(20, 12));
  const PavedPart part = pave(poly);
  const Measured m = check_paved(poly, part);
  report("rectangle 20x12", m, part);
  EXPECT_EQ(m.quads, 240u);
  EXPECT_NEAR(m.min, 1.0, 1e-12);
  EXPECT_EQ(m.singular, 0u);
}

TEST(Paving, Disk64) {
  const Polygon2 poly = ring_polygon(circle(64, 10));
  const PavedPart part = pave(poly);
  const Measured m = check_paved(poly, part);
  report("disk 64", m, part);
  EXPECT_GT(m.min, 0.5);
  EXPECT_GT(m.avg, 0.85);
}

}  // namespace
}  // namespace structmesh
