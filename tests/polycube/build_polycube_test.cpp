// build_polycube() end to end (chapter 4): a box gives a single cube; a torus, a sphere
// and the data set's genus-1 and genus-3 models give valid orthogonal polyhedra (closed
// 2-manifold quad surfaces, every quad axis-aligned) with the input's topology.
#include "polycube/shapes.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/polycube.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numbers>
#include <utility>

namespace structmesh {
namespace {

using test::torus;

std::filesystem::path data_dir() {
  const char* env = std::getenv("STRUCTMESH_DATA");
  return std::filesystem::path(env != nullptr && *env != '\0' ? env : STRUCTMESH_DATA_DEFAULT);
}

/// A box [0, a] x [0, b] x [0, c] with each face cut into n x n squares (two triangles each).
TriMesh subdivided_box(double a, double b, double c, int n) {
  TriMesh mesh;
  std::map<std::array<int, 3>, Index> ids;
  const auto vertex = [&](std::array<int, 3> k) {
    const auto [it, inserted] = ids.emplace(k, static_cast<Index>(mesh.points.size()));
    if (inserted) mesh.points.emplace_back(a * k[0] / n, b * k[1] / n, c * k[2] / n);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (const int side : {0, n}) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<int, 3> p0{}, p1{}, p2{}, p3{};
          p0[axis] = p1[axis] = p2[axis] = p3[axis] = side;
          p0[u] = i, p0[w] = j;
          p1[u] = i + 1, p1[w] = j;
          p2[u] = i + 1, p2[w] = j + 1;
          p3[u] = i, p3[w] = j + 1;
          std::array<Index, 4> q{vertex(p0), vertex(p1), vertex(p2), vertex(p3)};
          if (side == 0) std::swap(q[1], q[3]);  // e_u x e_w = e_axis points out at the far side
          mesh.triangles.push_back({q[0], q[1], q[2]});
          mesh.triangles.push_back({q[0], q[2], q[3]});
        }
    }
  return mesh;
}

/// A UV sphere of radius r (poles as single vertices).
TriMesh sphere(double r, int rings, int segments) {
  TriMesh mesh;
  mesh.points.emplace_back(0, 0, -r);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double polar = std::numbers::pi * i / rings, a = 2 * std::numbers::pi * j / segments;
      mesh.points.emplace_back(r * std::sin(polar) * std::cos(a), r * std::sin(polar) * std::sin(a),
                               -r * std::cos(polar));
    }
  mesh.points.emplace_back(0, 0, r);
  const auto id = [&](int i, int j) { return static_cast<Index>(1 + (i - 1) * segments + (j + segments) % segments); };
  const auto top = static_cast<Index>(mesh.points.size() - 1);
  for (int j = 0; j < segments; ++j) {
    mesh.triangles.push_back({0, id(1, j + 1), id(1, j)});
    mesh.triangles.push_back({top, id(rings - 1, j), id(rings - 1, j + 1)});
  }
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      mesh.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
    }
  return mesh;
}

/// The polycube surface is a valid orthogonal polyhedron: a closed, consistently oriented
/// 2-manifold of axis-aligned quads bounding positive volume, with the expected genus.
void expect_valid_polycube(const PolycubeResult& result, int genus) {
  SCOPED_TRACE("genus " + std::to_string(genus));
  EXPECT_EQ(result.final.components, 1);
  EXPECT_EQ(result.final.handles, genus);
  EXPECT_EQ(result.final.voids, 0);
  EXPECT_TRUE(is_well_composed(result.voxels));
  const QuadMesh& p = result.surface;
  ASSERT_FALSE(p.quads.empty());
  MeshBundle triangles;
  triangles.points = p.points;
  for (const auto& q : p.quads) {
    const Vec3 normal = (p.points[q[2]] - p.points[q[0]]).cross(p.points[q[3]] - p.points[q[1]]);
    EXPECT_NEAR(normal.cwiseAbs().maxCoeff(), normal.norm(), 1e-12 * normal.norm());  // axis-aligned
    triangles.triangles.push_back({q[0], q[1], q[2]});
    triangles.triangles.push_back({q[0], q[2], q[3]});
  }
  CheckOptions no_intersection_test;
  no_intersection_test.self_intersections = false;  // coplanar neighbours are fine here
  const SurfaceReport report = check_surface(triangles, no_intersection_test);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.edge_manifold);
  EXPECT_EQ(report.non_manifold_vertices, 0U);
  EXPECT_TRUE(report.oriented);
  EXPECT_GT(report.signed_volume, 0);
  EXPECT_EQ(report.genus, genus);
}

TEST(BuildPolycube, ABoxIsOneCube) {
  const PolycubeResult result = build_polycube(subdivided_box(3, 2, 1.5, 6));
  expect_valid_polycube(result, 0);
  std::size_t corners = 0;
  for (const std::uint8_t c : result.corner) corners += c;
  EXPECT_EQ(corners, 8U);
  EXPECT_EQ(result.optimization.after.corners, 8U);
  EXPECT_EQ(result.pseudo.wedges, 0U);
  // Its voxels fill a box: count = product of the box's extents in voxels.
  const BoundingBox3 box = bounding_box(result.surface.points);
  const Vec3 extent = (box.max - box.min) / result.voxels.size;
  EXPECT_NEAR(static_cast<double>(result.voxels.count()),
              std::round(extent.x()) * std::round(extent.y()) * std::round(extent.z()), 0.5);
}

TEST(BuildPolycube, TorusKeepsItsHandle) {
  const PolycubeResult result = build_polycube(torus(2, 0.6, 64, 32));
  expect_valid_polycube(result, 1);
  EXPECT_LE(result.optimization.after.total, result.optimization.before.total);
  EXPECT_EQ(result.optimization.after.corners, 16U);  // the fewest a polycube torus can have
}

TEST(BuildPolycube, SphereIsABallOfFewCorners) {
  const PolycubeResult result = build_polycube(sphere(1, 24, 48));
  expect_valid_polycube(result, 0);
  EXPECT_LE(result.optimization.after.corners, 64U);  // a blocky ball, not a staircase
}

TEST(BuildPolycube, RefusesAnOpenSurface) {
  TriMesh open = sphere(1, 8, 16);
  open.triangles.pop_back();
  EXPECT_THROW(build_polycube(open), InputError);
  EXPECT_THROW(build_polycube(TriMesh{}), InputError);
}

TEST(BuildPolycube, DataModelsOfGenusOneAndThree) {
  for (const auto& [name, genus] : {std::pair<const char*, int>{"kitten.off", 1}, {"3holes.off", 3}}) {
    SCOPED_TRACE(name);
    const MeshBundle bundle = read_mesh((data_dir() / "surfaces" / name).string());
    const PolycubeResult result = build_polycube(TriMesh{bundle.points, bundle.triangles});
    EXPECT_EQ(result.expected.handles, genus);
    expect_valid_polycube(result, genus);
  }
}

}  // namespace
}  // namespace structmesh
