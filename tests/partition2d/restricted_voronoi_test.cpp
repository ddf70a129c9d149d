// Restricted Voronoi diagram (design/partition2d.md §2.2): the pieces tile the domain,
// the tessellation is conforming with shared vertices, every piece belongs to its
// nearest site, holes can cut a cell, and the output does not depend on the threads.
#include "partition2d/partition_internal.hpp"

#include "structmesh/regions.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>

namespace structmesh::partition2d {
namespace {

Polygon2 square_with_hole(double size, const Vec2& hole_low, const Vec2& hole_high) {
  Polygon2 region;
  region.add_ring(std::vector<Vec2>{{0, 0}, {size, 0}, {size, size}, {0, size}});
  region.add_ring(std::vector<Vec2>{hole_low, {hole_low.x(), hole_high.y()}, hole_high, {hole_high.x(), hole_low.y()}});
  return region;
}

std::vector<Vec2> random_sites(std::size_t count, double size, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> coordinate(0, size);
  std::vector<Vec2> sites(count);
  for (Vec2& s : sites) s = Vec2(coordinate(random), coordinate(random));
  return sites;
}

double perimeter(const Polygon2& region) {
  double total = 0;
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const auto ring = region.ring(r);
    for (std::size_t i = 0; i < ring.size(); ++i) total += (ring[(i + 1) % ring.size()] - ring[i]).norm();
  }
  return total;
}

Vec2 face_centroid(const Tessellation& t, Index f) {
  const Index begin = t.face_offsets[f], end = t.face_offsets[f + 1];
  const Vec2 origin = t.vertices[t.face_vertices[begin]];
  Vec2 moment = Vec2::Zero();
  double twice = 0;
  for (Index h = begin + 1; h + 1 < end; ++h) {
    const Vec2 a = t.vertices[t.face_vertices[h]] - origin, b = t.vertices[t.face_vertices[h + 1]] - origin;
    const double cross = a.x() * b.y() - a.y() * b.x();
    twice += cross;
    moment += cross * (a + b) / 3;
  }
  return origin + moment / twice;
}

// The properties every restricted Voronoi tessellation must have.
void expect_valid_rvd(const Polygon2& region, const DomainMesh& domain, const std::vector<Vec2>& sites,
                      const Tessellation& t) {
  ASSERT_EQ(t.cell_count, sites.size());
  ASSERT_EQ(t.face_offsets.size(), t.face_count() + 1);
  ASSERT_EQ(t.twin.size(), t.face_vertices.size());
  ASSERT_EQ(t.boundary_ring.size(), t.face_vertices.size());
  ASSERT_EQ(t.input_vertex.size(), t.vertices.size());
  // Tiles the domain: positive areas summing to the domain area.
  const std::vector<double> areas = face_areas(t);
  double total = 0;
  for (const double a : areas) {
    EXPECT_GT(a, 0);
    total += a;
  }
  EXPECT_NEAR(total / domain.area, 1.0, 1e-9);
  // Twins: an involution on interior half-edges with the same vertices reversed; the
  // half-edges without twin have the total length of the region boundary.
  double boundary_length = 0;
  for (Index f = 0; f < t.face_count(); ++f) {
    for (Index h = t.face_offsets[f]; h < t.face_offsets[f + 1]; ++h) {
      const Index a = t.face_vertices[h], b = t.face_vertices[t.next(h, f)];
      EXPECT_NE(a, b);
      const Index twin = t.twin[h];
      if (twin == kInvalidIndex) {
        boundary_length += (t.vertices[b] - t.vertices[a]).norm();
        continue;
      }
      ASSERT_LT(twin, t.face_vertices.size());
      EXPECT_EQ(t.twin[twin], h);
      const Index g = static_cast<Index>(std::upper_bound(t.face_offsets.begin(), t.face_offsets.end(), twin) -
                                         t.face_offsets.begin() - 1);
      EXPECT_EQ(t.face_vertices[twin], b);
      EXPECT_EQ(t.face_vertices[t.next(twin, g)], a);
    }
  }
  EXPECT_NEAR(boundary_length / perimeter(region), 1.0, 1e-9);
  // Shared vertices: one id per point (bit-identical coordinates would mean a vertex
  // computed twice under different ids).
  std::map<std::pair<double, double>, Index> seen;
  for (Index v = 0; v < t.vertices.size(); ++v) {
    EXPECT_TRUE(seen.emplace(std::make_pair(t.vertices[v].x(), t.vertices[v].y()), v).second) << "vertex " << v;
  }
  // Input vertices: the region's points by index.
  for (Index v = 0; v < t.vertices.size(); ++v) {
    if (t.input_vertex[v] >= 0) {
      EXPECT_EQ(t.vertices[v], domain.points[static_cast<std::size_t>(t.input_vertex[v])]);
    }
  }
  // Each face is in its site's Voronoi cell (3.11): its centroid is nearest that site.
  for (Index f = 0; f < t.face_count(); ++f) {
    const Vec2 c = face_centroid(t, f);
    const double own = (c - sites[t.face_cell[f]]).norm();
    for (const Vec2& s : sites) EXPECT_LE(own, (c - s).norm() + 1e-9);
  }
}

TEST(RestrictedVoronoi, TilesSquareWithHole) {
  const Polygon2 region = square_with_hole(4, {1.2, 1.1}, {2.3, 2.6});
  for (const double spacing : {0.0, 0.37}) {
    const DomainMesh domain = build_domain_mesh(region, Frame{}, spacing);
    const std::vector<Vec2> sites = random_sites(40, 4, 7);
    const Tessellation t = restricted_voronoi(domain, sites);
    expect_valid_rvd(region, domain, sites, t);
    EXPECT_GT(t.face_count(), sites.size());
  }
}

TEST(RestrictedVoronoi, ExactGridAndTiesStillTile) {
  // Sites on an exact grid (four co-circular sites at every Voronoi vertex), Voronoi
  // vertices on CDT vertices (spacing 0.5), on CDT edges (the diagonals without
  // Steiner points) or inside triangles, and a site on a domain vertex: the tie
  // rules keep the tiling conforming with one vertex per point.
  Polygon2 region;
  region.add_ring(std::vector<Vec2>{{0, 0}, {3, 0}, {3, 3}, {0, 3}});
  for (const double spacing : {0.0, 0.5, 0.7}) {
    const DomainMesh domain = build_domain_mesh(region, Frame{}, spacing);
    std::vector<Vec2> sites;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) sites.emplace_back(0.5 + i, 0.5 + j);
    }
    sites.emplace_back(0, 0);
    const Tessellation t = restricted_voronoi(domain, sites);
    expect_valid_rvd(region, domain, sites, t);
    // Each of the four degree-4 Voronoi vertices is one vertex of the tessellation.
    for (const Vec2& corner : {Vec2(1, 1), Vec2(1, 2), Vec2(2, 1), Vec2(2, 2)}) {
      EXPECT_EQ(std::count(t.vertices.begin(), t.vertices.end(), corner), 1) << spacing;
    }
  }
}

TEST(RestrictedVoronoi, HoleCutsCellInTwo) {
  const Polygon2 region = square_with_hole(10, {1, 4}, {9, 6});
  const DomainMesh domain = build_domain_mesh(region, Frame{}, 0);
  // Site 0 sits in the hole; its cell [2.6, 7.4] x [2.75, 7.25] straddles the hole.
  const std::vector<Vec2> sites{{5, 5}, {5, 9.5}, {5, 0.5}, {0.2, 5}, {9.8, 5}};
  const Tessellation t = restricted_voronoi(domain, sites);
  expect_valid_rvd(region, domain, sites, t);
  std::vector<Index> parent(t.face_count());
  for (Index f = 0; f < parent.size(); ++f) parent[f] = f;
  const auto root = [&](Index x) {
    while (parent[x] != x) x = parent[x];
    return x;
  };
  double area0 = 0;
  const std::vector<double> areas = face_areas(t);
  for (Index f = 0; f < t.face_count(); ++f) {
    if (t.face_cell[f] != 0) continue;
    area0 += areas[f];
    for (Index h = t.face_offsets[f]; h < t.face_offsets[f + 1]; ++h) {
      if (t.twin[h] == kInvalidIndex) continue;
      const Index g = static_cast<Index>(std::upper_bound(t.face_offsets.begin(), t.face_offsets.end(), t.twin[h]) -
                                         t.face_offsets.begin() - 1);
      if (t.face_cell[g] == 0) parent[root(f)] = root(g);
    }
  }
  std::size_t components = 0;
  for (Index f = 0; f < t.face_count(); ++f) components += t.face_cell[f] == 0 && root(f) == f ? 1 : 0;
  EXPECT_EQ(components, 2u);
  EXPECT_NEAR(area0, 4.8 * (7.25 - 2.75 - 2), 1e-12);
}

TEST(RestrictedVoronoi, SiteOutsideDomainHasNoFaces) {
  Polygon2 region;
  region.add_ring(std::vector<Vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  const DomainMesh domain = build_domain_mesh(region, Frame{}, 0);
  const std::vector<Vec2> sites{{0.25, 0.25}, {0.75, 0.25}, {0.5, 0.8}, {10, 10}, {0.25, 0.25}, {0.75, 0.25}};
  const Tessellation t = restricted_voronoi(domain, sites);
  expect_valid_rvd(region, domain, sites, t);
  for (Index f = 0; f < t.face_count(); ++f) {
    EXPECT_LT(t.face_cell[f], 3u);  // duplicate sites 4 and 5: the lower index owns the cell
  }
  std::size_t empty = 0;
  lp_energy(domain, sites, 8, nullptr, &empty);
  EXPECT_EQ(empty, 3u);
}

TEST(RestrictedVoronoi, KeyRegionAfterOptimisation) {
  // Real data: the built-in key region in the normalised frame of 150 cells, sites
  // after a few L-BFGS iterations (close to a converged, near-grid L_8-CVT).
  const Polygon2 key = make_key_region(1500);
  Frame frame;
  const BoundingBox2 box = key.bounding_box();
  frame.center = 0.5 * (box.min + box.max);
  frame.scale = std::sqrt(area(key) / 150.0);
  const DomainMesh domain = build_domain_mesh(key, frame, 0.5 * frame.scale);
  LpCvtOptions options;
  options.max_iterations = 15;
  const LpCvtResult result = optimise_lp_cvt(domain, initial_grid_sites(domain, 150, 0), options);
  EXPECT_LT(result.energy_final, result.energy_initial);
  EXPECT_EQ(result.empty_cells, 0u);
  const Tessellation t = restricted_voronoi(domain, result.sites);
  Polygon2 normalised = key;
  for (Vec2& q : normalised.points) q = frame.to_normalised(q);
  expect_valid_rvd(normalised, domain, result.sites, t);
  for (Index v = 0; v < t.vertices.size(); ++v) {
    if (t.input_vertex[v] >= 0) {
      EXPECT_LT(static_cast<std::size_t>(t.input_vertex[v]), key.points.size());
    }
  }
}

TEST(RestrictedVoronoi, FewAndCollinearSites) {
  // One-dimensional Delaunay triangulations (collinear sites) and a single site.
  Polygon2 region;
  region.add_ring(std::vector<Vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  const DomainMesh domain = build_domain_mesh(region, Frame{}, 0.3);
  for (const std::vector<Vec2>& sites : {std::vector<Vec2>{{0.2, 0.5}, {0.5, 0.5}, {0.8, 0.5}},
                                         std::vector<Vec2>{{0.2, 0.5}, {0.7, 0.6}}, std::vector<Vec2>{{0.2, 0.5}}}) {
    const Tessellation t = restricted_voronoi(domain, sites);
    expect_valid_rvd(region, domain, sites, t);
    std::size_t empty = 1;
    lp_energy(domain, sites, 8, nullptr, &empty);
    EXPECT_EQ(empty, 0u);
  }
}

TEST(RestrictedVoronoi, DeterministicAndThreadCountIndependent) {
  const Polygon2 region = square_with_hole(20, {5, 4}, {11, 13});
  const DomainMesh domain = build_domain_mesh(region, Frame{}, 0.25);
  ASSERT_GT(domain.triangles.size(), 4000u);  // several blocks of 1024 triangles
  const std::vector<Vec2> sites = random_sites(300, 20, 3);
  const auto run = [&](int threads) {
    tbb::global_control control(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    std::vector<double> gradient;
    std::size_t empty = 0;
    const double energy = lp_energy(domain, sites, 8, &gradient, &empty);
    return std::make_tuple(restricted_voronoi(domain, sites), energy, gradient);
  };
  const auto [t1, e1, g1] = run(1);
  const auto [t2, e2, g2] = run(2);
  expect_valid_rvd(region, domain, sites, t1);
  EXPECT_EQ(t1.vertices, t2.vertices);
  EXPECT_EQ(t1.face_offsets, t2.face_offsets);
  EXPECT_EQ(t1.face_vertices, t2.face_vertices);
  EXPECT_EQ(t1.face_cell, t2.face_cell);
  EXPECT_EQ(t1.twin, t2.twin);
  EXPECT_EQ(t1.input_vertex, t2.input_vertex);
  EXPECT_EQ(e1, e2);
  EXPECT_EQ(g1, g2);
}

}  // namespace
}  // namespace structmesh::partition2d
