// tetrahedralize(): the contract on analytic surfaces and a real model — surface points
// first and bit-identical, positive tets, boundary = input triangles, volume = enclosed
// volume — and the error paths of bad input.
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/solids.hpp"
#include "structmesh/tetmesh.hpp"
#include "test_data.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

namespace structmesh {
namespace {

// Unit cube [0,1]^3, 12 triangles with outward normals.
TriMesh unit_cube(const Vec3& offset = Vec3::Zero()) {
  TriMesh cube;
  for (int i = 0; i < 8; ++i) cube.points.push_back(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1) + offset);
  // Corner i = x + 2y + 4z; each face as two triangles, counter-clockwise seen from outside.
  cube.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                    {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return cube;
}

// Torus of radii R and r from an nu x nv parametric grid, outward.
TriMesh torus(int nu, int nv, double R = 2.0, double r = 0.7) { return torus_surface(R, r, nu, nv); }

// Enclosed volume straight from the triangles, about the origin (independent of the library's).
double volume_from_origin(const TriMesh& s) {
  double six = 0;
  for (const auto& t : s.triangles) six += s.points[t[0]].dot(s.points[t[1]].cross(s.points[t[2]]));
  return six / 6;
}

double tet_volume(const TetMesh& m, const std::array<Index, 4>& t) {
  const Vec3 &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]], &d = m.points[t[3]];
  return (b - a).dot((c - a).cross(d - a)) / 6;
}

// Same triangle up to a cyclic rotation (same orientation).
bool same_oriented(std::array<Index, 3> a, const std::array<Index, 3>& b) {
  for (int k = 0; k < 3; ++k) {
    if (a == b) return true;
    std::rotate(a.begin(), a.begin() + 1, a.end());
  }
  return false;
}

// Every property the header promises, checked from the mesh itself.
void expect_valid(const TriMesh& surface, const TetmeshResult& result, double volume_tolerance) {
  const TetMesh& mesh = result.mesh;
  ASSERT_GE(mesh.points.size(), surface.points.size());
  for (std::size_t p = 0; p < surface.points.size(); ++p)
    ASSERT_EQ(std::memcmp(mesh.points[p].data(), surface.points[p].data(), 3 * sizeof(double)), 0)
        << "point " << p << " changed";
  ASSERT_FALSE(mesh.tets.empty());

  double volume = 0;
  std::size_t non_positive = 0;
  std::vector<std::uint8_t> used(mesh.points.size(), 0);
  for (const auto& t : mesh.tets) {
    for (Index v : t) {
      ASSERT_LT(v, mesh.points.size());
      used[v] = 1;
    }
    const double v = tet_volume(mesh, t);
    non_positive += v > 0 ? 0 : 1;
    volume += v;
  }
  EXPECT_EQ(non_positive, 0u);
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "points used by no tet";
  const double enclosed = volume_from_origin(surface);
  EXPECT_NEAR(volume, enclosed, volume_tolerance * std::abs(enclosed));
  EXPECT_NEAR(result.mesh_volume, enclosed, volume_tolerance * std::abs(enclosed));
  EXPECT_NEAR(result.surface_volume, enclosed, volume_tolerance * std::abs(enclosed));

  // Boundary faces (one tet) are the input triangles, oriented the same way (outward).
  const FaceAdjacency<3> faces = build_faces(mesh);
  EXPECT_TRUE(faces.extra_cells.empty());
  std::vector<std::array<Index, 3>> boundary;
  for (std::size_t f = 0; f < faces.faces.size(); ++f)
    if (faces.face_cells[f][1] == kInvalidIndex) boundary.push_back(faces.faces[f]);
  ASSERT_EQ(boundary.size(), surface.triangles.size());
  EXPECT_EQ(result.boundary_faces, surface.triangles.size());
  const auto key = [](std::array<Index, 3> f) {
    std::sort(f.begin(), f.end());
    return f;
  };
  std::vector<std::pair<std::array<Index, 3>, std::array<Index, 3>>> by_key;
  for (const auto& f : boundary) by_key.push_back({key(f), f});
  std::sort(by_key.begin(), by_key.end());
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    const auto k = key(surface.triangles[t]);
    const auto it = std::lower_bound(by_key.begin(), by_key.end(), std::make_pair(k, std::array<Index, 3>{}));
    ASSERT_TRUE(it != by_key.end() && it->first == k) << "input triangle " << t << " is not a boundary face";
    EXPECT_TRUE(same_oriented(it->second, surface.triangles[t])) << "triangle " << t << " flipped";
  }
  EXPECT_GT(result.min_dihedral_deg, 0);
  EXPECT_LT(result.max_dihedral_deg, 180);
  EXPECT_GT(result.min_tet_volume, 0);
}

std::string message_of(const TriMesh& surface) {
  try {
    tetrahedralize(surface);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

TEST(Tetrahedralize, UnitCube) {
  const TriMesh cube = unit_cube();
  const TetmeshResult result = tetrahedralize(cube);
  expect_valid(cube, result, 1e-9);
  EXPECT_NEAR(result.mesh_volume, 1.0, 1e-9);
  EXPECT_NEAR(result.size, (2 + std::numbers::sqrt2) / 3, 1e-12);  // mean edge: per triangle 1, 1, sqrt 2
}

TEST(Tetrahedralize, TorusKeepsSurfaceAndVolume) {
  const TriMesh surface = torus(48, 16);
  const TetmeshResult result = tetrahedralize(surface);
  expect_valid(surface, result, 1e-9);
  EXPECT_GT(result.interior_points, 0u);
  // The polyhedron is inscribed in the smooth torus (2 pi^2 R r^2), so slightly smaller.
  const double smooth = 2 * std::numbers::pi * std::numbers::pi * 2.0 * 0.7 * 0.7;
  EXPECT_LT(result.mesh_volume, smooth);
  EXPECT_GT(result.mesh_volume, 0.95 * smooth);
}

TEST(Tetrahedralize, SmallerSizeGivesMoreTets) {
  const TriMesh surface = torus(64, 24);
  TetmeshOptions coarse, fine;
  coarse.size = 0.4;
  fine.size = 0.15;
  const TetmeshResult a = tetrahedralize(surface, coarse), b = tetrahedralize(surface, fine);
  expect_valid(surface, a, 1e-9);
  expect_valid(surface, b, 1e-9);
  EXPECT_GT(b.mesh.tets.size(), a.mesh.tets.size() * 3 / 2);
  EXPECT_DOUBLE_EQ(b.size, 0.15);
}

TEST(Tetrahedralize, RejectsOpenSurface) {
  TriMesh cube = unit_cube();
  cube.triangles.pop_back();
  const std::string message = message_of(cube);
  EXPECT_NE(message.find("open"), std::string::npos) << message;
  EXPECT_NE(message.find("3 boundary edges"), std::string::npos) << message;
}

TEST(Tetrahedralize, RejectsSelfIntersection) {
  TriMesh two = unit_cube();
  const TriMesh other = unit_cube(Vec3(0.5, 0.25, 0.3));
  for (const auto& t : other.triangles) two.triangles.push_back({t[0] + 8, t[1] + 8, t[2] + 8});
  two.points.insert(two.points.end(), other.points.begin(), other.points.end());
  const std::string message = message_of(two);
  EXPECT_NE(message.find("self-intersecting"), std::string::npos) << message;
  EXPECT_NE(message.find("(first: face "), std::string::npos) << message;
}

TEST(Tetrahedralize, RejectsInwardSurface) {
  TriMesh cube = unit_cube();
  for (auto& t : cube.triangles) std::swap(t[1], t[2]);
  const std::string message = message_of(cube);
  EXPECT_NE(message.find("inward"), std::string::npos) << message;
  EXPECT_NE(message.find("--repair"), std::string::npos) << message;
}

TEST(Tetrahedralize, RejectsInconsistentOrientation) {
  TriMesh cube = unit_cube();
  std::swap(cube.triangles[0][1], cube.triangles[0][2]);
  const std::string message = message_of(cube);
  EXPECT_NE(message.find("orientation is inconsistent"), std::string::npos) << message;
}

TEST(Tetrahedralize, RejectsEmptySurfaceAndBadOptions) {
  EXPECT_NE(message_of(TriMesh{}).find("empty"), std::string::npos);
  TetmeshOptions options;
  options.radius_edge_ratio = 0.9;
  EXPECT_THROW(tetrahedralize(unit_cube(), options), InputError);
  options = {};
  options.size = -1;
  EXPECT_THROW(tetrahedralize(unit_cube(), options), InputError);
}

TEST(Tetrahedralize, RejectsCavity) {
  // A 3x3x3 cube with an inward unit cube inside: a valid boundary of a hollow solid,
  // but TetGen would fill the hollow.
  TriMesh hollow = unit_cube();
  for (Vec3& p : hollow.points) p *= 3;
  TriMesh inner = unit_cube(Vec3(1, 1, 1));
  for (const auto& t : inner.triangles) hollow.triangles.push_back({t[0] + 8, t[2] + 8, t[1] + 8});
  hollow.points.insert(hollow.points.end(), inner.points.begin(), inner.points.end());
  EXPECT_NE(message_of(hollow).find("cavity"), std::string::npos);
}

TEST(Tetrahedralize, RejectsUnusedPoints) {
  TriMesh cube = unit_cube();
  cube.points.push_back(Vec3(0.5, 0.5, 0.5));
  EXPECT_NE(message_of(cube).find("used by no triangle"), std::string::npos);
}

TEST(Tetrahedralize, TorusModelFromData) {
  const std::filesystem::path path = test::data_dir() / "surfaces" / "torus.obj";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is missing (set STRUCTMESH_DATA)";
  const TriMesh surface = to_tri_mesh(read_mesh(path));
  const TetmeshResult result = tetrahedralize(surface);
  expect_valid(surface, result, 1e-9);
  EXPECT_GT(result.mesh.tets.size(), surface.triangles.size());
}

// repair_solid_surface() (the --repair of guard and hex): an open, inward cube comes out
// closed and outward, and then tetrahedralizes; a self-intersecting surface stays so.
TEST(RepairSolidSurface, ClosesHolesAndTurnsAnInwardSurface) {
  TriMesh cube = unit_cube();
  cube.triangles.pop_back();
  for (auto& t : cube.triangles) std::swap(t[1], t[2]);
  const std::size_t kept = cube.triangles.size();
  const SurfaceRepair repair = repair_solid_surface(cube);
  EXPECT_EQ(repair.holes, 1u);
  EXPECT_EQ(repair.added_faces, 1u);
  EXPECT_TRUE(repair.turned);
  EXPECT_EQ(cube.triangles.size(), kept + 1);
  EXPECT_NEAR(enclosed_volume(cube), 1.0, 1e-12);
  expect_valid(cube, tetrahedralize(cube), 1e-9);
  // Nothing to do on a sound surface.
  TriMesh sound = unit_cube();
  const SurfaceRepair none = repair_solid_surface(sound);
  EXPECT_EQ(none.holes, 0u);
  EXPECT_FALSE(none.turned);
  EXPECT_EQ(sound.triangles, unit_cube().triangles);
}

}  // namespace
}  // namespace structmesh
