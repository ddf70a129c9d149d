// The partitioning domain: lon/lat projection, the proxy region for the CVT
// optimisation, and the flat constrained Delaunay triangulation in the normalised
// frame (design/partition2d.md §2.0, §2.1, §2.4).
#include "partition2d/partition_internal.hpp"

#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/triangulate.hpp"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace structmesh::partition2d {

namespace {

constexpr double kEarthRadius = 6371008.8;  // mean radius (IUGG), metres
constexpr double kDegree = std::numbers::pi / 180.0;

}  // namespace

// Forward and inverse LAEA, spherical form (Snyder, Map Projections, eq. 24-2..24-4
// and 20-14..20-18), as restated in design §2.0.
Vec2 Projection::forward(const Vec2& lonlat) const {
  const double phi0 = lat0 * kDegree, lambda0 = lon0 * kDegree;
  const double phi = lonlat.y() * kDegree, dlambda = lonlat.x() * kDegree - lambda0;
  const double k =
      std::sqrt(2.0 / (1.0 + std::sin(phi0) * std::sin(phi) + std::cos(phi0) * std::cos(phi) * std::cos(dlambda)));
  return {kEarthRadius * k * std::cos(phi) * std::sin(dlambda),
          kEarthRadius * k * (std::cos(phi0) * std::sin(phi) - std::sin(phi0) * std::cos(phi) * std::cos(dlambda))};
}

Vec2 Projection::inverse(const Vec2& xy) const {
  const double phi0 = lat0 * kDegree;
  const double rho = xy.norm();
  if (rho == 0) return {lon0, lat0};
  const double c = 2.0 * std::asin(std::min(1.0, rho / (2.0 * kEarthRadius)));
  const double phi = std::asin(std::cos(c) * std::sin(phi0) + xy.y() * std::sin(c) * std::cos(phi0) / rho);
  const double lambda =
      std::atan2(xy.x() * std::sin(c), rho * std::cos(phi0) * std::cos(c) - xy.y() * std::sin(phi0) * std::sin(c));
  return {lon0 + lambda / kDegree, phi / kDegree};
}

std::string Projection::describe() const {
  if (!active) return "";
  char text[128];
  std::snprintf(text, sizeof text, "LAEA lat0=%.6f lon0=%.6f R=6371008.8 (metres)", lat0, lon0);
  return text;
}

Projection choose_projection(const Polygon2& region) {
  Projection projection;
  if (region.coordinates != Polygon2::Coordinates::LonLat) return projection;
  const BoundingBox2 box = region.bounding_box();
  projection.active = true;
  projection.lon0 = 0.5 * (box.min.x() + box.max.x());
  projection.lat0 = 0.5 * (box.min.y() + box.max.y());
  return projection;
}

Polygon2 project_region(const Polygon2& region, const Projection& projection) {
  if (!projection.active) return region;
  Polygon2 metric = region;
  metric.coordinates = Polygon2::Coordinates::Planar;
  tbb::parallel_for(std::size_t{0}, metric.points.size(),
                    [&](std::size_t i) { metric.points[i] = projection.forward(region.points[i]); });
  return metric;
}

DomainMesh build_domain_mesh(const Polygon2& metric_region, const Frame& frame, double steiner_spacing) {
  TriangulateOptions options;
  options.steiner_spacing = steiner_spacing;
  RegionTriangulation cdt = triangulate_region(metric_region, options);

  DomainMesh domain;
  domain.frame = frame;
  domain.input_point_count = metric_region.points.size();
  domain.points.resize(cdt.points.size());
  tbb::parallel_for(std::size_t{0}, cdt.points.size(),
                    [&](std::size_t i) { domain.points[i] = frame.to_normalised(cdt.points[i]); });
  domain.triangles = std::move(cdt.triangles);

  // Neighbours by sorting half-edges on their unordered vertex pair: the two
  // half-edges of an interior edge become adjacent; a boundary edge stays alone.
  struct HalfEdge {
    Index low, high, triangle, corner;
  };
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(3 * domain.triangles.size());
  for (Index t = 0; t < domain.triangles.size(); ++t) {
    const auto& tri = domain.triangles[t];
    for (Index k = 0; k < 3; ++k) {
      const Index a = tri[k], b = tri[(k + 1) % 3];
      half_edges.push_back({std::min(a, b), std::max(a, b), t, k});
    }
  }
  std::sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.low != y.low ? x.low < y.low : x.high != y.high ? x.high < y.high : x.triangle < y.triangle;
  });
  domain.neighbors.assign(domain.triangles.size(), {kInvalidIndex, kInvalidIndex, kInvalidIndex});
  for (std::size_t i = 0; i + 1 < half_edges.size(); ++i) {
    const HalfEdge &x = half_edges[i], &y = half_edges[i + 1];
    if (x.low == y.low && x.high == y.high) {
      domain.neighbors[x.triangle][x.corner] = y.triangle;
      domain.neighbors[y.triangle][y.corner] = x.triangle;
      ++i;
    }
  }
  double twice_area = 0;
  for (const auto& tri : domain.triangles) {
    const Vec2 a = domain.points[tri[1]] - domain.points[tri[0]];
    const Vec2 b = domain.points[tri[2]] - domain.points[tri[0]];
    twice_area += a.x() * b.y() - a.y() * b.x();
  }
  domain.area = 0.5 * twice_area;
  return domain;
}

namespace {

// Squared distance from p to segment ab.
double squared_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double length2 = d.squaredNorm();
  const double t = length2 > 0 ? std::clamp((p - a).dot(d) / length2, 0.0, 1.0) : 0.0;
  return (a + t * d - p).squaredNorm();
}

// Douglas-Peucker on a closed ring (iterative, no recursion depth limit at 10^6
// points): the ring is split at its first point and the point farthest from it,
// then each chain keeps the farthest point while it is above the tolerance.
std::vector<Vec2> simplify_ring(std::span<const Vec2> ring, double tolerance) {
  const std::size_t n = ring.size();
  std::size_t far = 0;
  double far_distance = -1;
  for (std::size_t i = 1; i < n; ++i) {
    const double d = (ring[i] - ring[0]).squaredNorm();
    if (d > far_distance) far_distance = d, far = i;
  }
  std::vector<std::uint8_t> keep(n, 0);
  keep[0] = keep[far] = 1;
  const double tolerance2 = tolerance * tolerance;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, far}, {far, n}};  // chains [a, b], b == n is point 0
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    const Vec2& pa = ring[a];
    const Vec2& pb = ring[b % n];
    double worst = -1;
    std::size_t worst_index = a;
    for (std::size_t i = a + 1; i < b; ++i) {
      const double d = squared_distance(ring[i], pa, pb);
      if (d > worst) worst = d, worst_index = i;
    }
    if (worst > tolerance2) {
      keep[worst_index] = 1;
      stack.emplace_back(a, worst_index);
      stack.emplace_back(worst_index, b);
    }
  }
  std::vector<Vec2> out;
  for (std::size_t i = 0; i < n; ++i) {
    if (keep[i]) out.push_back(ring[i]);
  }
  return out;
}

}  // namespace

Polygon2 proxy_region(const Polygon2& metric_region, double tolerance, double min_area) {
  // Halving the tolerance until the simplified rings neither cross nor touch: the
  // simplification is per ring, so two rings may come to overlap.
  for (int attempt = 0; attempt < 4; ++attempt, tolerance *= 0.25) {
    const std::size_t rings = metric_region.ring_count();
    std::vector<std::vector<Vec2>> simplified(rings);
    tbb::parallel_for(std::size_t{0}, rings,
                      [&](std::size_t r) { simplified[r] = simplify_ring(metric_region.ring(r), tolerance); });
    Polygon2 proxy;
    proxy.coordinates = metric_region.coordinates;
    for (std::size_t r = 0; r < rings; ++r) {
      if (simplified[r].size() < 3) continue;
      if (r > 0 && std::abs(signed_area(simplified[r])) < min_area) continue;
      if (r == 0 && simplified[r].size() < 3) return metric_region;
      proxy.add_ring(simplified[r]);
    }
    if (proxy.ring_count() == 0) return metric_region;
    if (proxy.points.size() == metric_region.points.size()) return metric_region;
    if (check_region({proxy}).valid) return proxy;
  }
  return metric_region;
}

}  // namespace structmesh::partition2d
