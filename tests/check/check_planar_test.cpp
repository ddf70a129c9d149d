// Planar mesh validation on hand-made meshes whose answers can be counted.
#include "structmesh/check.hpp"

#include <gtest/gtest.h>

namespace structmesh {
namespace {

// An nx x ny grid of unit quads, counter-clockwise; `hole` removes the quad (hx, hy).
MeshBundle grid(int nx, int ny, int hx = -1, int hy = -1) {
  MeshBundle mesh;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) mesh.points.emplace_back(i, j, 0.0);
  const auto id = [nx](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      if (i != hx || j != hy) mesh.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return mesh;
}

bool has_kind(const PlanarMeshReport& r, const std::string& kind) {
  for (const Problem& p : r.problems)
    if (p.kind == kind) return true;
  return false;
}

TEST(CheckPlanar, RegularGridIsValidDiskWithArea) {
  const PlanarMeshReport r = check_planar_mesh(grid(4, 3));
  EXPECT_TRUE(r.valid);
  EXPECT_TRUE(r.planar);
  EXPECT_EQ(r.quads, 12u);
  EXPECT_EQ(r.edges, 31u);  // 4*4 horizontal + 5*3 vertical
  EXPECT_EQ(r.boundary_edges, 14u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.holes, 0u);
  EXPECT_DOUBLE_EQ(r.area, 12.0);
  EXPECT_DOUBLE_EQ(r.min_quad_scaled_jacobian, 1.0);
}

TEST(CheckPlanar, MissingInteriorQuadIsAHole) {
  const PlanarMeshReport r = check_planar_mesh(grid(3, 3, 1, 1));
  EXPECT_TRUE(r.valid);
  EXPECT_EQ(r.holes, 1u);
  EXPECT_DOUBLE_EQ(r.area, 8.0);
  EXPECT_EQ(r.boundary_edges, 16u);
}

TEST(CheckPlanar, FlippedQuadIsInvertedAndInconsistent) {
  MeshBundle mesh = grid(3, 1);
  std::reverse(mesh.quads[1].begin(), mesh.quads[1].end());
  const PlanarMeshReport r = check_planar_mesh(mesh);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.inverted, 1u);
  EXPECT_EQ(r.inconsistent_edges, 2u);  // shared with both neighbours
  EXPECT_TRUE(has_kind(r, "inverted-element"));
  EXPECT_DOUBLE_EQ(r.min_quad_scaled_jacobian, -1.0);
}

TEST(CheckPlanar, NonConvexQuadIsInverted) {
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {2, 0, 0}, {0.5, 0.5, 0}, {0, 2, 0}};  // reflex corner at vertex 2
  mesh.quads = {{0, 1, 2, 3}};
  const PlanarMeshReport r = check_planar_mesh(mesh);
  EXPECT_EQ(r.inverted, 1u);
  EXPECT_FALSE(r.valid);
  EXPECT_GT(r.area, 0.0);
}

TEST(CheckPlanar, ThreeQuadsOnOneEdgeAreNonManifold) {
  MeshBundle mesh = grid(2, 1);
  mesh.points.emplace_back(1.5, -1, 0);
  mesh.points.emplace_back(0.5, -1, 0);
  // A third quad hanging under edge 1-4 (the shared edge of the two grid quads).
  mesh.quads.push_back({1, 4, 7, 6});
  const PlanarMeshReport r = check_planar_mesh(mesh);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_FALSE(r.valid);
}

TEST(CheckPlanar, DegenerateAndUnusedAndNotPlanar) {
  MeshBundle mesh = grid(1, 1);
  mesh.quads.push_back({0, 1, 1, 3});
  mesh.points.emplace_back(5, 5, 0);
  PlanarMeshReport r = check_planar_mesh(mesh);
  EXPECT_EQ(r.degenerate, 1u);
  EXPECT_EQ(r.unused_vertices, 1u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_FALSE(r.valid);

  MeshBundle bent = grid(1, 1);
  bent.points[3].z() = 0.5;
  r = check_planar_mesh(bent);
  EXPECT_FALSE(r.planar);
  EXPECT_FALSE(r.valid);
  EXPECT_TRUE(has_kind(r, "not-planar"));
}

TEST(CheckPlanar, MixedTrianglesAndQuadsConform) {
  MeshBundle mesh = grid(1, 1);
  mesh.points.emplace_back(2, 0.5, 0);
  mesh.triangles.push_back({1, 4, 3});
  const PlanarMeshReport r = check_planar_mesh(mesh);
  EXPECT_TRUE(r.valid);
  EXPECT_EQ(r.edges, 6u);
  EXPECT_EQ(r.boundary_edges, 5u);
  EXPECT_DOUBLE_EQ(r.area, 1.5);
}

TEST(CheckPlanar, OutOfRangeIndexIsReportedNotCrashed) {
  MeshBundle mesh = grid(1, 1);
  mesh.quads.push_back({0, 1, 2, 99});
  const PlanarMeshReport r = check_planar_mesh(mesh);
  EXPECT_FALSE(r.valid);
  EXPECT_TRUE(has_kind(r, "index-out-of-range"));
}

}  // namespace
}  // namespace structmesh
