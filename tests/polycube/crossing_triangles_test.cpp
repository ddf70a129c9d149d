// The intersection guard of the pre-deformation: its cheap filters must never hide a
// pair the exact search of check_surface() reports, so on every surface it returns
// exactly the triangles of the full exact search.
#include "polycube/crossing_triangles.hpp"
#include "check/self_intersections.hpp"
#include "guard/shapes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace structmesh {
namespace {

// The triangles in the pairs the exact search over all triangles reports.
std::vector<Index> oracle(const TriMesh& mesh) {
  const detail::SelfIntersections found = detail::find_self_intersections(mesh.points, mesh.triangles, {}, true);
  std::vector<Index> triangles;
  for (const auto& pairs : {found.disjoint_pairs, found.adjacent_overlaps})
    for (const auto& pair : pairs) triangles.insert(triangles.end(), pair.begin(), pair.end());
  std::sort(triangles.begin(), triangles.end());
  triangles.erase(std::unique(triangles.begin(), triangles.end()), triangles.end());
  return triangles;
}

std::vector<Index> guard(const TriMesh& mesh) {
  return polycube_detail::crossing_triangles(mesh.points, mesh.triangles,
                                             build_vertex_elements(mesh.triangles, mesh.points.size()));
}

TEST(CrossingTriangles, CleanSurfacesHaveNone) {
  EXPECT_TRUE(guard(test::unit_icosphere(3)).empty());
  EXPECT_TRUE(guard(test::bumpy_sphere(3)).empty());
  EXPECT_TRUE(guard(test::voxel_surface(test::ring_cells(), 3)).empty());
}

TEST(CrossingTriangles, SameTrianglesAsTheExactSearchOnNoisySpheres) {
  // Vertices pushed along random directions by up to `noise` edge lengths: folds,
  // fans turned over and sheets passing through each other, at several strengths.
  std::mt19937 random(20240611);
  for (const double noise : {0.2, 0.6, 1.5, 4.0}) {
    for (int sample = 0; sample < 4; ++sample) {
      TriMesh mesh = test::unit_icosphere(3);
      const double edge = (mesh.points[mesh.triangles[0][0]] - mesh.points[mesh.triangles[0][1]]).norm();
      std::uniform_real_distribution<double> uniform(-1.0, 1.0);
      for (Vec3& p : mesh.points) p += noise * edge * Vec3(uniform(random), uniform(random), uniform(random));
      const std::vector<Index> expected = oracle(mesh);
      EXPECT_EQ(guard(mesh), expected) << "noise " << noise << ", sample " << sample;
      if (noise >= 0.6) {
        EXPECT_FALSE(expected.empty());
      }
    }
  }
}

TEST(CrossingTriangles, SameTrianglesFarFromTheOrigin) {
  // Two unit boxes through each other, a million units away: the filters' margins must
  // account for the rounding of large coordinates.
  TriMesh mesh = test::voxel_surface({{0, 0, 0}}, 3);
  const std::size_t first = mesh.points.size();
  const TriMesh other = test::voxel_surface({{0, 0, 0}}, 3);
  for (const Vec3& p : other.points) mesh.points.push_back(p + Vec3(0.5, 0.25, 0.125));
  for (const auto& t : other.triangles)
    mesh.triangles.push_back({Index(t[0] + first), Index(t[1] + first), Index(t[2] + first)});
  for (Vec3& p : mesh.points) p += Vec3(1e6, -2e6, 3e6);
  const std::vector<Index> expected = oracle(mesh);
  EXPECT_FALSE(expected.empty());
  EXPECT_EQ(guard(mesh), expected);
}

TEST(CrossingTriangles, ZeroAreaTrianglesAreReported) {
  TriMesh mesh = test::unit_icosphere(2);
  // Two corners of triangle 7 on one point: zero area (exactly collinear).
  const auto& t = mesh.triangles[7];
  mesh.points[t[0]] = mesh.points[t[1]];
  const std::vector<Index> found = guard(mesh);
  EXPECT_TRUE(std::binary_search(found.begin(), found.end(), Index(7)));
}

}  // namespace
}  // namespace structmesh
