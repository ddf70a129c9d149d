// check_surface() on every model of $STRUCTMESH_DATA/surfaces against the table of
// shared/data/README.md (counted there by independent scripts). A missing data
// folder is a failure, not a skip: these are the tests that matter.
#include "structmesh/check.hpp"
#include "structmesh/io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <set>
#include <string>

namespace structmesh {
namespace {

std::filesystem::path surfaces_dir() {
  const char* env = std::getenv("STRUCTMESH_DATA");
  return std::filesystem::path(env && *env ? env : STRUCTMESH_DATA_DEFAULT) / "surfaces";
}

// One row of the README's surfaces table.
struct Expected {
  const char* file;
  std::size_t vertices, faces;
  bool closed;
  int volume_sign;  // +1 outward, -1 inward
  long chi;
  int genus;  // -1 for open models ("–")
  std::size_t self_intersections;
  std::size_t boundary_edges;  // from the notes: holes and their edges
  std::size_t non_manifold_vertices;
};

// Every model is consistently oriented, connected, without degenerate faces or non-manifold edges.
const Expected kTable[] = {
    {"bunny_hr.obj", 29834, 59664, true, +1, 2, 0, 0, 0, 0},
    {"rocker-arm.obj", 10044, 20088, true, +1, 0, 1, 0, 0, 0},
    {"fertility.off", 23188, 46388, true, +1, -6, 4, 0, 0, 0},
    {"kitten.off", 10000, 20000, true, +1, 0, 1, 0, 0, 0},
    {"kitten_40k.off", 40000, 80000, true, +1, 0, 1, 0, 0, 0},
    {"hand_closed.obj", 7993, 15982, true, +1, 2, 0, 0, 0, 0},
    {"3holes.off", 3596, 7200, true, +1, -4, 3, 0, 0, 0},
    {"eight.off", 766, 1536, true, +1, -2, 2, 0, 0, 0},
    {"double-torus.obj", 2174, 4352, true, +1, -2, 2, 0, 0, 0},
    {"torus.obj", 2304, 4608, true, +1, 0, 1, 0, 0, 0},
    {"screwdriver.off", 3395, 6786, true, +1, 2, 0, 0, 0, 0},
    {"wingnut.obj", 3047, 6090, true, +1, 2, 0, 1, 0, 0},
    {"horse.off", 48485, 96966, true, -1, 2, 0, 2, 0, 0},
    {"happy_buddha_13k.off", 13295, 26999, false, +1, -208, -1, 105, 7, 2},
    {"tosca_centaur.off", 10000, 19996, true, +1, 2, 0, 32, 0, 0},
    {"tosca_dog0.off", 25290, 50528, false, +1, 0, -1, 0, 52, 0},
    {"tosca_dog0_closed.off", 25292, 50580, true, +1, 2, 0, 0, 0, 0},
    {"tosca_gorilla.off", 25438, 50868, false, +1, 1, -1, 447, 6, 0},
    {"tosca_michael.off", 52565, 105028, false, +1, -2, -1, 1001, 106, 0},
    {"tosca_victoria.off", 45659, 91208, false, +1, -1, -1, 1632, 112, 0},
};

// Names the file when a parameterised test fails (instead of the struct's bytes).
void PrintTo(const Expected& e, std::ostream* os) { *os << e.file; }

class SurfaceData : public testing::TestWithParam<Expected> {};

TEST_P(SurfaceData, MatchesTheReadmeTable) {
  const Expected& e = GetParam();
  const std::filesystem::path path = surfaces_dir() / e.file;
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " is missing (set STRUCTMESH_DATA)";
  const MeshBundle mesh = read_mesh(path);
  ASSERT_EQ(mesh.points.size(), e.vertices);
  ASSERT_EQ(mesh.triangles.size(), e.faces);

  const SurfaceReport r = check_surface(mesh);
  EXPECT_EQ(r.vertices, e.vertices);
  EXPECT_EQ(r.isolated_vertices, 0u);
  EXPECT_EQ(r.faces, e.faces);
  EXPECT_EQ(r.closed, e.closed);
  EXPECT_EQ(r.boundary_edges, e.boundary_edges);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_TRUE(r.edge_manifold);
  EXPECT_EQ(r.non_manifold_vertices, e.non_manifold_vertices);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.degenerate_faces, 0u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, e.chi);
  EXPECT_EQ(r.genus, e.genus);
  EXPECT_EQ(r.signed_volume > 0 ? +1 : -1, e.volume_sign) << r.signed_volume;
  EXPECT_EQ(r.self_intersections, e.self_intersections);
  // The README's rule for "usable as-is for tetrahedralization".
  const bool usable = e.closed && e.non_manifold_vertices == 0 && e.volume_sign > 0 && e.self_intersections == 0;
  EXPECT_EQ(r.valid_solid_boundary, usable);
}

INSTANTIATE_TEST_SUITE_P(Readme, SurfaceData, testing::ValuesIn(kTable), [](const auto& info) {
  std::string name = info.param.file;
  name = name.substr(0, name.find('.'));
  std::replace_if(
      name.begin(), name.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
  return name;
});

TEST(SurfaceData, TableCoversEveryFile) {
  const std::filesystem::path dir = surfaces_dir();
  ASSERT_TRUE(std::filesystem::is_directory(dir)) << dir << " is missing (set STRUCTMESH_DATA)";
  std::set<std::string> on_disk, in_table;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) on_disk.insert(entry.path().filename().string());
  for (const Expected& e : kTable) in_table.insert(e.file);
  EXPECT_EQ(on_disk, in_table);
}

}  // namespace
}  // namespace structmesh
