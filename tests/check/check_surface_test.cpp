// check_surface() on small hand-made surfaces whose answers are known by construction.
#include "structmesh/check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace structmesh {
namespace {

// The boundary of the tet (0,0,0) (1,0,0) (0,1,0) (0,0,1), normals outward, volume 1/6.
MeshBundle tetra_surface(const Vec3& offset = Vec3::Zero(), double scale = 1.0) {
  MeshBundle mesh;
  mesh.points = {offset, offset + scale * Vec3(1, 0, 0), offset + scale * Vec3(0, 1, 0),
                 offset + scale * Vec3(0, 0, 1)};
  for (const auto& f : kTetFaces) mesh.triangles.push_back({Index(f[0]), Index(f[1]), Index(f[2])});
  return mesh;
}

// Appends `other` to `mesh` as a separate set of vertices and faces.
void append(MeshBundle& mesh, const MeshBundle& other) {
  const Index base = Index(mesh.points.size());
  mesh.points.insert(mesh.points.end(), other.points.begin(), other.points.end());
  for (auto t : other.triangles) mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

// A torus (R = 2, r = 0.5) from an nu x nv grid with wrap-around, normals outward.
MeshBundle torus(int nu, int nv, bool quads) {
  MeshBundle mesh;
  const double pi = std::numbers::pi;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
      mesh.points.emplace_back((2 + 0.5 * std::cos(v)) * std::cos(u), (2 + 0.5 * std::cos(v)) * std::sin(u),
                               0.5 * std::sin(v));
    }
  }
  auto id = [&](int i, int j) { return Index(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      // (u, v) is a right-handed frame seen from outside: u-then-v corners run counter-clockwise.
      const Index a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (quads) {
        mesh.quads.push_back({a, b, c, d});
      } else {
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      }
    }
  }
  return mesh;
}

std::size_t count_kind(const SurfaceReport& report, const std::string& kind) {
  return std::size_t(
      std::count_if(report.problems.begin(), report.problems.end(), [&](const Problem& p) { return p.kind == kind; }));
}

const Problem* find_kind(const SurfaceReport& report, const std::string& kind) {
  for (const Problem& p : report.problems)
    if (p.kind == kind) return &p;
  return nullptr;
}

TEST(CheckSurface, TetrahedronIsAValidSolidBoundary) {
  const SurfaceReport r = check_surface(tetra_surface());
  EXPECT_EQ(r.vertices, 4u);
  EXPECT_EQ(r.faces, 4u);
  EXPECT_EQ(r.edges, 6u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.components, 1u);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.edge_manifold);
  EXPECT_TRUE(r.oriented);
  EXPECT_NEAR(r.signed_volume, 1.0 / 6.0, 1e-15);
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_EQ(r.adjacent_overlaps, 0u);
  EXPECT_TRUE(r.valid_solid_boundary);
  EXPECT_TRUE(r.problems.empty()) << r.problems.front().message;
}

TEST(CheckSurface, FlippedFaceIsNamed) {
  MeshBundle mesh = tetra_surface();
  std::swap(mesh.triangles[2][1], mesh.triangles[2][2]);
  mesh.lines.triangle_lines = {10, 11, 12, 13};
  const SurfaceReport r = check_surface(mesh);
  EXPECT_TRUE(r.closed);
  EXPECT_FALSE(r.oriented);
  EXPECT_EQ(r.inconsistent_edges, 3u);
  EXPECT_EQ(r.flipped_faces, 1u);
  EXPECT_EQ(r.genus, -1);
  EXPECT_FALSE(r.valid_solid_boundary);
  const Problem* flipped = find_kind(r, "flipped-face");
  ASSERT_NE(flipped, nullptr);
  EXPECT_EQ(flipped->element, 2);
  EXPECT_EQ(flipped->line, 12u);
  EXPECT_NE(flipped->message.find("face 2"), std::string::npos) << flipped->message;
  EXPECT_EQ(count_kind(r, "flipped-face"), 1u);
  EXPECT_EQ(count_kind(r, "inconsistent-edge"), 3u);
}

TEST(CheckSurface, InwardSurfaceHasNegativeVolume) {
  MeshBundle mesh = tetra_surface();
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  const SurfaceReport r = check_surface(mesh);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.genus, 0);
  EXPECT_NEAR(r.signed_volume, -1.0 / 6.0, 1e-15);
  EXPECT_FALSE(r.valid_solid_boundary);
  EXPECT_EQ(count_kind(r, "negative-volume"), 1u);
}

TEST(CheckSurface, MissingFaceLeavesThreeBoundaryEdges) {
  MeshBundle mesh = tetra_surface();
  mesh.triangles.pop_back();
  const SurfaceReport r = check_surface(mesh);
  EXPECT_FALSE(r.closed);
  EXPECT_TRUE(r.edge_manifold);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.boundary_edges, 3u);
  EXPECT_EQ(r.non_manifold_vertices, 0u);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.genus, -1);
  EXPECT_FALSE(r.valid_solid_boundary);
  EXPECT_EQ(count_kind(r, "open-edge"), 3u);
}

TEST(CheckSurface, SolidBoundaryProblemsNameEachKindAndTheFirstProblem) {
  EXPECT_EQ(solid_boundary_problems(check_surface(tetra_surface())), "");
  MeshBundle open = tetra_surface();
  open.triangles.pop_back();
  const SurfaceReport r = check_surface(open);
  const std::string what = solid_boundary_problems(r);
  EXPECT_EQ(what.rfind(" open (3 boundary edges); first problem: ", 0), 0u) << what;
  EXPECT_NE(what.find(r.problems.front().message), std::string::npos) << what;
  MeshBundle inward = tetra_surface();
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  EXPECT_NE(solid_boundary_problems(check_surface(inward)).find(" oriented inward (negative volume);"),
            std::string::npos);
}

TEST(CheckSurface, TwoTetrahedraSharingAnEdge) {
  // Tet A in the positive octant, tet B below it: they share the edge 0-1 only.
  MeshBundle mesh = tetra_surface();
  mesh.points.emplace_back(0, -1, 0);        // 4
  mesh.points.emplace_back(0, 0, -1);        // 5
  const std::array<Index, 4> b{0, 1, 4, 5};  // positive orientation
  for (const auto& f : kTetFaces) mesh.triangles.push_back({b[f[0]], b[f[1]], b[f[2]]});
  const SurfaceReport r = check_surface(mesh);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_FALSE(r.closed);
  EXPECT_FALSE(r.edge_manifold);
  // The fans at both ends of the edge join only through the non-manifold edge.
  EXPECT_EQ(r.non_manifold_vertices, 2u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_GT(r.signed_volume, 0);
  EXPECT_FALSE(r.valid_solid_boundary);
  const Problem* edge = find_kind(r, "non-manifold-edge");
  ASSERT_NE(edge, nullptr);
  EXPECT_NE(edge->message.find("edge 0-1"), std::string::npos) << edge->message;
}

TEST(CheckSurface, TwoTetrahedraSharingAVertex) {
  MeshBundle mesh = tetra_surface();
  mesh.points.emplace_back(-1, 0, 0);        // 4
  mesh.points.emplace_back(0, -1, 0);        // 5
  mesh.points.emplace_back(0, 0, -1);        // 6
  const std::array<Index, 4> b{0, 5, 4, 6};  // the mirror image of tet A, re-oriented
  for (const auto& f : kTetFaces) mesh.triangles.push_back({b[f[0]], b[f[1]], b[f[2]]});
  const SurfaceReport r = check_surface(mesh);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.edge_manifold);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_EQ(r.euler_characteristic, 3);
  EXPECT_EQ(r.genus, -1);
  EXPECT_NEAR(r.signed_volume, 2.0 / 6.0, 1e-15);
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_FALSE(r.valid_solid_boundary);
  const Problem* vertex = find_kind(r, "non-manifold-vertex");
  ASSERT_NE(vertex, nullptr);
  EXPECT_NE(vertex->message.find("vertex 0"), std::string::npos) << vertex->message;
}

TEST(CheckSurface, BowtieOfTwoTriangles) {
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 3, 4}};
  const SurfaceReport r = check_surface(mesh);
  EXPECT_EQ(r.boundary_edges, 6u);
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.adjacent_overlaps, 0u);
}

TEST(CheckSurface, TorusHasGenusOne) {
  for (bool quads : {false, true}) {
    const SurfaceReport r = check_surface(torus(24, 12, quads));
    SCOPED_TRACE(quads ? "quads" : "triangles");
    EXPECT_EQ(r.vertices, 24u * 12u);
    EXPECT_EQ(r.faces, quads ? 24u * 12u : 2u * 24u * 12u);
    EXPECT_TRUE(r.closed);
    EXPECT_TRUE(r.oriented);
    EXPECT_EQ(r.euler_characteristic, 0);
    EXPECT_EQ(r.genus, 1);
    EXPECT_EQ(r.components, 1u);
    // Inscribed polyhedron: a little below the smooth torus' 2 pi^2 R r^2.
    const double smooth = 2 * std::numbers::pi * std::numbers::pi * 2 * 0.25;
    EXPECT_GT(r.signed_volume, 0.9 * smooth);
    EXPECT_LT(r.signed_volume, smooth);
    EXPECT_EQ(r.degenerate_faces, 0u);
    EXPECT_EQ(r.self_intersections, 0u);
    EXPECT_EQ(r.adjacent_overlaps, 0u);
    EXPECT_TRUE(r.valid_solid_boundary);
  }
}

TEST(CheckSurface, TwoToriAddTheirGenera) {
  MeshBundle mesh = torus(16, 8, false);
  MeshBundle other = torus(16, 8, false);
  for (Vec3& p : other.points) p.x() += 10;
  append(mesh, other);
  const SurfaceReport r = check_surface(mesh);
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.genus, 2);
  EXPECT_TRUE(r.valid_solid_boundary);
}

TEST(CheckSurface, IntersectingTetrahedra) {
  MeshBundle mesh = tetra_surface();
  append(mesh, tetra_surface(Vec3(0.2, 0.2, 0.2)));
  const SurfaceReport r = check_surface(mesh);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.genus, 0);
  EXPECT_GT(r.self_intersections, 0u);
  EXPECT_FALSE(r.valid_solid_boundary);
  const Problem* hit = find_kind(r, "self-intersection");
  ASSERT_NE(hit, nullptr);
  EXPECT_LT(hit->element, 4);  // the first face of a pair is one of tet A's
}

TEST(CheckSurface, CountsEachIntersectingPairOnce) {
  // Triangle 1 pierces triangle 0; triangle 2 is far away; triangle 3 shares a
  // vertex with triangle 0 and crosses it too, but shared-vertex pairs are skipped.
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {2, 0, 0},  {0, 2, 0},  {0.5, 0.5, -1}, {0.5, 0.5, 1}, {1, 1, -1},
                 {9, 9, 9}, {9, 10, 9}, {10, 9, 9}, {0.3, 0.3, 1},  {1.2, 0.8, -1}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {0, 9, 10}};
  const SurfaceReport r = check_surface(mesh);
  EXPECT_EQ(r.self_intersections, 1u);
  EXPECT_EQ(r.adjacent_overlaps, 1u);  // triangle 3 passes through triangle 0 beyond their shared vertex
  const Problem* hit = find_kind(r, "self-intersection");
  ASSERT_NE(hit, nullptr);
  EXPECT_NE(hit->message.find("face 0 and face 1"), std::string::npos) << hit->message;
}

TEST(CheckSurface, TouchingTrianglesIntersect) {
  // Exact predicates: a vertex lying exactly on another triangle is an intersection.
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, 0}, {0.5, 0.5, 1}, {1, 0.5, 1}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  EXPECT_EQ(check_surface(mesh).self_intersections, 1u);
  mesh.points[3].z() = 1e-300;  // just above: no contact
  EXPECT_EQ(check_surface(mesh).self_intersections, 0u);
}

TEST(CheckSurface, FoldedAdjacentTrianglesOverlap) {
  // Two triangles on the edge 0-1, both on the same side of it in the same plane.
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {1, 0, 3}};
  const SurfaceReport r = check_surface(mesh);
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_EQ(r.adjacent_overlaps, 1u);
  EXPECT_EQ(count_kind(r, "adjacent-overlap"), 1u);
  mesh.points[3] = {1, -1, 0};  // unfolded: a flat square
  EXPECT_EQ(check_surface(mesh).adjacent_overlaps, 0u);
}

TEST(CheckSurface, DegenerateFaces) {
  // A face repeating an index is left out of the topology: the tet stays closed.
  MeshBundle mesh = tetra_surface();
  mesh.triangles.push_back({0, 0, 1});
  SurfaceReport r = check_surface(mesh);
  EXPECT_EQ(r.degenerate_faces, 1u);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_FALSE(r.valid_solid_boundary);
  const Problem* bad = find_kind(r, "degenerate-face");
  ASSERT_NE(bad, nullptr);
  EXPECT_EQ(bad->element, 4);

  // Zero area with distinct indices: three collinear points, far from the tet.
  mesh = tetra_surface();
  mesh.points.insert(mesh.points.end(), {Vec3(5, 5, 5), Vec3(6, 6, 6), Vec3(7, 7, 7)});
  mesh.triangles.push_back({4, 5, 6});
  r = check_surface(mesh);
  EXPECT_EQ(r.degenerate_faces, 1u);
  EXPECT_EQ(r.boundary_edges, 3u);
  EXPECT_FALSE(r.valid_solid_boundary);

  // A zero-area face is still tested for intersections (as a segment).
  mesh.points[4] = {0.1, 0.1, -1};
  mesh.points[5] = {0.1, 0.1, 0.5};
  mesh.points[6] = {0.1, 0.1, 2};
  EXPECT_EQ(check_surface(mesh).self_intersections, 2u);  // enters and leaves the tet
}

TEST(CheckSurface, IsolatedVertexIsCounted) {
  MeshBundle mesh = tetra_surface();
  mesh.points.emplace_back(3, 3, 3);
  const SurfaceReport r = check_surface(mesh);
  EXPECT_EQ(r.vertices, 4u);
  EXPECT_EQ(r.isolated_vertices, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_TRUE(r.valid_solid_boundary);  // a stray point does not spoil the surface
  EXPECT_EQ(count_kind(r, "isolated-vertex"), 1u);
}

TEST(CheckSurface, ProblemsAreCappedButCountsAreNot) {
  MeshBundle mesh;
  for (int i = 0; i < 10; ++i) {
    const Index b = Index(mesh.points.size());
    mesh.points.insert(mesh.points.end(), {Vec3(3.0 * i, 0, 0), Vec3(3.0 * i + 1, 0, 0), Vec3(3.0 * i, 1, 0)});
    mesh.triangles.push_back({b, b + 1, b + 2});
  }
  CheckOptions options;
  options.max_problems_per_kind = 4;
  const SurfaceReport r = check_surface(mesh, options);
  EXPECT_EQ(r.boundary_edges, 30u);
  EXPECT_EQ(r.components, 10u);
  EXPECT_EQ(count_kind(r, "open-edge"), 4u);
}

TEST(CheckSurface, OutOfRangeIndexStopsTheCheck) {
  MeshBundle mesh = tetra_surface();
  mesh.triangles.push_back({0, 1, 99});
  const SurfaceReport r = check_surface(mesh);
  EXPECT_FALSE(r.valid_solid_boundary);
  const Problem* bad = find_kind(r, "index-out-of-range");
  ASSERT_NE(bad, nullptr);
  EXPECT_EQ(bad->element, 4);
  EXPECT_NE(bad->message.find("99"), std::string::npos);
}

TEST(CheckSurface, NonFinitePointStopsTheCheck) {
  MeshBundle mesh = tetra_surface();
  mesh.points[2].y() = std::numeric_limits<double>::quiet_NaN();
  const SurfaceReport r = check_surface(mesh);
  EXPECT_FALSE(r.valid_solid_boundary);
  EXPECT_EQ(count_kind(r, "non-finite-point"), 1u);
}

TEST(CheckSurface, EmptyMeshIsNotValid) {
  const SurfaceReport r = check_surface(MeshBundle{});
  EXPECT_FALSE(r.valid_solid_boundary);
  EXPECT_EQ(count_kind(r, "no-faces"), 1u);
}

TEST(CheckSurface, SelfIntersectionTestCanBeSkipped) {
  MeshBundle mesh = tetra_surface();
  append(mesh, tetra_surface(Vec3(0.2, 0.2, 0.2)));
  CheckOptions options;
  options.self_intersections = false;
  const SurfaceReport r = check_surface(mesh, options);
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_TRUE(r.valid_solid_boundary);
}

TEST(CheckSurface, MoebiusStripIsNotOrientable) {
  // A strip of 8 quads (16 triangles) closed with a half twist.
  MeshBundle mesh;
  const int n = 8;
  const double pi = std::numbers::pi;
  for (int i = 0; i < n; ++i) {
    const double u = 2 * pi * i / n;
    for (double s : {-0.3, 0.3}) {
      const double w = s * std::cos(u / 2);
      mesh.points.emplace_back((1 + w) * std::cos(u), (1 + w) * std::sin(u), s * std::sin(u / 2));
    }
  }
  for (int i = 0; i < n; ++i) {
    Index a = Index(2 * i), b = Index(2 * i + 1);
    Index c = Index(2 * ((i + 1) % n)), d = Index(2 * ((i + 1) % n) + 1);
    if (i == n - 1) std::swap(c, d);  // the half twist
    mesh.triangles.push_back({a, c, d});
    mesh.triangles.push_back({a, d, b});
  }
  const SurfaceReport r = check_surface(mesh);
  EXPECT_FALSE(r.oriented);
  EXPECT_EQ(r.boundary_edges, 2u * n);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(count_kind(r, "non-orientable"), 1u);
}

}  // namespace
}  // namespace structmesh
