// VisibilityOracle (§2.2.1): analytic cases on unions of unit cubes, the grazing rule
// on a notch, and agreement with an exact CGAL brute force on non-convex solids.
#include "guard/shapes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <boost/variant/get.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <random>
#include <span>
#include <utility>
#include <vector>

namespace structmesh {
namespace {

using test::Cell;
using test::voxel_surface;

Index vertex_at(const TriMesh& mesh, const Vec3& p) {
  for (Index v = 0; v < mesh.points.size(); ++v)
    if (mesh.points[v] == p) return v;
  ADD_FAILURE() << "no vertex at " << p.transpose();
  return 0;
}

// A two-cell-thick L of unit cubes: arm A along x (3 cells), arm B along y (2 more),
// two layers in z. Its reflex edge x = y = 1 runs from z = 0 to 2 through the surface
// vertex (1, 1, 1).
TriMesh two_cell_thick_l() {
  std::vector<Cell> cells;
  for (int k = 0; k < 2; ++k) {
    for (int i = 0; i < 3; ++i) cells.push_back({i, 0, k});
    for (int j = 1; j < 3; ++j) cells.push_back({0, j, k});
  }
  return voxel_surface(cells);
}

TEST(Visibility, UnitCubeCentreSeesEverythingAndAnOutsidePointNothing) {
  const TriMesh cube = voxel_surface({{0, 0, 0}});
  ASSERT_EQ(cube.points.size(), 8u);
  ASSERT_EQ(cube.triangles.size(), 12u);
  const VisibilityOracle oracle(cube);
  for (const Vec3& p : {Vec3(0.5, 0.5, 0.5), Vec3(0.01, 0.02, 0.99), Vec3(0.999, 0.5, 0.3)})
    for (Index v = 0; v < 8; ++v) EXPECT_TRUE(oracle.sees(p, v)) << "from " << p.transpose() << " vertex " << v;
  const Vec3 centre(0.5, 0.5, 0.5);
  const CompressedRows faces = visible_faces(oracle, cube, std::span<const Vec3>(&centre, 1));
  ASSERT_EQ(faces.row_count(), 1u);
  EXPECT_EQ(faces.row(0).size(), 12u);

  // Just outside the +x face: the far vertices are behind that face, the near ones are
  // reached from outside the solid. Nothing is visible.
  for (const Vec3& p : {Vec3(1.001, 0.5, 0.5), Vec3(1.5, 0.5, 0.5), Vec3(-0.2, -0.3, 0.4), Vec3(3, 3, 3)})
    for (Index v = 0; v < 8; ++v) EXPECT_FALSE(oracle.sees(p, v)) << "from " << p.transpose() << " vertex " << v;
  const std::vector<Vec3> outside{{1.001, 0.5, 0.5}, {0.5, 0.5, -0.01}};
  const CompressedRows none = visible_faces(oracle, cube, outside);
  EXPECT_EQ(none.row(0).size() + none.row(1).size(), 0u);
}

TEST(Visibility, LShapeArmsHideEachOtherButTheCornerSeesBoth) {
  // Arm A along x (cells x = 0..4), arm B along y (cells y = 1..4), one cell thick.
  std::vector<Cell> cells;
  for (int i = 0; i < 5; ++i) cells.push_back({i, 0, 0});
  for (int j = 1; j < 5; ++j) cells.push_back({0, j, 0});
  const TriMesh mesh = voxel_surface(cells);
  const VisibilityOracle oracle(mesh);
  std::vector<Index> end_a, end_b;
  for (Index v = 0; v < mesh.points.size(); ++v) {
    if (mesh.points[v].x() == 5) end_a.push_back(v);
    if (mesh.points[v].y() == 5) end_b.push_back(v);
  }
  ASSERT_EQ(end_a.size(), 4u);
  ASSERT_EQ(end_b.size(), 4u);
  const Vec3 deep_a(4.5, 0.5, 0.5), deep_b(0.5, 4.5, 0.5), corner(0.5, 0.5, 0.5);
  for (const Index v : end_b) {
    EXPECT_FALSE(oracle.sees(deep_a, v)) << "vertex " << mesh.points[v].transpose();
    EXPECT_TRUE(oracle.sees(corner, v)) << "vertex " << mesh.points[v].transpose();
    EXPECT_TRUE(oracle.sees(deep_b, v)) << "vertex " << mesh.points[v].transpose();
  }
  for (const Index v : end_a) {
    EXPECT_FALSE(oracle.sees(deep_b, v)) << "vertex " << mesh.points[v].transpose();
    EXPECT_TRUE(oracle.sees(corner, v)) << "vertex " << mesh.points[v].transpose();
    EXPECT_TRUE(oracle.sees(deep_a, v)) << "vertex " << mesh.points[v].transpose();
  }
  // Faces: the corner cell's point sees the far ends' caps; deep in A sees none of B's cap.
  const std::vector<Vec3> candidates{deep_a, corner};
  const CompressedRows faces = visible_faces(oracle, mesh, candidates);
  std::size_t cap_b_from_a = 0, cap_b_from_corner = 0;
  for (int c = 0; c < 2; ++c)
    for (const Index f : faces.row(c)) {
      const auto& t = mesh.triangles[f];
      const bool cap_b = mesh.points[t[0]].y() == 5 && mesh.points[t[1]].y() == 5 && mesh.points[t[2]].y() == 5;
      if (cap_b) ++(c == 0 ? cap_b_from_a : cap_b_from_corner);
    }
  EXPECT_EQ(cap_b_from_a, 0u);
  EXPECT_EQ(cap_b_from_corner, 2u);
}

TEST(Visibility, GrazingSegmentsAreBlocked) {
  // A two-cell-thick L: the reflex edge x = y = 1 runs from z = 0 to 2 through the
  // surface vertex (1, 1, 1). The solid near it is {x < 1 or y < 1}.
  const TriMesh mesh = two_cell_thick_l();
  const VisibilityOracle oracle(mesh);
  const Index v = vertex_at(mesh, Vec3(0, 2, 0));
  ASSERT_EQ(mesh.points[vertex_at(mesh, Vec3(1, 1, 1))], Vec3(1, 1, 1));

  // Through the reflex vertex (1, 1, 1) at t = 1/3: touches the surface, blocked.
  EXPECT_FALSE(oracle.sees(Vec3(1.5, 0.5, 1.5), v));
  EXPECT_TRUE(oracle.segment_blocked(Vec3(1.5, 0.5, 1.5), v));
  // Through the inside of the reflex edge, at (1, 1, 5/6): blocked.
  EXPECT_FALSE(oracle.sees(Vec3(1.5, 0.5, 1.25), v));
  // Passing the edge on the inside (y = 0.93 at x = 1): visible; on the outside: blocked.
  EXPECT_TRUE(oracle.sees(Vec3(1.5, 0.4, 1.5), v));
  EXPECT_FALSE(oracle.sees(Vec3(1.5, 0.6, 1.5), v));

  // Along a face: from (0.5, 1, 0.5) to the far top corner (3, 1, 1) of arm A the
  // segment runs in the plane y = 1 over the face x in [1, 3]; blocked by the ray test
  // and by the test at the target (the direction lies in the plane of its faces).
  const Index far = vertex_at(mesh, Vec3(3, 1, 1));
  const Vec3 along(0.5, 1, 0.5);
  EXPECT_FALSE(oracle.sees(along, far));
  EXPECT_FALSE(oracle.enters_interior(far, along - mesh.points[far]));
  // Nudged into the solid it is visible.
  EXPECT_TRUE(oracle.sees(Vec3(0.5, 0.95, 0.5), far));

  // Through a face's diagonal (the edge between its two triangles), from outside the
  // cube to its far corner: never slips between the two triangles.
  const TriMesh cube = voxel_surface({{0, 0, 0}});
  const VisibilityOracle cube_oracle(cube);
  const Index origin = vertex_at(cube, Vec3(0, 0, 0));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> along_diagonal(0.01, 0.99), beyond(1.01, 3.0);
  std::size_t leaks = 0;
  for (int i = 0; i < 2000; ++i) {
    // The x = 1 face is split along (1, 0, 0)-(1, 1, 1): the segment crosses it at (1, t, t).
    const double t = along_diagonal(rng), l = beyond(rng);
    leaks += cube_oracle.segment_blocked(Vec3(l, l * t, l * t), origin) ? 0 : 1;
  }
  EXPECT_EQ(leaks, 0u);

  // The test at a vertex. Convex corner (0, 0, 0): only the open octant enters the
  // solid. Reflex vertex (1, 1, 1) on the reflex edge: three quarters of the space
  // (x < 1 or y < 1) do.
  const Index convex = vertex_at(mesh, Vec3(0, 0, 0));
  EXPECT_TRUE(oracle.enters_interior(convex, Vec3(1, 2, 3)));
  EXPECT_FALSE(oracle.enters_interior(convex, Vec3(1, 2, -3)));
  EXPECT_FALSE(oracle.enters_interior(convex, Vec3(1, 2, 0)));  // along the bottom face
  const Index reflex = vertex_at(mesh, Vec3(1, 1, 1));
  EXPECT_TRUE(oracle.enters_interior(reflex, Vec3(-1, 1, 0.3)));
  EXPECT_TRUE(oracle.enters_interior(reflex, Vec3(1, -1, -0.3)));
  EXPECT_TRUE(oracle.enters_interior(reflex, Vec3(-1, -1, 0.2)));
  EXPECT_FALSE(oracle.enters_interior(reflex, Vec3(1, 1, 0.2)));
  EXPECT_FALSE(oracle.enters_interior(reflex, Vec3(0, 1, 0.2)));   // along the face x = 1
  EXPECT_FALSE(oracle.enters_interior(reflex, Vec3(0, 0, 1)));     // along the reflex edge
  EXPECT_FALSE(oracle.enters_interior(reflex, Vec3(1, 1e-3, 0)));  // just outside
}

TEST(Visibility, RejectsSurfacesThatAreNotClosedOutwardSolids) {
  TriMesh cube = voxel_surface({{0, 0, 0}});
  TriMesh open = cube;
  open.triangles.pop_back();
  EXPECT_THROW(VisibilityOracle{open}, InputError);
  TriMesh inward = cube;
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  EXPECT_THROW(VisibilityOracle{inward}, InputError);
  TriMesh flipped_one = cube;
  std::swap(flipped_one.triangles[3][1], flipped_one.triangles[3][2]);
  EXPECT_THROW(VisibilityOracle{flipped_one}, InputError);
  EXPECT_THROW(VisibilityOracle{TriMesh{}}, InputError);
}

TEST(Visibility, MovedOracleKeepsWorking) {
  const TriMesh cube = voxel_surface({{0, 0, 0}});
  VisibilityOracle a(cube);
  VisibilityOracle b(std::move(a));
  EXPECT_TRUE(b.sees(Vec3(0.5, 0.5, 0.5), 0));
  VisibilityOracle c(voxel_surface({{0, 0, 0}, {1, 0, 0}}));
  c = std::move(b);
  EXPECT_EQ(c.face_count(), 12u);
  EXPECT_TRUE(c.sees(Vec3(0.5, 0.5, 0.5), 7));
}

// --- Exact brute force -------------------------------------------------------------

using K = CGAL::Exact_predicates_exact_constructions_kernel;

struct ExactSurface {
  std::vector<K::Point_3> points;
  std::vector<K::Triangle_3> triangles;
  const TriMesh* mesh = nullptr;

  explicit ExactSurface(const TriMesh& m) : mesh(&m) {
    for (const Vec3& p : m.points) points.emplace_back(p.x(), p.y(), p.z());
    for (const auto& t : m.triangles) triangles.emplace_back(points[t[0]], points[t[1]], points[t[2]]);
  }

  /// Crossings of the ray p + s dir (s > 0) with the surface, parity: inside iff odd.
  bool inside(const Vec3& p, const Vec3& dir) const {
    const K::Ray_3 ray(K::Point_3(p.x(), p.y(), p.z()), K::Vector_3(dir.x(), dir.y(), dir.z()));
    std::size_t hits = 0;
    for (const auto& t : triangles) hits += CGAL::do_intersect(ray, t) ? 1 : 0;
    return hits % 2 == 1;
  }

  /// §2.2.1 exactly: [p, v] meets no face except at v (a face of v may meet it only at v).
  bool sees(const Vec3& p, Index v) const {
    const K::Segment_3 segment(K::Point_3(p.x(), p.y(), p.z()), points[v]);
    for (std::size_t f = 0; f < triangles.size(); ++f) {
      const auto& t = mesh->triangles[f];
      const bool incident = t[0] == v || t[1] == v || t[2] == v;
      if (!incident) {
        if (CGAL::do_intersect(segment, triangles[f])) return false;
        continue;
      }
      const auto meet = CGAL::intersection(segment, triangles[f]);
      if (meet && boost::get<K::Point_3>(&*meet) == nullptr) return false;  // a segment: runs along the face
    }
    return true;
  }
};

struct Agreement {
  std::size_t pairs = 0, disagreements = 0, visible = 0;
  std::size_t stream_disagreements = 0;  // of sees_many(), the rays of one point as one stream
};

void compare_with_exact(const TriMesh& mesh, const std::vector<Vec3>& points, Agreement& agreement) {
  const VisibilityOracle oracle(mesh);
  const ExactSurface exact(mesh);
  std::vector<Index> all(mesh.points.size());
  for (Index v = 0; v < all.size(); ++v) all[v] = v;
  std::vector<std::uint8_t> streamed(all.size());
  for (const Vec3& p : points) {
    oracle.sees_many(p, all, streamed);
    for (Index v = 0; v < mesh.points.size(); ++v) {
      const bool expected = exact.sees(p, v);
      agreement.stream_disagreements += (streamed[v] != 0) != expected ? 1 : 0;
      ++agreement.pairs;
      agreement.visible += expected ? 1 : 0;
      if (oracle.sees(p, v) != expected) {
        ++agreement.disagreements;
        std::printf("  disagreement: p = (%.17g, %.17g, %.17g), vertex %u, exact %s\n", p.x(), p.y(), p.z(), v,
                    expected ? "visible" : "blocked");
      }
    }
  }
}

TEST(Visibility, AgreesWithExactBruteForceOnNonConvexSolids) {
  std::mt19937 rng(2015);
  Agreement agreement;

  // A bumpy blob: interior points by exact ray parity (two directions must agree).
  const TriMesh blob = test::bumpy_sphere(2);
  {
    const ExactSurface exact(blob);
    std::uniform_real_distribution<double> coordinate(-1.45, 1.45);
    std::vector<Vec3> points;
    while (points.size() < 16) {
      const Vec3 p(coordinate(rng), coordinate(rng), coordinate(rng));
      const bool a = exact.inside(p, Vec3(0.3122, 0.8171, 0.4847)), b = exact.inside(p, Vec3(-0.6, 0.13, -0.79));
      if (a && b) points.push_back(p);
    }
    compare_with_exact(blob, points, agreement);
  }
  // A union of cubes with a tunnel-like notch: interior points inside random cells.
  std::vector<Cell> cells;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 2; ++k)
        if (!(j >= 1 && j <= 2 && i >= 1) || k == 0) cells.push_back({i, j, k});
  const TriMesh notched = voxel_surface(cells);
  {
    std::uniform_real_distribution<double> unit(0.001, 0.999);
    std::uniform_int_distribution<std::size_t> which(0, cells.size() - 1);
    std::vector<Vec3> points;
    for (int n = 0; n < 16; ++n) {
      const Cell& c = cells[which(rng)];
      points.emplace_back(c[0] + unit(rng), c[1] + unit(rng), c[2] + unit(rng));
    }
    compare_with_exact(notched, points, agreement);
  }
  std::printf("exact comparison: %zu pairs, %zu visible, %zu disagreements (%zu as ray streams)\n", agreement.pairs,
              agreement.visible, agreement.disagreements, agreement.stream_disagreements);
  ASSERT_GT(agreement.pairs, 3000u);
  // Both outcomes must be common, or the comparison says little.
  EXPECT_GT(agreement.visible, agreement.pairs / 10);
  EXPECT_LT(agreement.visible, agreement.pairs * 9 / 10);
  EXPECT_LE(agreement.disagreements * 1000, agreement.pairs);
  EXPECT_LE(agreement.stream_disagreements * 1000, agreement.pairs);
}

TEST(Visibility, StreamedRaysBlockGrazingSegmentsAndCheckTheirInput) {
  // The L of GrazingSegmentsAreBlocked, asked as one stream per point: every vertex
  // as in a stream of its own, sees() (no grazing ray there is decided by rounding),
  // the segment through the reflex vertex (1, 1, 1) blocked.
  const TriMesh mesh = two_cell_thick_l();
  const VisibilityOracle oracle(mesh);
  std::vector<Index> all(mesh.points.size());
  for (Index v = 0; v < all.size(); ++v) all[v] = v;
  std::vector<std::uint8_t> visible(all.size());
  std::size_t seen = 0;
  for (const Vec3& p : {Vec3(1.5, 0.5, 1.5), Vec3(0.5, 0.5, 0.5), Vec3(0.5, 2.5, 1.5), Vec3(2.9, 0.1, 0.1)}) {
    oracle.sees_many(p, all, visible);
    for (Index v = 0; v < all.size(); ++v) {
      EXPECT_EQ(visible[v] != 0, oracle.sees(p, v)) << "from " << p.transpose() << " to " << mesh.points[v].transpose();
      seen += visible[v];
    }
  }
  EXPECT_GT(seen, all.size());
  oracle.sees_many(Vec3(1.5, 0.5, 1.5), std::vector<Index>{vertex_at(mesh, Vec3(0, 2, 0))},
                   std::span(visible).first(1));
  EXPECT_EQ(visible[0], 0);
  // An empty stream is fine; answers of the wrong length are an error.
  oracle.sees_many(Vec3(0.5, 0.5, 0.5), {}, {});
  EXPECT_THROW(oracle.sees_many(Vec3(0.5, 0.5, 0.5), all, std::span(visible).first(2)), Error);
}

}  // namespace
}  // namespace structmesh
