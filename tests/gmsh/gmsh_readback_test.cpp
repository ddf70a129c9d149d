// Independent readers as oracles for our writers, and an independent writer for our
// reader: the Gmsh library opens our .msh files, VTK (python3-vtk9) opens our .vtu and
// .pvtu files, and VTK writes .vtu files in every uncompressed encoding for read_vtu.
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/mesh.hpp"

#include <gmsh.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace structmesh {
namespace {

std::filesystem::path temp_dir() {
  const std::filesystem::path dir = std::filesystem::path(STRUCTMESH_BINARY_DIR) / "test_tmp" / "gmsh_readback";
  std::filesystem::create_directories(dir);
  return dir;
}

// An n x n x n grid of points with spacing that needs all 17 digits.
std::vector<Vec3> grid_points(int n) {
  std::vector<Vec3> points;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) points.emplace_back(i / 3.0, j * 0.7 + 0.1, k * 1.1);
  return points;
}

Index grid_index(int n, int i, int j, int k) { return static_cast<Index>((k * n + j) * n + i); }

// 2 x 2 x 2 hexes in VTK order, labelled by layer (two volume entities).
MeshBundle hex_mesh() {
  MeshBundle mesh;
  mesh.points = grid_points(3);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const auto at = [&](int di, int dj, int dk) { return grid_index(3, i + di, j + dj, k + dk); };
        mesh.hexes.push_back(
            {at(0, 0, 0), at(1, 0, 0), at(1, 1, 0), at(0, 1, 0), at(0, 0, 1), at(1, 0, 1), at(1, 1, 1), at(0, 1, 1)});
        mesh.hex_labels.push_back(10 + k);
      }
  return mesh;
}

// Each hex of hex_mesh() split into 6 positive tets around its 0-6 diagonal.
MeshBundle tet_mesh() {
  const MeshBundle hexes = hex_mesh();
  MeshBundle mesh;
  mesh.points = hexes.points;
  static constexpr int kSplit[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                       {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  for (const auto& h : hexes.hexes)
    for (const auto& t : kSplit) {
      const std::array<Index, 4> tet{h[t[0]], h[t[1]], h[t[2]], h[t[3]]};
      const Vec3& p = mesh.points[tet[0]];
      EXPECT_GT((mesh.points[tet[1]] - p).cross(mesh.points[tet[2]] - p).dot(mesh.points[tet[3]] - p), 0.0);
      mesh.tets.push_back(tet);
    }
  return mesh;
}

// 3 x 3 quads in the z = 0 plane, counter-clockwise seen from +z.
MeshBundle quad_mesh() {
  MeshBundle mesh;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) mesh.points.emplace_back(i * 0.25, j / 7.0, 0.0);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const auto at = [&](int di, int dj) { return static_cast<Index>((j + dj) * 4 + i + di); };
      mesh.quads.push_back({at(0, 0), at(1, 0), at(1, 1), at(0, 1)});
    }
  return mesh;
}

// The mixed mesh of the VTU checks: 1 hex, 1 tet on top, 1 quad under, 2 triangles.
MeshBundle mixed_mesh() {
  MeshBundle mesh;
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {0.5, 0.5, 2}};
  mesh.points[8].x() = 1.0 / 3.0;
  mesh.hexes = {{0, 1, 2, 3, 4, 5, 6, 7}};
  mesh.tets = {{4, 5, 6, 8}};
  mesh.quads = {{0, 3, 2, 1}};
  mesh.triangles = {{4, 5, 8}, {5, 6, 8}};
  return mesh;
}

class GmshReadback : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);
  }
  static void TearDownTestSuite() { gmsh::finalize(); }

  // Writes `mesh` with write_mesh, opens it with Gmsh and compares nodes, elements
  // (per Gmsh type, in order) and volume/surface entities.
  static void check(const MeshBundle& mesh, const std::string& name) {
    const std::filesystem::path path = temp_dir() / name;
    write_mesh(path, mesh);
    gmsh::open(path.string());

    std::vector<std::size_t> node_tags;
    std::vector<double> coords, parametric;
    gmsh::model::mesh::getNodes(node_tags, coords, parametric, -1, -1, false, false);
    ASSERT_EQ(node_tags.size(), mesh.points.size());
    for (std::size_t n = 0; n < node_tags.size(); ++n) {
      const std::size_t i = node_tags[n] - 1;  // we write point i as node tag i + 1
      ASSERT_LT(i, mesh.points.size());
      for (int k = 0; k < 3; ++k) EXPECT_EQ(coords[3 * n + k], mesh.points[i][k]) << "node " << node_tags[n];
    }

    std::vector<int> types;
    std::vector<std::vector<std::size_t>> element_tags, element_nodes;
    gmsh::model::mesh::getElements(types, element_tags, element_nodes, -1, -1);
    std::map<int, std::vector<std::size_t>> nodes_by_type;  // Gmsh type -> node tags in element-tag order
    for (std::size_t t = 0; t < types.size(); ++t) {
      const std::size_t per = element_nodes[t].size() / element_tags[t].size();
      std::vector<std::pair<std::size_t, std::size_t>> order;  // (element tag, position)
      for (std::size_t e = 0; e < element_tags[t].size(); ++e) order.emplace_back(element_tags[t][e], e);
      std::sort(order.begin(), order.end());
      for (const auto& [tag, e] : order)
        for (std::size_t k = 0; k < per; ++k) nodes_by_type[types[t]].push_back(element_nodes[t][e * per + k]);
    }
    EXPECT_EQ(nodes_by_type.size(), static_cast<std::size_t>(!mesh.triangles.empty()) + !mesh.quads.empty() +
                                        !mesh.tets.empty() + !mesh.hexes.empty());
    const auto expect_type = [&](int type, const auto& elements) {
      std::vector<std::size_t> expected;
      for (const auto& element : elements)
        for (const Index v : element) expected.push_back(std::size_t{v} + 1);
      EXPECT_EQ(nodes_by_type[type], expected) << name << ": Gmsh element type " << type;
    };
    expect_type(2, mesh.triangles);
    expect_type(3, mesh.quads);
    expect_type(4, mesh.tets);
    expect_type(5, mesh.hexes);

    std::set<std::int32_t> volume_labels(mesh.tet_labels.begin(), mesh.tet_labels.end());
    volume_labels.insert(mesh.hex_labels.begin(), mesh.hex_labels.end());
    if (volume_labels.empty() && (!mesh.tets.empty() || !mesh.hexes.empty())) volume_labels.insert(0);
    gmsh::vectorpair volumes;
    gmsh::model::getEntities(volumes, 3);
    std::set<std::int32_t> gmsh_volumes;
    for (const auto& [dim, tag] : volumes) gmsh_volumes.insert(tag);
    if (!volume_labels.empty()) {
      EXPECT_EQ(gmsh_volumes, volume_labels) << name;
    }
  }
};

TEST_F(GmshReadback, TetMesh) { check(tet_mesh(), "tets.msh"); }
TEST_F(GmshReadback, HexMeshWithTwoEntities) { check(hex_mesh(), "hexes.msh"); }
TEST_F(GmshReadback, QuadMesh) { check(quad_mesh(), "quads.msh"); }
TEST_F(GmshReadback, MixedMesh) { check(mixed_mesh(), "mixed.msh"); }

// --- VTK as oracle ---

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs a Python script with Debian's python3 (which has python3-vtk9) and returns stdout.
std::string run_python(const std::string& script, const std::string& name) {
  EXPECT_EQ(std::system("/usr/bin/python3 -c 'import vtk' > /dev/null 2>&1"), 0)
      << "/usr/bin/python3 with the vtk module (Debian: python3-vtk9) is required";
  const std::filesystem::path py = temp_dir() / (name + ".py"), out = temp_dir() / (name + ".out");
  std::ofstream(py) << script;
  const std::string command = "/usr/bin/python3 '" + py.string() + "' > '" + out.string() + "' 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << command << "\n" << slurp(out);
  return slurp(out);
}

TEST(VtkReadsOurVtu, CountsTypesCoordinatesAndArrays) {
  const MeshBundle mesh = mixed_mesh();
  WriteOptions options;
  options.cell_data.push_back({"part", {}, {1, 2, 3, 4, 5}});
  options.cell_data.push_back({"quality", {0.5, 0.25, 1.0 / 3.0, 1, 0}, {}});
  std::vector<double> temperature;
  for (std::size_t i = 0; i < mesh.points.size(); ++i) temperature.push_back(i * 0.1);
  options.point_data.push_back({"temperature", temperature, {}});
  const std::filesystem::path path = temp_dir() / "mixed.vtu";
  write_mesh(path, mesh, options);

  const std::string output = run_python(
      "import vtk\n"
      "r = vtk.vtkXMLUnstructuredGridReader()\n"
      "r.SetFileName('" +
          path.string() +
          "')\n"
          "r.Update()\n"
          "g = r.GetOutput()\n"
          "print(g.GetNumberOfPoints(), g.GetNumberOfCells())\n"
          "print(' '.join(str(g.GetCellType(c)) for c in range(g.GetNumberOfCells())))\n"
          "print(' '.join(str(g.GetCell(c).GetPointId(k)) for c in range(g.GetNumberOfCells())"
          " for k in range(g.GetCell(c).GetNumberOfPoints())))\n"
          "print(' '.join(repr(g.GetPoint(8)[k]) for k in range(3)))\n"
          "a = g.GetCellData().GetArray('part')\n"
          "print(a.GetDataTypeAsString(), ' '.join(str(int(a.GetTuple1(c))) for c in range(a.GetNumberOfTuples())))\n"
          "q = g.GetCellData().GetArray('quality')\n"
          "print(repr(q.GetTuple1(2)))\n"
          "t = g.GetPointData().GetArray('temperature')\n"
          "print(repr(t.GetTuple1(3)))\n",
      "vtk_reads_vtu");
  std::istringstream lines(output);
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "9 5") << output;
  std::getline(lines, line);
  EXPECT_EQ(line, "5 5 9 10 12") << output;
  std::getline(lines, line);
  EXPECT_EQ(line, "4 5 8 5 6 8 0 3 2 1 4 5 6 8 0 1 2 3 4 5 6 7") << output;
  std::getline(lines, line);
  EXPECT_EQ(line, "0.3333333333333333 0.5 2.0") << output;
  std::getline(lines, line);
  EXPECT_EQ(line, "int 1 2 3 4 5") << output;
  std::getline(lines, line);
  EXPECT_EQ(line, "0.3333333333333333") << output;
  std::getline(lines, line);
  EXPECT_EQ(line, "0.30000000000000004") << output;
}

TEST(VtkReadsOurVtu, ParallelIndex) {
  const std::filesystem::path dir = temp_dir();
  const MeshBundle a = mixed_mesh(), b = hex_mesh();
  WriteOptions options_a, options_b;
  options_a.cell_data.push_back({"part", {}, std::vector<std::int32_t>(a.cell_count(), 1)});
  options_b.cell_data.push_back({"part", {}, std::vector<std::int32_t>(b.cell_count(), 2)});
  write_mesh(dir / "piece_0.vtu", a, options_a);
  write_mesh(dir / "piece_1.vtu", b, options_b);
  write_file_atomic(dir / "pieces.pvtu", write_pvtu({"piece_0.vtu", "piece_1.vtu"}, options_a));
  const std::string output = run_python(
      "import vtk\n"
      "r = vtk.vtkXMLPUnstructuredGridReader()\n"
      "r.SetFileName('" +
          (dir / "pieces.pvtu").string() +
          "')\n"
          "r.Update()\n"
          "g = r.GetOutput()\n"
          "a = g.GetCellData().GetArray('part')\n"
          "print(g.GetNumberOfPoints(), g.GetNumberOfCells(), int(a.GetRange()[0]), int(a.GetRange()[1]))\n",
      "vtk_reads_pvtu");
  EXPECT_EQ(output, "36 13 1 2\n");
}

// --- VTK as an independent producer for read_vtu ---

TEST(OurReaderReadsVtkVtu, EveryEncodingIncludingZlib) {
  const std::filesystem::path dir = temp_dir();
  run_python(
      "import vtk\n"
      "pts = vtk.vtkPoints()\n"
      "pts.SetDataTypeToFloat()\n"
      "for c in [(0,0,0),(1,0,0),(1,1,0),(0,1,0),(0,0,1),(1,0,1),(1,1,1),(0,1,1),(0.5,0.5,2)]:\n"
      "    pts.InsertNextPoint(c)\n"
      "g = vtk.vtkUnstructuredGrid()\n"
      "g.SetPoints(pts)\n"
      "def add(t, ns):\n"
      "    l = vtk.vtkIdList()\n"
      "    for n in ns: l.InsertNextId(n)\n"
      "    g.InsertNextCell(t, l)\n"
      "add(12, [0,1,2,3,4,5,6,7]); add(10, [4,5,6,8]); add(9, [0,3,2,1]); add(5, [4,6,7]); add(10, [4,6,7,8])\n"
      "part = vtk.vtkIntArray()\n"
      "part.SetName('part')\n"
      "for v in [7, 8, 9, 10, 11]: part.InsertNextValue(v)\n"
      "g.GetCellData().AddArray(part)\n"
      "def write(name, mode, header64, encode=True, big=False):\n"
      "    w = vtk.vtkXMLUnstructuredGridWriter()\n"
      "    w.SetInputData(g)\n"
      "    w.SetFileName('" +
          dir.string() +
          "/' + name)\n"
          "    w.SetCompressorTypeToNone()\n"
          "    if big: w.SetByteOrderToBigEndian()\n"
          "    if header64: w.SetHeaderTypeToUInt64()\n"
          "    else: w.SetHeaderTypeToUInt32()\n"
          "    if mode == 'ascii': w.SetDataModeToAscii()\n"
          "    elif mode == 'binary': w.SetDataModeToBinary()\n"
          "    else:\n"
          "        w.SetDataModeToAppended()\n"
          "        w.SetEncodeAppendedData(encode)\n"
          "    w.Write()\n"
          "write('vtk_ascii.vtu', 'ascii', False)\n"
          "write('vtk_binary32.vtu', 'binary', False)\n"
          "write('vtk_binary64.vtu', 'binary', True)\n"
          "write('vtk_raw32.vtu', 'appended', False, False)\n"
          "write('vtk_raw64.vtu', 'appended', True, False)\n"
          "write('vtk_base64_32.vtu', 'appended', False, True)\n"
          "write('vtk_base64_64.vtu', 'appended', True, True)\n"
          "write('vtk_raw64_big.vtu', 'appended', True, False, True)\n"
          "c = vtk.vtkXMLUnstructuredGridWriter()\n"
          "c.SetInputData(g)\n"
          "c.SetFileName('" +
          dir.string() +
          "/vtk_zlib.vtu')\n"
          "c.Write()\n",
      "vtk_writes_vtu");
  for (const char* name : {"vtk_ascii.vtu", "vtk_binary32.vtu", "vtk_binary64.vtu", "vtk_raw32.vtu", "vtk_raw64.vtu",
                           "vtk_base64_32.vtu", "vtk_base64_64.vtu", "vtk_raw64_big.vtu", "vtk_zlib.vtu"}) {
    SCOPED_TRACE(name);
    const MeshBundle mesh = read_mesh(dir / name);
    ASSERT_EQ(mesh.points.size(), 9u);
    EXPECT_EQ(mesh.points[8], Vec3(0.5, 0.5, 2));
    EXPECT_EQ(mesh.hexes, (std::vector<std::array<Index, 8>>{{0, 1, 2, 3, 4, 5, 6, 7}}));
    EXPECT_EQ(mesh.tets, (std::vector<std::array<Index, 4>>{{4, 5, 6, 8}, {4, 6, 7, 8}}));
    EXPECT_EQ(mesh.quads, (std::vector<std::array<Index, 4>>{{0, 3, 2, 1}}));
    EXPECT_EQ(mesh.triangles, (std::vector<std::array<Index, 3>>{{4, 6, 7}}));
    EXPECT_EQ(mesh.hex_labels, std::vector<std::int32_t>{7});
    EXPECT_EQ(mesh.tet_labels, (std::vector<std::int32_t>{8, 11}));
    EXPECT_EQ(mesh.quad_labels, std::vector<std::int32_t>{9});
    EXPECT_EQ(mesh.triangle_labels, std::vector<std::int32_t>{10});
  }
}

}  // namespace
}  // namespace structmesh
