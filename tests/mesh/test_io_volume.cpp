// Volume and mixed mesh readers and writers (MEDIT .mesh, Gmsh .msh, VTK .vtu):
// exact round trips of a mixed mesh, files produced by the gmsh CLI and by VTK (independent
// producers; also the check of the node-order conventions and of VTK's compressed layout),
// every prefix of a valid file (truncation never crashes), and one test per malformed-input rule.
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/mesh.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace structmesh {
namespace {

using Reader = MeshBundle (*)(std::string_view, const std::string&);

std::filesystem::path temp_dir() {
  const std::filesystem::path dir = std::filesystem::path(STRUCTMESH_BINARY_DIR) / "test_tmp" / "volume_io";
  std::filesystem::create_directories(dir);
  return dir;
}

// Two hexes stacked in z, two tets on top, quads under the hexes and triangles on the
// tets' outer faces. Coordinates need all 17 significant digits, so any rounding in a
// writer shows up as a mismatch.
MeshBundle mixed_mesh() {
  MeshBundle mesh;
  const double xs[2] = {0.1, 1.0 / 3.0 + 0.5};
  const double ys[2] = {-2.0 / 7.0, 0.9};
  const double zs[3] = {1e-17, 0.6180339887498949, 1.25};
  for (const double z : zs) {
    mesh.points.emplace_back(xs[0], ys[0], z);
    mesh.points.emplace_back(xs[1], ys[0], z);
    mesh.points.emplace_back(xs[1], ys[1], z);
    mesh.points.emplace_back(xs[0], ys[1], z);
  }
  mesh.points.emplace_back(0.4, 0.3, 2.5);  // 12: apex above the top face
  mesh.hexes = {{0, 1, 2, 3, 4, 5, 6, 7}, {4, 5, 6, 7, 8, 9, 10, 11}};
  mesh.hex_labels = {3, 4};
  mesh.tets = {{8, 9, 10, 12}, {8, 10, 11, 12}};  // split of the top face, apex above: positive
  mesh.tet_labels = {5, 0};
  mesh.quads = {{0, 3, 2, 1}, {0, 1, 5, 4}};
  mesh.quad_labels = {1, 2};
  mesh.triangles = {{8, 9, 12}, {9, 10, 12}, {10, 11, 12}};
  mesh.triangle_labels = {-1, 7, 7};
  return mesh;
}

void expect_same_mesh(const MeshBundle& read, const MeshBundle& written, bool labels = true) {
  ASSERT_EQ(read.points.size(), written.points.size());
  for (std::size_t i = 0; i < read.points.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(read.points[i][k], written.points[i][k]) << "point " << i << " axis " << k;
  EXPECT_EQ(read.triangles, written.triangles);
  EXPECT_EQ(read.quads, written.quads);
  EXPECT_EQ(read.tets, written.tets);
  EXPECT_EQ(read.hexes, written.hexes);
  if (labels) {
    EXPECT_EQ(read.triangle_labels, written.triangle_labels);
    EXPECT_EQ(read.quad_labels, written.quad_labels);
    EXPECT_EQ(read.tet_labels, written.tet_labels);
    EXPECT_EQ(read.hex_labels, written.hex_labels);
  }
}

double tet_volume(const MeshBundle& mesh, const std::array<Index, 4>& t) {
  const Vec3& p0 = mesh.points[t[0]];
  return (mesh.points[t[1]] - p0).cross(mesh.points[t[2]] - p0).dot(mesh.points[t[3]] - p0) / 6.0;
}

// The smallest corner Jacobian determinant of a hex in VTK order (each corner's three
// edges in the order Verdict uses): positive for every corner of a valid hex.
double min_corner_jacobian(const MeshBundle& mesh, const std::array<Index, 8>& h) {
  static constexpr int kCorner[8][4] = {{0, 1, 3, 4}, {1, 2, 0, 5}, {2, 3, 1, 6}, {3, 0, 2, 7},
                                        {4, 7, 5, 0}, {5, 4, 6, 1}, {6, 5, 7, 2}, {7, 6, 4, 3}};
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& c : kCorner) {
    const Vec3& o = mesh.points[h[c[0]]];
    const Vec3 a = mesh.points[h[c[1]]] - o, b = mesh.points[h[c[2]]] - o, n = mesh.points[h[c[3]]] - o;
    lowest = std::min(lowest, a.cross(b).dot(n));
  }
  return lowest;
}

std::string error_of(Reader reader, std::string_view data, const std::string& name = "bad.file") {
  try {
    reader(data, name);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for:\n" << std::string(data.substr(0, 400));
  return {};
}

// Every prefix of a valid file either reads or throws InputError; the full file reads.
void expect_prefixes_safe(Reader reader, const std::string& data, std::size_t step = 1) {
  for (std::size_t n = 0; n < data.size(); n += step) {
    try {
      reader(std::string_view(data).substr(0, n), "prefix");
    } catch (const InputError&) {
    }
  }
  EXPECT_NO_THROW(reader(data, "full"));
}

// --- round trips ---

TEST(VolumeIoRoundTrip, MeditKeepsEverything) {
  const MeshBundle mesh = mixed_mesh();
  const MeshBundle back = read_medit(write_medit(mesh), "m.mesh");
  expect_same_mesh(back, mesh);
  EXPECT_EQ(back.lines.point_lines.size(), mesh.points.size());
  EXPECT_EQ(back.lines.hex_lines.size(), mesh.hexes.size());
  EXPECT_EQ(back.lines.point_lines[0], 7u);  // "MeshVersionFormatted", blank, "Dimension", blank, "Vertices", count
}

TEST(VolumeIoRoundTrip, MshKeepsEverything) {
  const MeshBundle mesh = mixed_mesh();
  const MeshBundle back = read_msh(write_msh(mesh), "m.msh");
  expect_same_mesh(back, mesh);
  EXPECT_EQ(back.lines.tet_lines.size(), mesh.tets.size());
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t pos = text.find(what); pos != std::string::npos; pos = text.find(what, pos + 1)) ++n;
  return n;
}

TEST(VolumeIoRoundTrip, VtuKeepsEverythingAndPartBecomesLabels) {
  MeshBundle mesh = mixed_mesh();
  WriteOptions options;
  DataArray part{"part", {}, {}};
  for (const auto* labels : {&mesh.triangle_labels, &mesh.quad_labels, &mesh.tet_labels, &mesh.hex_labels})
    part.i32.insert(part.i32.end(), labels->begin(), labels->end());
  options.cell_data.push_back(part);
  options.cell_data.push_back({"quality", std::vector<double>(mesh.cell_count(), 0.5), {}});
  options.point_data.push_back({"temperature", std::vector<double>(mesh.points.size(), -3.0), {}});
  const std::string vtu = write_vtu(mesh, options);
  const MeshBundle back = read_vtu(vtu, "m.vtu");
  expect_same_mesh(back, mesh);
  EXPECT_TRUE(back.lines.hex_lines.empty());

  // The "part" array carries the labels, so no "label" array is added beside it.
  EXPECT_EQ(count_of(vtu, "Name=\"label\""), 0u);
}

TEST(VolumeIoRoundTrip, VtuWritesTheBundleLabels) {
  const MeshBundle mesh = mixed_mesh();
  const std::string vtu = write_vtu(mesh);
  EXPECT_NE(vtu.find("<DataArray type=\"Int32\" Name=\"label\""), std::string::npos);
  expect_same_mesh(read_vtu(vtu, "m.vtu"), mesh);

  // Kinds without labels get 0.
  MeshBundle tets_only = mesh;
  tets_only.triangle_labels.clear();
  tets_only.quad_labels.clear();
  tets_only.hex_labels.clear();
  const MeshBundle back = read_vtu(write_vtu(tets_only), "t.vtu");
  expect_same_mesh(back, tets_only, false);
  EXPECT_EQ(back.tet_labels, tets_only.tet_labels);
  EXPECT_EQ(back.triangle_labels, std::vector<std::int32_t>(3, 0));
  EXPECT_EQ(back.hex_labels, std::vector<std::int32_t>(2, 0));

  // A bundle without labels gets no "label" array and reads back without labels.
  MeshBundle unlabeled = mesh;
  unlabeled.triangle_labels.clear();
  unlabeled.tet_labels.clear();
  unlabeled.quad_labels.clear();
  unlabeled.hex_labels.clear();
  const std::string plain = write_vtu(unlabeled);
  EXPECT_EQ(count_of(plain, "Name=\"label\""), 0u);
  expect_same_mesh(read_vtu(plain, "u.vtu"), unlabeled);

  // A caller's own "label" array wins, even a floating-point one (which is not read as labels).
  WriteOptions own;
  own.cell_data.push_back({"label", std::vector<double>(mesh.cell_count(), 2.5), {}});
  const std::string theirs = write_vtu(mesh, own);
  EXPECT_EQ(count_of(theirs, "Name=\"label\""), 1u);
  EXPECT_NE(theirs.find("<DataArray type=\"Float64\" Name=\"label\""), std::string::npos);
  EXPECT_TRUE(read_vtu(theirs, "f.vtu").hex_labels.empty());
}

TEST(VolumeIoRoundTrip, MeditReferencesSurviveConversionToVtu) {
  const MeshBundle mesh = mixed_mesh();
  const std::filesystem::path medit = temp_dir() / "refs.mesh", vtu = temp_dir() / "refs.vtu";
  write_mesh(medit, mesh);
  write_mesh(vtu, read_mesh(medit));
  expect_same_mesh(read_mesh(vtu), mesh);
}

TEST(VolumeIoRoundTrip, ThroughFilesByExtension) {
  const MeshBundle mesh = mixed_mesh();
  for (const char* name : {"mixed.mesh", "mixed.msh"}) {
    const std::filesystem::path path = temp_dir() / name;
    write_mesh(path, mesh);
    const MeshBundle back = read_mesh(path);
    expect_same_mesh(back, mesh);
    EXPECT_EQ(back.source_name, path.string());
  }
  const std::filesystem::path vtu = temp_dir() / "mixed.vtu";
  write_mesh(vtu, mesh);
  expect_same_mesh(read_mesh(vtu), mesh);
}

TEST(VolumeIoRoundTrip, EmptyAndPointOnlyBundles) {
  MeshBundle points_only;
  points_only.points = {Vec3(1, 2, 3), Vec3(4, 5, 6)};
  for (const MeshBundle& mesh : {MeshBundle{}, points_only}) {
    expect_same_mesh(read_msh(write_msh(mesh), "e.msh"), mesh);
    expect_same_mesh(read_vtu(write_vtu(mesh), "e.vtu"), mesh);
    expect_same_mesh(read_medit(write_medit(mesh), "e.mesh"), mesh);
  }
}

TEST(VolumeIoRoundTrip, MshKeepsOrderWithInterleavedLabels) {
  MeshBundle mesh = mixed_mesh();
  mesh.triangle_labels = {1, 2, 1};  // three blocks on two entities
  const MeshBundle back = read_msh(write_msh(mesh), "m.msh");
  expect_same_mesh(back, mesh);
}

TEST(VolumeIoWriters, RejectInconsistentBundles) {
  MeshBundle bad_index = mixed_mesh();
  bad_index.tets[1][3] = 13;
  EXPECT_THROW(write_medit(bad_index), Error);
  EXPECT_THROW(write_msh(bad_index), Error);
  EXPECT_THROW(write_vtu(bad_index), Error);
  MeshBundle bad_labels = mixed_mesh();
  bad_labels.hex_labels.pop_back();
  EXPECT_THROW(write_msh(bad_labels), Error);
}

TEST(VolumeIoWriters, VtuRejectsDataArraysOfTheWrongSize) {
  const MeshBundle mesh = mixed_mesh();
  WriteOptions cells;
  cells.cell_data.push_back({"part", {}, std::vector<std::int32_t>(mesh.cell_count() - 1, 1)});
  try {
    write_vtu(mesh, cells);
    FAIL() << "no Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'part' has 8 values, expected 9"), std::string::npos) << e.what();
  }
  WriteOptions points;
  points.point_data.push_back({"t", std::vector<double>(mesh.points.size() + 1, 0.0), {}});
  EXPECT_THROW(write_vtu(mesh, points), Error);
  WriteOptions both;
  both.cell_data.push_back({"x", std::vector<double>(mesh.cell_count()), std::vector<std::int32_t>(mesh.cell_count())});
  EXPECT_THROW(write_vtu(mesh, both), Error);
}

TEST(VolumeIoWriters, VtuLayout) {
  const MeshBundle mesh = mixed_mesh();
  const std::string vtu = write_vtu(mesh);
  EXPECT_NE(vtu.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(vtu.find("byte_order=\"LittleEndian\""), std::string::npos);
  EXPECT_NE(vtu.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  EXPECT_NE(vtu.find("NumberOfPoints=\"13\" NumberOfCells=\"9\""), std::string::npos);
  // The types block is the last one: 3 triangles, 2 quads, 2 tets, 2 hexes.
  const std::string types = "\x05\x05\x05\x09\x09\x0a\x0a\x0c\x0c";
  EXPECT_NE(vtu.find(types + "\n  </AppendedData>"), std::string::npos);
}

TEST(VolumeIoWriters, PvtuDeclaresPiecesAndArrays) {
  WriteOptions options;
  options.cell_data.push_back({"part", {}, {1}});
  options.point_data.push_back({"t&x", {1.0}, {}});
  const std::string pvtu = write_pvtu({"a_0.vtu", "a_1.vtu"}, options);
  EXPECT_NE(pvtu.find("type=\"PUnstructuredGrid\""), std::string::npos);
  EXPECT_NE(pvtu.find("<Piece Source=\"a_0.vtu\"/>"), std::string::npos);
  EXPECT_NE(pvtu.find("<Piece Source=\"a_1.vtu\"/>"), std::string::npos);
  EXPECT_NE(pvtu.find("<PDataArray type=\"Int32\" Name=\"part\"/>"), std::string::npos);
  EXPECT_NE(pvtu.find("<PDataArray type=\"Float64\" Name=\"t&amp;x\"/>"), std::string::npos);
  EXPECT_NE(pvtu.find("<PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>"), std::string::npos);
  EXPECT_THROW(write_pvtu({}, options), Error);
  EXPECT_NE(error_of(read_vtu, pvtu).find("read its .vtu pieces"), std::string::npos);
}

// --- files written by Gmsh (independent producer; node-order conventions) ---

// A unit box: hexes when `hexes` (transfinite + recombined extrusion), else tets.
void write_box_geo(const std::filesystem::path& path, bool hexes) {
  std::ofstream geo(path);
  if (hexes) {
    geo << "Point(1)={0,0,0,1}; Point(2)={1,0,0,1}; Point(3)={1,1,0,1}; Point(4)={0,1,0,1};\n"
           "Line(1)={1,2}; Line(2)={2,3}; Line(3)={3,4}; Line(4)={4,1};\n"
           "Curve Loop(1)={1,2,3,4}; Plane Surface(1)={1};\n"
           "Transfinite Curve{1,2,3,4}=3; Transfinite Surface{1}; Recombine Surface{1};\n"
           "Extrude {0,0,1} { Surface{1}; Layers{2}; Recombine; }\n";
  } else {
    geo << "SetFactory(\"OpenCASCADE\");\nBox(1) = {0,0,0,1,1,1};\nMesh.MeshSizeMax = 0.5;\n";
  }
}

void run_gmsh(const std::filesystem::path& geo, const std::string& options, const std::filesystem::path& out) {
  ASSERT_EQ(std::system("command -v gmsh > /dev/null 2>&1"), 0) << "the gmsh CLI is required (Debian: gmsh)";
  const std::string command =
      "gmsh '" + geo.string() + "' -3 " + options + " -o '" + out.string() + "' > '" + out.string() + ".log' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
}

TEST(VolumeIoGmsh, BinaryMsh41HexBoxReadsWithPositiveHexes) {
  const std::filesystem::path geo = temp_dir() / "hexbox.geo", msh = temp_dir() / "hexbox_bin.msh";
  write_box_geo(geo, true);
  run_gmsh(geo, "-format msh41 -bin", msh);
  const std::string data = read_file(msh);
  ASSERT_NE(data.find("4.1 1 8"), std::string::npos) << "gmsh did not write binary MSH 4.1";
  const MeshBundle mesh = read_msh(data, msh.string());
  EXPECT_EQ(mesh.points.size(), 27u);
  ASSERT_EQ(mesh.hexes.size(), 8u);
  EXPECT_EQ(mesh.quads.size(), 24u);  // the six boundary faces, 2 x 2 each
  EXPECT_TRUE(mesh.lines.hex_lines.empty());
  for (const auto& h : mesh.hexes) EXPECT_NEAR(min_corner_jacobian(mesh, h), 0.125, 1e-9);
  for (const std::int32_t label : mesh.hex_labels) EXPECT_EQ(label, 1);  // the one volume entity

  // The same box as ASCII 4.1, ASCII 2.2 and MEDIT gives the same mesh.
  for (const std::string format : {"msh41", "msh22", "mesh"}) {
    const bool medit = format == "mesh";
    const std::filesystem::path out = temp_dir() / ("hexbox_" + format + (medit ? ".mesh" : ".msh"));
    run_gmsh(geo, medit ? "" : "-format " + format, out);
    const MeshBundle other = read_mesh(out);
    EXPECT_EQ(other.hexes, mesh.hexes) << format;
    ASSERT_EQ(other.points.size(), mesh.points.size()) << format;
    for (std::size_t i = 0; i < mesh.points.size(); ++i) EXPECT_LT((other.points[i] - mesh.points[i]).norm(), 1e-12);
  }
}

TEST(VolumeIoGmsh, TetsFromGmshArePositiveInEveryFormat) {
  const std::filesystem::path geo = temp_dir() / "tetbox.geo";
  write_box_geo(geo, false);
  for (const char* format : {"msh41", "msh41 -bin", "msh22", "mesh"}) {
    const bool medit = std::string(format) == "mesh";
    std::string file = std::string("tetbox_") + format;
    for (char& c : file)
      if (c == ' ') c = '_';
    const std::filesystem::path out = temp_dir() / (file + (medit ? ".mesh" : ".msh"));
    run_gmsh(geo, medit ? "" : std::string("-format ") + format, out);
    const MeshBundle mesh = read_mesh(out);
    ASSERT_GT(mesh.tets.size(), 100u) << format;
    double volume = 0;
    for (const auto& t : mesh.tets) {
      const double v = tet_volume(mesh, t);
      EXPECT_GT(v, 0.0) << format;
      volume += v;
    }
    EXPECT_NEAR(volume, 1.0, 1e-9) << format;
    EXPECT_FALSE(mesh.triangles.empty()) << format;
  }
}

// --- files written by VTK with its zlib compressor (ParaView's and VTK's default) ---

void run_python(const std::string& script, const std::filesystem::path& py) {
  ASSERT_EQ(std::system("/usr/bin/python3 -c 'import vtk' > /dev/null 2>&1"), 0)
      << "/usr/bin/python3 with the vtk module (Debian: python3-vtk9) is required";
  std::ofstream(py) << script;
  const std::string command = "/usr/bin/python3 '" + py.string() + "' > '" + py.string() + ".log' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
}

struct VtkMode {
  const char* name;
  const char* setup;  // Python statements configuring the writer `w`
};

// ascii is never compressed; the others are, header and blocks alike. A 64-byte block
// size splits every array of the mixed mesh but the types into several blocks.
constexpr VtkMode kVtkModes[] = {
    {"ascii", "w.SetDataModeToAscii()"},
    {"binary32", "w.SetDataModeToBinary(); w.SetHeaderTypeToUInt32()"},
    {"binary64", "w.SetDataModeToBinary(); w.SetHeaderTypeToUInt64()"},
    {"raw32", "w.SetDataModeToAppended(); w.EncodeAppendedDataOff(); w.SetHeaderTypeToUInt32()"},
    {"raw64", "w.SetDataModeToAppended(); w.EncodeAppendedDataOff(); w.SetHeaderTypeToUInt64()"},
    {"base64_32", "w.SetDataModeToAppended(); w.EncodeAppendedDataOn(); w.SetHeaderTypeToUInt32()"},
    {"base64_64", "w.SetDataModeToAppended(); w.EncodeAppendedDataOn(); w.SetHeaderTypeToUInt64()"},
    {"binary32_blocks", "w.SetDataModeToBinary(); w.SetHeaderTypeToUInt32(); w.SetBlockSize(64)"},
    {"binary64_blocks", "w.SetDataModeToBinary(); w.SetHeaderTypeToUInt64(); w.SetBlockSize(64)"},
    {"raw32_blocks",
     "w.SetDataModeToAppended(); w.EncodeAppendedDataOff(); w.SetHeaderTypeToUInt32(); w.SetBlockSize(64)"},
    {"raw64_blocks",
     "w.SetDataModeToAppended(); w.EncodeAppendedDataOff(); w.SetHeaderTypeToUInt64(); w.SetBlockSize(64)"},
    {"base64_32_blocks",
     "w.SetDataModeToAppended(); w.EncodeAppendedDataOn(); w.SetHeaderTypeToUInt32(); w.SetBlockSize(64)"},
    {"base64_64_blocks",
     "w.SetDataModeToAppended(); w.EncodeAppendedDataOn(); w.SetHeaderTypeToUInt64(); w.SetBlockSize(64)"},
    {"raw64_big_endian",
     "w.SetDataModeToAppended(); w.EncodeAppendedDataOff(); w.SetHeaderTypeToUInt64(); w.SetBlockSize(64); "
     "w.SetByteOrderToBigEndian()"},
};

// VTK reads our mixed mesh (with its "label" array) and writes it back in every mode;
// returns the path of each file, named <mode>.vtu.
std::filesystem::path write_with_vtk(const std::string& name) {
  const std::filesystem::path dir = temp_dir() / name;
  std::filesystem::create_directories(dir);
  write_mesh(dir / "input.vtu", mixed_mesh());
  std::string script =
      "import vtk\n"
      "r = vtk.vtkXMLUnstructuredGridReader()\n"
      "r.SetFileName('" +
      (dir / "input.vtu").string() +
      "')\n"
      "r.Update()\n"
      "def write(mode, setup):\n"
      "    w = vtk.vtkXMLUnstructuredGridWriter()\n"
      "    w.SetInputConnection(r.GetOutputPort())\n"
      "    w.SetCompressorTypeToZLib()\n"
      "    exec(setup)\n"
      "    w.SetFileName('" +
      dir.string() +
      "/' + mode + '.vtu')\n"
      "    assert w.Write() == 1\n";
  for (const VtkMode& mode : kVtkModes) script += "write('" + std::string(mode.name) + "', '" + mode.setup + "')\n";
  run_python(script, dir / "write.py");
  return dir;
}

// Position of the Points array's block in a file with raw appended data.
std::size_t points_block(const std::string& vtu) {
  const std::size_t data = vtu.find('_', vtu.find("<AppendedData")) + 1;
  const std::size_t offset = vtu.find("offset=\"", vtu.find("Name=\"Points\"")) + 8;
  return data + std::stoull(vtu.substr(offset, 20));
}

TEST(VtuCompressed, EveryModeWrittenByVtkReadsBackExactly) {
  const std::filesystem::path dir = write_with_vtk("vtk_zlib");
  const MeshBundle mesh = mixed_mesh();
  for (const VtkMode& mode : kVtkModes) {
    const std::filesystem::path path = dir / (std::string(mode.name) + ".vtu");
    const std::string data = read_file(path);
    EXPECT_NE(data.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos) << mode.name;
    SCOPED_TRACE(mode.name);
    expect_same_mesh(read_mesh(path), mesh);
  }
  // The block-size setting took effect: the points' header announces several blocks.
  const std::string raw = read_file(dir / "raw64_blocks.vtu");
  std::uint64_t blocks = 0;
  std::memcpy(&blocks, raw.data() + points_block(raw), sizeof blocks);
  EXPECT_EQ(blocks, 5u);  // 13 x 24 bytes in blocks of 64
}

TEST(VtuCompressed, EveryPrefixReadsOrThrowsInputError) {
  const std::filesystem::path dir = write_with_vtk("vtk_zlib_prefix");
  for (const char* mode : {"binary32_blocks", "raw64_blocks", "base64_64_blocks"})
    expect_prefixes_safe(read_vtu, read_file(dir / (std::string(mode) + ".vtu")));
}

TEST(VtuCompressed, Errors) {
  const std::filesystem::path dir = write_with_vtk("vtk_zlib_errors");
  // Raw appended, UInt64 header: the points' header is [blocks, block size, last block
  // size, compressed sizes...], then the zlib streams.
  const std::string vtu = read_file(dir / "raw64_blocks.vtu");
  const std::size_t header = points_block(vtu);
  std::uint64_t blocks = 0;
  std::memcpy(&blocks, vtu.data() + header, sizeof blocks);
  ASSERT_GT(blocks, 1u);
  ASSERT_LT(blocks, 100u);
  const std::size_t stream = header + 8 * (3 + blocks);
  const auto with_value = [&](std::size_t field, std::uint64_t value) {
    std::string changed = vtu;
    std::memcpy(changed.data() + header + 8 * field, &value, sizeof value);
    return changed;
  };

  // Cut inside the compressed blocks.
  EXPECT_NE(error_of(read_vtu, vtu.substr(0, stream + 10)).find("runs past the end (truncated?)"), std::string::npos);
  EXPECT_NE(error_of(read_vtu, vtu.substr(0, header + 20)).find("compression header runs past the end"),
            std::string::npos);
  // A corrupted zlib stream: its header byte, then a byte inside the deflate data.
  std::string corrupt = vtu;
  corrupt[stream] = '\x00';
  EXPECT_NE(error_of(read_vtu, corrupt).find("compressed block 0 of " + std::to_string(blocks) + " is corrupt (zlib:"),
            std::string::npos);
  corrupt = vtu;
  corrupt[stream + 5] = static_cast<char>(corrupt[stream + 5] ^ 0x5a);
  EXPECT_NE(error_of(read_vtu, corrupt).find("is corrupt (zlib:"), std::string::npos);
  // A header whose sizes do not match the streams.
  EXPECT_NE(error_of(read_vtu, with_value(2, 48)).find("compressed block 4 of 5 is corrupt"), std::string::npos);
  // Implausible sizes: a block count, a compressed size, an uncompressed size.
  EXPECT_NE(error_of(read_vtu, with_value(0, 1ull << 40)).find("compression header for 1099511627776 blocks"),
            std::string::npos);
  EXPECT_NE(error_of(read_vtu, with_value(3, 1ull << 40)).find("compressed block 0 of"), std::string::npos);
  EXPECT_NE(error_of(read_vtu, with_value(1, 1ull << 40)).find("decompressed size implausible"), std::string::npos);
  EXPECT_NE(error_of(read_vtu, with_value(1, 1u << 20)).find("decompressed size implausible"), std::string::npos);
  EXPECT_NE(error_of(read_vtu, with_value(2, 1u << 20)).find("larger than the block size"), std::string::npos);
  EXPECT_NE(error_of(read_vtu, with_value(2, 52)).find("not a multiple of the value size"), std::string::npos);
  EXPECT_NE(error_of(read_vtu, with_value(1, 32)).find("larger than the block size"), std::string::npos);
  // Inline base64: the same checks behind the encoding.
  const std::string binary = read_file(dir / "binary64_blocks.vtu");
  const std::size_t inline_data = binary.find("format=\"binary\"");
  ASSERT_NE(inline_data, std::string::npos);
  const std::size_t text = binary.find('>', inline_data) + 1;
  const std::size_t text_end = binary.find('<', text);
  std::string cut = binary;
  cut.erase(text + (text_end - text) / 2, (text_end - text) / 2);
  EXPECT_NE(error_of(read_vtu, cut).find("truncated"), std::string::npos);
  // Other compressors are named.
  for (const std::string other : {"vtkLZ4DataCompressor", "vtkLZMADataCompressor"}) {
    std::string changed = vtu;
    changed.replace(changed.find("vtkZLibDataCompressor"), 21, other);
    EXPECT_NE(error_of(read_vtu, changed).find("VTU compressor '" + other + "' is not supported"), std::string::npos);
  }
}

// --- truncation: every prefix of a valid file is handled ---

TEST(VolumeIoTruncation, EveryPrefixReadsOrThrowsInputError) {
  MeshBundle mesh = mixed_mesh();
  expect_prefixes_safe(read_medit, write_medit(mesh));
  expect_prefixes_safe(read_msh, write_msh(mesh));
  expect_prefixes_safe(read_vtu, write_vtu(mesh));
  const std::filesystem::path geo = temp_dir() / "hexbox_trunc.geo", msh = temp_dir() / "hexbox_trunc.msh";
  write_box_geo(geo, true);
  run_gmsh(geo, "-format msh41 -bin", msh);
  expect_prefixes_safe(read_msh, read_file(msh));
}

// --- MEDIT reader ---

TEST(MeditReader, SkipsOtherSectionsCommentsAndReadsTwoDimensions) {
  const std::string data =
      "# a comment\n"
      "meshversionformatted 1\n"
      "Dimension 2\n"
      "Vertices\n4\n0 0 1\n1 0 1\n1 1 2\n0 1 2 # trailing comment\n"
      "Edges\n2\n1 2 5\n2 3 5\n"
      "Corners\n1\n1\n"
      "Normals\n1\n0 1\n"
      "SomeFutureKeyword\n3\n1 2 3\n"
      "RequiredVertices 2 1 2\n"
      "Quadrilaterals\n1\n1 2 3 4 9\n"
      "Triangles\n2\n1 2 3 7\n1 3 4 8\n"
      "END\n"
      "anything after End is ignored\n";
  const MeshBundle mesh = read_medit(data, "2d.mesh");
  ASSERT_EQ(mesh.points.size(), 4u);
  EXPECT_EQ(mesh.points[2], Vec3(1, 1, 0));
  EXPECT_EQ(mesh.quads, (std::vector<std::array<Index, 4>>{{0, 1, 2, 3}}));
  EXPECT_EQ(mesh.quad_labels, std::vector<std::int32_t>{9});
  EXPECT_EQ(mesh.triangle_labels, (std::vector<std::int32_t>{7, 8}));
  EXPECT_EQ(mesh.lines.triangle_lines, (std::vector<std::uint32_t>{29, 30}));
  EXPECT_EQ(mesh.lines.point_lines[3], 9u);
}

TEST(MeditReader, Errors) {
  const std::string head = "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n";
  EXPECT_NE(error_of(read_medit, "").find("bad.file:1: empty file"), std::string::npos);
  EXPECT_NE(error_of(read_medit, "   \n# only a comment\n").find("empty file"), std::string::npos);
  EXPECT_NE(error_of(read_medit, "solid x\nfacet\n").find("not a MEDIT file"), std::string::npos);
  EXPECT_NE(error_of(read_medit, std::string("\1\0\0\0\2\0\0\0", 8)).find("binary MEDIT (.meshb)"), std::string::npos);
  // Truncated inside the vertices (the count alone does not give it away).
  EXPECT_NE(error_of(read_medit, "MeshVersionFormatted 2\nDimension 3\nVertices\n2\n0.5000 0.5000 0.5000 1\n0.25")
                .find("bad.file:6: unexpected end of file"),
            std::string::npos);
  EXPECT_NE(error_of(read_medit, head.substr(0, head.size() - 12)).find("too short for them (truncated?)"),
            std::string::npos);
  // An index beyond the vertex count: named with the element, the index and the line.
  EXPECT_NE(error_of(read_medit, head + "Tetrahedra\n2\n1 2 3 4 0\n1 2 3 5 0\nEnd\n")
                .find("bad.file:12: tetrahedron 2 refers to vertex 5 of 4"),
            std::string::npos);
  EXPECT_NE(error_of(read_medit, head + "Triangles\n1\n0 1 2 0\n").find("bad.file:11: triangle 1 refers to vertex 0"),
            std::string::npos);
  // NaN and infinite coordinates.
  EXPECT_NE(error_of(read_medit, "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 nan 0 0\n").find("bad.file:5:"),
            std::string::npos);
  EXPECT_NE(error_of(read_medit, "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 inf 0 0\n").find("not finite"),
            std::string::npos);
  // A count that does not match the rows.
  EXPECT_NE(error_of(read_medit, head + "Triangles\n1\n1 2 3 0\n1 2 4 0\nEnd\n").find("does the section's count match"),
            std::string::npos);
  // An absurd count is rejected before anything is allocated.
  EXPECT_NE(error_of(read_medit, "MeshVersionFormatted 2\nDimension 3\nVertices\n999999999999999\n0 0 0 0\n")
                .find("too short"),
            std::string::npos);
  EXPECT_NE(error_of(read_medit, head + "Hexahedra\n-1\n").find("negative count"), std::string::npos);
  EXPECT_NE(error_of(read_medit, head + "Prisms\n1\n1 2 3 4 1 2 0\n").find("'Prisms' is not supported"),
            std::string::npos);
  EXPECT_NE(error_of(read_medit, head + "TetrahedraP2\n0\n").find("higher-order"), std::string::npos);
  EXPECT_NE(error_of(read_medit, "MeshVersionFormatted 2\nDimension 4\n").find("Dimension must be 2 or 3"),
            std::string::npos);
  EXPECT_NE(error_of(read_medit, head + "Triangles\n1\n1 2 3 99999999999\n").find("does not fit in 32 bits"),
            std::string::npos);
  EXPECT_NE(error_of(read_medit, "MeshVersionFormatted 2\nDimension 3\nEnd\n").find("no Vertices section"),
            std::string::npos);
}

// --- Gmsh reader ---

TEST(MshReader, SparseNodeTagsAreMapped) {
  const std::string data =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
      "$PhysicalNames\n1\n3 1 \"v\"\n$EndPhysicalNames\n"
      "$Nodes\n2 4 5 9000000000\n"
      "0 1 0 1\n9000000000\n1 2 3\n"
      "3 7 1 3\n77\n5\n123456\n4 5 6 0.1 0.2 0.3\n7 8 9 0 0 0\n1 1 1 0 0 0\n"
      "$EndNodes\n"
      "$Elements\n2 2 1 2\n0 1 15 1\n1 77\n3 7 4 1\n2 9000000000 77 5 123456\n$EndElements\n"
      "$NodeData\n1\n\"x\"\n$EndNodeData\n";
  const MeshBundle mesh = read_msh(data, "sparse.msh");
  ASSERT_EQ(mesh.points.size(), 4u);
  EXPECT_EQ(mesh.points[1], Vec3(4, 5, 6));  // parametric coordinates skipped
  EXPECT_EQ(mesh.tets, (std::vector<std::array<Index, 4>>{{0, 1, 2, 3}}));
  EXPECT_EQ(mesh.tet_labels, std::vector<std::int32_t>{7});
  EXPECT_EQ(mesh.lines.tet_lines, std::vector<std::uint32_t>{26});
}

TEST(MshReader, ReadsAsciiVersion22) {
  const std::string data =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
      "$Nodes\n5\n10 0 0 0\n20 1 0 0\n30 0 1 0\n40 0 0 1\n50 1 1 1\n$EndNodes\n"
      "$Elements\n3\n1 15 2 0 1 10\n2 4 2 9 3 10 20 30 40\n3 2 3 9 4 0 20 30 50\n$EndElements\n";
  const MeshBundle mesh = read_msh(data, "v2.msh");
  EXPECT_EQ(mesh.tets, (std::vector<std::array<Index, 4>>{{0, 1, 2, 3}}));
  EXPECT_EQ(mesh.tet_labels, std::vector<std::int32_t>{3});  // the elementary (entity) tag
  EXPECT_EQ(mesh.triangles, (std::vector<std::array<Index, 3>>{{1, 2, 4}}));
  EXPECT_EQ(mesh.triangle_labels, std::vector<std::int32_t>{4});
}

TEST(MshReader, Errors) {
  const std::string head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  const std::string nodes = "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n";
  EXPECT_NE(error_of(read_msh, "").find("empty file"), std::string::npos);
  EXPECT_NE(error_of(read_msh, "hello\n").find("not a Gmsh .msh file"), std::string::npos);
  EXPECT_NE(error_of(read_msh, head).find("no $Nodes section"), std::string::npos);
  // Truncated inside the nodes: caught by the count check, or while reading.
  EXPECT_NE(error_of(read_msh, head + nodes.substr(0, 40)).find("bad.file:6: node count 4 exceeds what the file holds"),
            std::string::npos);
  EXPECT_NE(error_of(read_msh, head + "$Nodes\n1 2 1 2\n3 1 0 2\n1\n2\n0.0000 0.0000 0.0000\n1.0000")
                .find("bad.file:10: unexpected end of file, expected node y coordinate"),
            std::string::npos);
  // A node tag that does not exist, with the element's line.
  EXPECT_NE(error_of(read_msh, head + nodes + "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 9\n$EndElements\n")
                .find("bad.file:19: element 1 (tetrahedron) refers to node 9, which is not in $Nodes"),
            std::string::npos);
  EXPECT_NE(error_of(read_msh, head + "$Nodes\n1 1 1 1\n0 1 0 1\n1\n0 NaN 0\n$EndNodes\n").find("bad.file:8:"),
            std::string::npos);
  // Wrong counts.
  EXPECT_NE(error_of(read_msh, head + "$Nodes\n1 5 1 4\n3 1 0 1\n1\n0 0 0\n$EndNodes\n")
                .find("$Nodes declares 5 nodes but its blocks hold 1"),
            std::string::npos);
  EXPECT_NE(error_of(read_msh, head + nodes + "$Elements\n1 1 1 1\n3 1 4 2\n1 1 2 3 4\n$EndElements\n")
                .find("expected element tag, found '$EndElements'"),
            std::string::npos);
  EXPECT_NE(error_of(read_msh, head + nodes + "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n2 1 2 3 4\n$EndElements\n")
                .find("expected '$EndElements'"),
            std::string::npos);
  EXPECT_NE(error_of(read_msh, head + "$Nodes\n1 99999999999 1 1\n3 1 0 99999999999\n1\n").find("exceeds"),
            std::string::npos);
  EXPECT_NE(error_of(read_msh, head + nodes + "$Elements\n1 1 1 1\n3 1 6 1\n1 1 2 3 4 1 2\n$EndElements\n")
                .find("element type 6 (6-node prism) is not supported"),
            std::string::npos);
  EXPECT_NE(error_of(read_msh, head + nodes + "$Elements\n1 1 1 1\n3 1 11 1\n1 1 2 3 4 1 2 3 4 1 2\n$EndElements\n")
                .find("Mesh.ElementOrder = 1"),
            std::string::npos);
  EXPECT_NE(error_of(read_msh, head + "$Nodes\n1 2 1 1\n3 1 0 2\n1\n1\n0 0 0\n1 1 1\n$EndNodes\n")
                .find("node tag 1 appears twice"),
            std::string::npos);
  EXPECT_NE(error_of(read_msh, head + nodes + "$Comments\nno end\n").find("has no $EndComments"), std::string::npos);
  EXPECT_NE(error_of(read_msh, "$MeshFormat\n4 0 8\n$EndMeshFormat\n").find("MSH 4.0 is not supported"),
            std::string::npos);
  EXPECT_NE(error_of(read_msh, "$MeshFormat\n2.2 1 8\n").find("binary MSH 2 is not supported"), std::string::npos);
}

TEST(MshReader, BinaryErrors) {
  const std::filesystem::path geo = temp_dir() / "hexbox_err.geo", msh = temp_dir() / "hexbox_err.msh";
  write_box_geo(geo, true);
  run_gmsh(geo, "-format msh41 -bin", msh);
  const std::string data = read_file(msh);
  // Cut inside the element blocks: the message says what is missing and has no line.
  const std::size_t elements = data.find("$Elements\n");
  ASSERT_NE(elements, std::string::npos);
  const std::string cut = error_of(read_msh, std::string_view(data).substr(0, elements + 200));
  EXPECT_NE(cut.find("bad.file: "), std::string::npos) << cut;
  EXPECT_NE(cut.find("truncated"), std::string::npos) << cut;
  // A NaN coordinate in the first node (after the node header and the first block's header and tag).
  std::string nan = data;
  const std::size_t first_x = nan.find("$Nodes\n") + 7 + 4 * 8 + 3 * 4 + 8 + 8;
  const double q = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(nan.data() + first_x, &q, sizeof q);
  EXPECT_NE(error_of(read_msh, nan).find("not finite"), std::string::npos);
  // An element block with an absurd count.
  std::string absurd = data;
  const std::uint64_t huge = 1ull << 60;
  std::memcpy(absurd.data() + elements + 10 + 4 * 8 + 3 * 4, &huge, sizeof huge);
  EXPECT_NE(error_of(read_msh, absurd).find("too short"), std::string::npos);
}

// --- VTU reader ---

std::string ascii_vtu(const std::string& points, const std::string& connectivity, const std::string& offsets,
                      const std::string& types, int point_count, int cell_count, const std::string& extra = "") {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\"" + extra +
         ">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"" + std::to_string(point_count) + "\" NumberOfCells=\"" +
         std::to_string(cell_count) +
         "\">\n<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">\n" + points +
         "\n</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n" +
         connectivity + "\n</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n" + offsets +
         "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n" + types +
         "\n</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

TEST(VtuReader, AsciiWithVoxelAndLabelArray) {
  std::string vtu = ascii_vtu("0 0 0 1 0 0 0 1 0 1 1 0 0 0 1 1 0 1 0 1 1 1 1 1", "0 1 2 3 4 5 6 7", "8", "11", 8, 1);
  vtu.insert(vtu.find("<Points>"),
             "<CellData><DataArray type=\"Float64\" Name=\"part\" format=\"ascii\">1.5</DataArray>"
             "<DataArray type=\"Int64\" Name=\"label\" format=\"ascii\">-4</DataArray></CellData>\n");
  const MeshBundle mesh = read_vtu(vtu, "voxel.vtu");
  // A voxel's nodes are x-then-y-then-z; the hex is a ring at the bottom then the top.
  EXPECT_EQ(mesh.hexes, (std::vector<std::array<Index, 8>>{{0, 1, 3, 2, 4, 5, 7, 6}}));
  EXPECT_GT(min_corner_jacobian(mesh, mesh.hexes[0]), 0.0);
  EXPECT_EQ(mesh.hex_labels, std::vector<std::int32_t>{-4});  // the float "part" is not a label array
}

TEST(VtuReader, Errors) {
  const std::string pts = "0 0 0 1 0 0 0 1 0 0 0 1";
  EXPECT_NE(error_of(read_vtu, "").find("empty file"), std::string::npos);
  EXPECT_NE(error_of(read_vtu, "<?xml version=\"1.0\"?><html></html>").find("not a VTK XML file"), std::string::npos);
  // ascii arrays are never compressed, whatever the compressor.
  EXPECT_EQ(read_vtu(ascii_vtu(pts, "0 1 2 3", "4", "10", 4, 1, " compressor=\"vtkZLibDataCompressor\""), "z.vtu")
                .tets.size(),
            1u);
  EXPECT_NE(error_of(read_vtu, ascii_vtu(pts, "0 1 2 3", "4", "10", 4, 1, " compressor=\"vtkBZip2\""))
                .find("VTU compressor 'vtkBZip2' is not supported"),
            std::string::npos);
  // A point index out of range: named with the cell, the index, and the connectivity array's line.
  EXPECT_NE(error_of(read_vtu, ascii_vtu(pts, "0 1 2 9", "4", "10", 4, 1))
                .find("bad.file:11: cell 0 (tetrahedron) refers to point 9 of 4"),
            std::string::npos);
  EXPECT_NE(error_of(read_vtu, ascii_vtu("0 0 0 1 0 0 0 nan 0 0 0 1", "0 1 2 3", "4", "10", 4, 1)).find("not finite"),
            std::string::npos);
  EXPECT_NE(error_of(read_vtu, ascii_vtu(pts, "0 1 2 3", "4", "10", 5, 1)).find("Points holds 12 values"),
            std::string::npos);
  EXPECT_NE(error_of(read_vtu, ascii_vtu(pts, "0 1 2 3", "4", "10 10", 4, 1)).find("types holds 2 values for 1 cells"),
            std::string::npos);
  EXPECT_NE(error_of(read_vtu, ascii_vtu(pts, "0 1 2 3", "3", "10", 4, 1)).find("offsets give 3 nodes, expected 4"),
            std::string::npos);
  EXPECT_NE(error_of(read_vtu, ascii_vtu(pts, "0 1 2 3 0", "4", "10", 4, 1)).find("connectivity holds 5 values"),
            std::string::npos);
  EXPECT_NE(error_of(read_vtu, ascii_vtu(pts, "0 1 2 3 1 2", "6", "13", 4, 1)).find("VTK cell type 13 (wedge)"),
            std::string::npos);
  EXPECT_NE(error_of(read_vtu, ascii_vtu(pts, "0 1 2 3", "4", "10", 4, 1).substr(0, 200)).find("unterminated"),
            std::string::npos);
  // Appended raw data cut short.
  const std::string vtu = write_vtu(mixed_mesh());
  EXPECT_NE(error_of(read_vtu, vtu.substr(0, vtu.size() - 40)).find("truncated"), std::string::npos);
  // An absurd block size in the first appended header.
  std::string absurd = vtu;
  const std::size_t data = absurd.find('_', absurd.find("<AppendedData")) + 1;
  absurd[data + 7] = '\x7f';
  EXPECT_NE(error_of(read_vtu, absurd).find("runs past the end"), std::string::npos);
  // Two pieces sharing one appended block would let a small file demand a lot of memory.
  MeshBundle cloud;
  for (int i = 0; i < 1000; ++i) cloud.points.emplace_back(i, 0, 0);
  std::string shared = write_vtu(cloud);
  const std::size_t piece = shared.find("    <Piece"), piece_end = shared.find("</Piece>\n") + 9;
  shared.insert(piece_end, shared.substr(piece, piece_end - piece));
  EXPECT_NE(error_of(read_vtu, shared).find("do appended offsets overlap?"), std::string::npos);
}

}  // namespace
}  // namespace structmesh
