// Surface readers and writers (OBJ, OFF, PLY, STL): exact round trips, one test
// per malformed-input rule (the message must name the file and, for text, the
// line), the real data set against the table of shared/data/README.md, and the
// adjacency builders of mesh.hpp on small analytic meshes.
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/mesh.hpp"
#include "test_data.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace structmesh {
namespace {

using Reader = MeshBundle (*)(std::string_view, const std::string&);

// A cube with outward faces in VTK hex order (see kHexFaces). With `quads`, the
// first two sides stay quads and the other four are split into triangles.
// `float_exact` picks coordinates a binary STL (32-bit floats) stores exactly;
// otherwise they need all 17 significant digits.
MeshBundle cube(bool quads, bool float_exact) {
  const double lo[3] = {float_exact ? 0.5 : 0.1, float_exact ? -1.25 : 1.0 / 3.0, float_exact ? 2.0 : -1e-17};
  const double hi[3] = {float_exact ? 1.5 : 0.7, float_exact ? 0.75 : 2.0 / 3.0, float_exact ? 3.5 : 1e300};
  MeshBundle mesh;
  for (int top = 0; top < 2; ++top) {
    const double z = top ? hi[2] : lo[2];
    mesh.points.emplace_back(lo[0], lo[1], z);
    mesh.points.emplace_back(hi[0], lo[1], z);
    mesh.points.emplace_back(hi[0], hi[1], z);
    mesh.points.emplace_back(lo[0], hi[1], z);
  }
  for (std::size_t f = 0; f < kHexFaces.size(); ++f) {
    const auto& q = kHexFaces[f];
    const auto at = [&](int i) { return static_cast<Index>(q[i]); };
    if (quads && f < 2) {
      mesh.quads.push_back({at(0), at(1), at(2), at(3)});
    } else {
      mesh.triangles.push_back({at(0), at(1), at(2)});
      mesh.triangles.push_back({at(0), at(2), at(3)});
    }
  }
  return mesh;
}

void expect_points_bitwise_equal(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(a[i][k]), std::bit_cast<std::uint64_t>(b[i][k]))
          << "point " << i << " coordinate " << k << ": " << a[i][k] << " vs " << b[i][k];
}

void expect_same_mesh(const MeshBundle& expected, const MeshBundle& actual) {
  expect_points_bitwise_equal(expected.points, actual.points);
  EXPECT_EQ(expected.triangles, actual.triangles);
  EXPECT_EQ(expected.quads, actual.quads);
  EXPECT_TRUE(actual.tets.empty());
  EXPECT_TRUE(actual.hexes.empty());
}

// STL has no shared vertices and splits quads, so compare triangle by triangle
// through their corner coordinates.
void expect_same_stl_geometry(const MeshBundle& expected, const MeshBundle& actual) {
  std::vector<std::array<Vec3, 3>> want;
  for (const auto& t : expected.triangles)
    want.push_back({expected.points[t[0]], expected.points[t[1]], expected.points[t[2]]});
  for (const auto& q : expected.quads) {
    want.push_back({expected.points[q[0]], expected.points[q[1]], expected.points[q[2]]});
    want.push_back({expected.points[q[0]], expected.points[q[2]], expected.points[q[3]]});
  }
  ASSERT_EQ(actual.triangles.size(), want.size());
  EXPECT_TRUE(actual.quads.empty());
  for (std::size_t t = 0; t < want.size(); ++t)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(actual.points[actual.triangles[t][c]], want[t][c]) << "triangle " << t << " corner " << c;
}

// The InputError message of `reader` on `data`; records a failure when there is none.
std::string error_of(Reader reader, std::string_view data, const std::string& source) {
  try {
    reader(data, source);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for:\n" << data.substr(0, 300);
  return {};
}

// The message must start with `location` ("bad.obj:4:" or "bad.ply:") and contain `problem`.
void expect_error(Reader reader, std::string_view data, const std::string& location, const std::string& problem) {
  const std::string source = location.substr(0, location.find(':'));
  const std::string message = error_of(reader, data, source);
  EXPECT_TRUE(message.starts_with(location + " ")) << "message: " << message << "\nexpected prefix: " << location;
  EXPECT_NE(message.find(problem), std::string::npos) << "message: " << message << "\nexpected: " << problem;
}

// ---------------------------------------------------------------- round trips

TEST(SurfaceIoRoundTrip, ObjKeepsTrianglesQuadsAndEveryBit) {
  const MeshBundle mesh = cube(true, false);
  const MeshBundle back = read_obj(write_obj(mesh), "cube.obj");
  expect_same_mesh(mesh, back);
  EXPECT_EQ(back.source_name, "cube.obj");
  EXPECT_EQ(back.lines.point_lines.size(), 8u);
  EXPECT_EQ(back.lines.triangle_lines.size(), 8u);
  EXPECT_EQ(back.lines.quad_lines.size(), 2u);
  EXPECT_EQ(back.lines.point_lines.front(), 2u);  // after the comment line
}

TEST(SurfaceIoRoundTrip, OffKeepsTrianglesQuadsAndEveryBit) {
  const MeshBundle mesh = cube(true, false);
  const MeshBundle back = read_off(write_off(mesh), "cube.off");
  expect_same_mesh(mesh, back);
  EXPECT_EQ(back.lines.point_lines.front(), 3u);
  EXPECT_EQ(back.lines.triangle_lines.front(), 11u);  // triangles are written before quads
}

TEST(SurfaceIoRoundTrip, PlyAsciiAndBinaryKeepEveryBit) {
  const MeshBundle mesh = cube(true, false);
  const MeshBundle ascii = read_ply(write_ply(mesh, Encoding::Ascii), "cube.ply");
  expect_same_mesh(mesh, ascii);
  EXPECT_EQ(ascii.lines.point_lines.size(), 8u);
  EXPECT_EQ(ascii.lines.point_lines.front(), 11u);
  const std::string binary_file = write_ply(mesh, Encoding::Binary);
  EXPECT_TRUE(binary_file.starts_with("ply\nformat binary_little_endian 1.0\n"));
  const MeshBundle binary = read_ply(binary_file, "cube.ply");
  expect_same_mesh(mesh, binary);
  EXPECT_TRUE(binary.lines.point_lines.empty());
  EXPECT_TRUE(binary.lines.triangle_lines.empty());
}

TEST(SurfaceIoRoundTrip, StlAsciiKeepsEveryBitAndWelds) {
  for (const bool quads : {false, true}) {
    const MeshBundle mesh = cube(quads, false);
    const std::string file = write_stl(mesh, Encoding::Ascii);
    EXPECT_TRUE(file.starts_with("solid "));
    const MeshBundle back = read_stl(file, "cube.stl");
    EXPECT_EQ(back.points.size(), 8u);  // 36 corners welded into the 8 cube corners
    expect_same_stl_geometry(mesh, back);
    EXPECT_EQ(back.lines.triangle_lines.size(), 12u);
    EXPECT_EQ(back.lines.triangle_lines.front(), 2u);
  }
}

TEST(SurfaceIoRoundTrip, StlBinaryKeepsFloatsAndWelds) {
  for (const bool quads : {false, true}) {
    const MeshBundle mesh = cube(quads, true);
    const std::string file = write_stl(mesh, Encoding::Binary);
    ASSERT_EQ(file.size(), 84u + 50u * 12u);
    const MeshBundle back = read_stl(file, "cube.stl");
    EXPECT_EQ(back.points.size(), 8u);
    expect_same_stl_geometry(mesh, back);
    EXPECT_TRUE(back.lines.triangle_lines.empty());
  }
}

TEST(SurfaceIoRoundTrip, StlWriterComputesUnitOutwardNormals) {
  const std::string file = write_stl(cube(false, true), Encoding::Binary);
  float normal[3];
  std::memcpy(normal, file.data() + 84, sizeof normal);  // first triangle: the bottom side (z = 2)
  EXPECT_EQ(normal[0], 0.0f);
  EXPECT_EQ(normal[1], 0.0f);
  EXPECT_EQ(normal[2], -1.0f);
}

TEST(SurfaceIoRoundTrip, BinaryStlWhoseHeaderStartsWithSolid) {
  std::string file = write_stl(cube(false, true), Encoding::Binary);
  file.replace(0, 11, "solid cube ");
  const MeshBundle back = read_stl(file, "cube.stl");
  EXPECT_EQ(back.triangles.size(), 12u);
  EXPECT_EQ(back.points.size(), 8u);
}

TEST(SurfaceIoRoundTrip, WritersRejectVolumeCellsAndBadIndices) {
  MeshBundle volume = cube(false, true);
  volume.source_name = "volume.mesh";
  volume.tets.push_back({0, 1, 2, 4});
  for (const auto& write : {write_obj, write_off}) EXPECT_THROW(write(volume), InputError);
  EXPECT_THROW(write_ply(volume, Encoding::Binary), InputError);
  EXPECT_THROW(write_stl(volume, Encoding::Ascii), InputError);
  MeshBundle broken = cube(false, true);
  broken.triangles[3][1] = 8;
  EXPECT_THROW(write_stl(broken, Encoding::Binary), InputError);
  EXPECT_THROW(write_obj(broken), InputError);
}

// ---------------------------------------------------------------- OBJ

constexpr std::string_view kObjTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(SurfaceIoObj, IgnoresAttributesAndReadsAllIndexForms) {
  const MeshBundle mesh = read_obj(
      "# comment\nmtllib a.mtl\no thing\nv 0 0 0\nv 1 0 0 1.0\nv 1 1 0 0.5 0.5 0.5\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "g group\ns off\nusemtl red\nf 1/1/1 2//1 3/1\n\nf -4 -2 -1  # relative\nl 1 2\n",
      "a.obj");
  ASSERT_EQ(mesh.points.size(), 4u);
  EXPECT_EQ(mesh.points[2], Vec3(1, 1, 0));
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[0], (std::array<Index, 3>{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (std::array<Index, 3>{0, 2, 3}));
  EXPECT_EQ(mesh.lines.point_lines, (std::vector<std::uint32_t>{4, 5, 6, 7}));
  EXPECT_EQ(mesh.lines.triangle_lines, (std::vector<std::uint32_t>{13, 15}));
}

TEST(SurfaceIoObj, FanTriangulatesPolygonsAndKeepsQuads) {
  const MeshBundle mesh = read_obj("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\nf 1 2 3 4\n", "poly.obj");
  ASSERT_EQ(mesh.triangles.size(), 3u);
  EXPECT_EQ(mesh.triangles[2], (std::array<Index, 3>{0, 3, 4}));
  EXPECT_EQ(mesh.lines.triangle_lines, (std::vector<std::uint32_t>{6, 6, 6}));
  ASSERT_EQ(mesh.quads.size(), 1u);
  EXPECT_EQ(mesh.lines.quad_lines, (std::vector<std::uint32_t>{7}));
}

TEST(SurfaceIoObj, FacesMayPrecedeTheirVertices) {
  const MeshBundle mesh = read_obj("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "late.obj");
  EXPECT_EQ(mesh.triangles.size(), 1u);
}

TEST(SurfaceIoObj, Errors) {
  expect_error(read_obj, "", "bad.obj:", "empty file");
  expect_error(read_obj, " \n\n", "bad.obj:", "empty file");
  expect_error(read_obj, "# nothing here\n", "bad.obj:", "holds no vertices");
  expect_error(read_obj, std::string(kObjTriangle) + "f 1 2 4\n", "bad.obj:4:", "face refers to vertex 4 of 3");
  expect_error(read_obj, std::string(kObjTriangle) + "f 1 2 3\nf 1 2 3 9001\n",
               "bad.obj:5:", "face refers to vertex 9001 of 3");
  expect_error(read_obj, "v 0 0 0\nv 1 nan 0\n", "bad.obj:2:", "not finite");
  expect_error(read_obj, "v 0 0 0\nv 1 0 -inf\n", "bad.obj:2:", "not finite");
  expect_error(read_obj, "v 0 0 0\nv 1 0\n", "bad.obj:2:", "fewer than 3 coordinates");
  expect_error(read_obj, "v 0 0 0\nv 1 0 x\n", "bad.obj:2:", "expected vertex coordinate");
  expect_error(read_obj, std::string(kObjTriangle) + "f 1 2\n", "bad.obj:4:", "at least 3");
  expect_error(read_obj, std::string(kObjTriangle) + "f 1 2 -4\n", "bad.obj:4:", "only 3 vertices precede it");
  expect_error(read_obj, std::string(kObjTriangle) + "f 0 1 2\n", "bad.obj:4:", "index 0 is invalid");
  expect_error(read_obj, std::string(kObjTriangle) + "f 1 2 /3\n", "bad.obj:4:", "expected a vertex index");
  expect_error(read_obj, std::string(kObjTriangle) + "f 1 2 99999999999\n", "bad.obj:4:", "refers to vertex");
  expect_error(read_obj, std::string(kObjTriangle) + "f 1 2 -9223372036854775808\n", "bad.obj:4:", "precede it");
  expect_error(read_obj, "v 0 0 0\nsolid x\n", "bad.obj:2:", "unknown OBJ statement 'solid'");
}

// ---------------------------------------------------------------- OFF

constexpr std::string_view kOffTriangle = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";

TEST(SurfaceIoOff, HeaderVariantsCommentsAndPolygons) {
  const MeshBundle same_line = read_off("OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "a.off");
  EXPECT_EQ(same_line.triangles.size(), 1u);
  const MeshBundle comments = read_off(
      "# leading\nOFF # header\n# between\n\n4 3 7\n0 0 0\n# inside\n1 0 0\n1 1 0  # trailing\n0 1 0\n"
      "3 0 1 2 255 0 0\n4 0 1 2 3\n5 0 1 2 3 0\n",
      "b.off");
  EXPECT_EQ(comments.points.size(), 4u);
  EXPECT_EQ(comments.lines.point_lines, (std::vector<std::uint32_t>{6, 8, 9, 10}));
  EXPECT_EQ(comments.triangles.size(), 4u);  // 1 + a fan of 3
  EXPECT_EQ(comments.lines.triangle_lines, (std::vector<std::uint32_t>{11, 13, 13, 13}));
  EXPECT_EQ(comments.quads.size(), 1u);
  const MeshBundle coloured = read_off("COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2\n", "c.off");
  EXPECT_EQ(coloured.points[1], Vec3(1, 0, 0));
  const MeshBundle normals = read_off("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", "n.off");
  EXPECT_EQ(normals.triangles.size(), 1u);
}

TEST(SurfaceIoOff, Errors) {
  expect_error(read_off, "", "bad.off:", "empty file");
  expect_error(read_off, "# only a comment\n", "bad.off:2:", "no OFF header");
  expect_error(read_off, "PLY\n3 1 0\n", "bad.off:1:", "expected the OFF header");
  expect_error(read_off, "4OFF\n3 1 0\n", "bad.off:1:", "not supported");
  expect_error(read_off, "OFF BINARY\n", "bad.off:1:", "binary OFF is not supported");
  expect_error(read_off, "OFF\n", "bad.off:2:", "missing the vertex, face and edge counts");
  expect_error(read_off, "OFF\n3\n", "bad.off:2:", "lacks the face count");
  expect_error(read_off, "OFF\n-3 1 0\n", "bad.off:2:", "negative vertex count");
  expect_error(read_off, "OFF\n5000000000 1 0\n0 0 0\n", "bad.off:2:", "does not fit 32-bit indices");
  expect_error(read_off, "OFF\n4000000000 4000000000 0\n0 0 0\n", "bad.off:2:", "more than the remaining");
  expect_error(read_off, "OFF\n0 0 0\n", "bad.off:2:", "announces no vertices");
  // Truncated: the second face is missing.
  expect_error(read_off, std::string(kOffTriangle).replace(4, 5, "3 2 0") + "3 0 1 2\n",
               "bad.off:7:", "file ends after 1 of 2 faces");
  expect_error(read_off, "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "bad.off:6:", "more than 3 values");
  expect_error(read_off, "OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n", "bad.off:4:", "not finite");
  expect_error(read_off, "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", "bad.off:4:", "fewer than 3 coordinates");
  expect_error(read_off, std::string(kOffTriangle) + "3 0 1 3\n",
               "bad.off:6:", "face refers to vertex 3, but vertices are numbered 0 to 2");
  expect_error(read_off, std::string(kOffTriangle) + "3 0 -1 2\n", "bad.off:6:", "face refers to vertex -1");
  expect_error(read_off, std::string(kOffTriangle) + "2 0 1\n", "bad.off:6:", "at least 3");
  expect_error(read_off, std::string(kOffTriangle) + "4 0 1 2\n", "bad.off:6:", "lists only 3");
  expect_error(read_off, std::string(kOffTriangle) + "3 0 1 2\n3 0 1 2\n", "bad.off:7:", "unexpected data");
}

// ---------------------------------------------------------------- PLY

constexpr std::string_view kPlyAsciiHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

// A big-endian binary PLY with properties and an element the reader must skip.
std::string big_endian_ply() {
  std::string out =
      "ply\nformat binary_big_endian 1.0\ncomment skipped parts: normal_count, red, the edge element\n"
      "element vertex 4\nproperty uchar red\nproperty float x\nproperty double y\nproperty short z\n"
      "property list uint short normal_count\nelement edge 2\nproperty int a\nproperty list ushort uint b\n"
      "element face 2\nproperty float quality\nproperty list ushort uint vertex_index\nend_header\n";
  const auto put = [&out](auto value) {
    unsigned char bytes[sizeof value];
    std::memcpy(bytes, &value, sizeof value);
    if constexpr (std::endian::native == std::endian::little) std::reverse(std::begin(bytes), std::end(bytes));
    out.append(reinterpret_cast<const char*>(bytes), sizeof value);
  };
  const double xyz[4][3] = {{0.5, 0.1, 1}, {1.5, 0.2, 2}, {1.5, 1.3, -3}, {0.5, 1.4, 4}};
  for (int v = 0; v < 4; ++v) {
    put(std::uint8_t{200});
    put(static_cast<float>(xyz[v][0]));
    put(xyz[v][1]);
    put(static_cast<std::int16_t>(xyz[v][2]));
    put(std::uint32_t{v == 1 ? 2u : 0u});
    if (v == 1) put(std::int16_t{7}), put(std::int16_t{8});
  }
  for (int e = 0; e < 2; ++e) put(std::int32_t{e}), put(std::uint16_t{1}), put(std::uint32_t{9});
  put(1.0f), put(std::uint16_t{3}), put(std::uint32_t{0}), put(std::uint32_t{1}), put(std::uint32_t{2});
  put(1.0f), put(std::uint16_t{4}), put(std::uint32_t{0}), put(std::uint32_t{1}), put(std::uint32_t{2}),
      put(std::uint32_t{3});
  return out;
}

TEST(SurfaceIoPly, BigEndianWithSkippedPropertiesAndElements) {
  const MeshBundle mesh = read_ply(big_endian_ply(), "be.ply");
  ASSERT_EQ(mesh.points.size(), 4u);
  EXPECT_EQ(mesh.points[2], Vec3(1.5, 1.3, -3));
  EXPECT_EQ(mesh.points[3], Vec3(0.5, 1.4, 4));
  EXPECT_EQ(mesh.triangles, (std::vector<std::array<Index, 3>>{{0, 1, 2}}));
  EXPECT_EQ(mesh.quads, (std::vector<std::array<Index, 4>>{{0, 1, 2, 3}}));
}

TEST(SurfaceIoPly, AsciiRecordsLinesAndFanTriangulates) {
  const MeshBundle mesh = read_ply(
      "ply\r\nformat ascii 1.0\r\ncomment x\r\nelement vertex 5\r\nproperty double x\r\nproperty double y\r\n"
      "property double z\r\nelement face 1\r\nproperty list uchar uint vertex_indices\r\nend_header\r\n"
      "0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n0 2 0\r\n5 0 1 2 3 4\r\n",
      "crlf.ply");
  EXPECT_EQ(mesh.points.size(), 5u);
  EXPECT_EQ(mesh.lines.point_lines.front(), 11u);
  EXPECT_EQ(mesh.lines.triangle_lines, (std::vector<std::uint32_t>{16, 16, 16}));
}

TEST(SurfaceIoPly, PointCloudWithoutFaces) {
  const MeshBundle mesh = read_ply(
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n0 0 0\n1 1 1\n",
      "cloud.ply");
  EXPECT_EQ(mesh.points.size(), 2u);
  EXPECT_EQ(mesh.cell_count(), 0u);
}

TEST(SurfaceIoPly, HeaderErrors) {
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  expect_error(read_ply, "", "bad.ply:", "empty file");
  expect_error(read_ply, "plyx\n", "bad.ply:1:", "not a PLY file");
  expect_error(read_ply, "ply\nformat ascii 1.0\n", "bad.ply:3:", "no end_header line");
  expect_error(read_ply, "ply\nformat ascii 1.0 x\n", "bad.ply:2:", "expected 'format");
  expect_error(read_ply, "ply\nformat utf8 1.0\n", "bad.ply:2:", "unknown PLY format 'utf8'");
  expect_error(read_ply, "ply\nformat ascii 1.0\nproperty float x\n", "bad.ply:3:", "before any element");
  expect_error(read_ply, "ply\nformat ascii 1.0\nelement vertex 99999999999\n",
               "bad.ply:3:", "does not fit 32-bit indices");
  expect_error(read_ply, "ply\nformat ascii 1.0\nelement vertex -1\n", "bad.ply:3:", "expected an element count");
  expect_error(read_ply, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\n",
               "bad.ply:4:", "unknown property type 'float128'");
  expect_error(read_ply, "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz + "property float x\n",
               "bad.ply:7:", "'x' declared twice");
  expect_error(
      read_ply,
      "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz + "element face 1\nproperty list float int vertex_indices\n",
      "bad.ply:8:", "list count type must be an integer type");
  expect_error(
      read_ply,
      "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz + "element face 1\nproperty list uchar float vertex_indices\n",
      "bad.ply:8:", "must have an integer type");
  expect_error(read_ply, "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz + "element vertex 1\n",
               "bad.ply:7:", "a second 'vertex' element");
  expect_error(read_ply, "ply\nformat ascii 1.0\nbogus\n", "bad.ply:3:", "unknown header line 'bogus'");
  expect_error(read_ply, "ply\nformat ascii 1.0\nend_header now\n", "bad.ply:3:", "after end_header");
  expect_error(read_ply, "ply\nelement vertex 1\n" + xyz + "end_header\n0 0 0\n", "bad.ply:", "no format line");
  expect_error(read_ply, "ply\nformat ascii 1.0\nend_header\n", "bad.ply:", "declares no vertex element");
  expect_error(read_ply, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
               "bad.ply:", "lacks one of the properties x, y, z");
  expect_error(read_ply,
               "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz +
                   "element face 1\nproperty list uchar int indices\nend_header\n0 0 0\n3 0 0 0\n",
               "bad.ply:", "no 'vertex_indices' list");
  expect_error(read_ply, "ply\nformat ascii 1.0\nelement vertex 0\n" + xyz + "end_header\n",
               "bad.ply:", "announces no vertices");
}

TEST(SurfaceIoPly, AsciiDataErrors) {
  const std::string header(kPlyAsciiHeader);
  expect_error(read_ply, header + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "bad.ply:14:", "unexpected end of file");
  expect_error(read_ply, header + "0 0 0\n1 0 0\n", "bad.ply:10:", "element 'vertex' announces 3 instances");
  expect_error(read_ply, header + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "bad.ply:11:", "not finite");
  expect_error(read_ply, header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
               "bad.ply:13:", "face 0 refers to vertex 3, but vertices are numbered 0 to 2");
  expect_error(read_ply, header + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "bad.ply:13:", "at least 3");
  expect_error(read_ply, header + "0 0 0\n1 0 0\n0 1 0\n-1 0 1\n", "bad.ply:13:", "negative list length");
  expect_error(read_ply, header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n7\n", "bad.ply:14:", "unexpected data");
  std::string absurd = header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  absurd.replace(absurd.find("vertex 3"), 8, "vertex 4000000000");
  expect_error(read_ply, absurd, "bad.ply:10:", "announces 4000000000 instances, more than the remaining");
}

// Bytes at the end of a binary file, written in little-endian order.
void set_le_uint32(std::string& file, std::size_t offset, std::uint32_t value) {
  for (int b = 0; b < 4; ++b) file[offset + b] = static_cast<char>((value >> (8 * b)) & 0xff);
}

TEST(SurfaceIoPly, BinaryDataErrors) {
  const std::string file = write_ply(cube(true, false), Encoding::Binary);
  const std::size_t body = file.find("end_header\n") + 11;

  expect_error(read_ply, file.substr(0, file.size() - 1), "bad.ply:", "file is truncated");
  expect_error(read_ply, file.substr(0, body + 100), "bad.ply:", "more than the remaining");
  std::string absurd = file;
  absurd.replace(absurd.find("vertex 8"), 8, "vertex 4000000000");
  expect_error(read_ply, absurd, "bad.ply:", "announces 4000000000 instances, more than the remaining");

  std::string nan = file;
  const double not_a_number = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(nan.data() + body + 8, &not_a_number, sizeof not_a_number);
  expect_error(read_ply, nan, "bad.ply:", "vertex 0 has a non-finite coordinate");

  std::string out_of_range = file;
  set_le_uint32(out_of_range, file.size() - 4, 8);
  expect_error(read_ply, out_of_range, "bad.ply:", "face 9 refers to vertex 8, but vertices are numbered 0 to 7");
  set_le_uint32(out_of_range, file.size() - 4, 0xffffffffu);
  expect_error(read_ply, out_of_range, "bad.ply:", "face 9 refers to vertex -1");

  expect_error(read_ply, file + "xyz", "bad.ply:", "3 bytes of unexpected data after the last element");

  // A 32-bit list length of 4e9 must be checked against the data before it is read.
  std::string huge_list =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty uchar x\nproperty uchar y\n"
      "property uchar z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
  huge_list += std::string(9, '\0') + std::string(4, '\xff') + std::string(12, '\0');
  expect_error(read_ply, huge_list, "bad.ply:", "file is truncated: a list needs 17179869180 bytes");
}

// ---------------------------------------------------------------- STL

constexpr std::string_view kStlFacet =
    "facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\n";

TEST(SurfaceIoStl, AsciiVariants) {
  // Upper-case keywords, "nan" normals (written for degenerate facets), two solids in one file.
  const std::string upper =
      "SOLID a\nFACET NORMAL nan nan nan\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 1 0 0\n"
      "VERTEX 0 1 0\nENDLOOP\nENDFACET\nENDSOLID a\n";
  const std::string second =
      "solid b\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\n"
      "endsolid b";
  const MeshBundle mesh = read_stl(upper + second, "two.stl");
  EXPECT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.points.size(), 4u);
  EXPECT_EQ(mesh.triangles[1], (std::array<Index, 3>{1, 3, 2}));
  EXPECT_EQ(mesh.lines.triangle_lines, (std::vector<std::uint32_t>{2, 11}));
  EXPECT_EQ(mesh.lines.point_lines, (std::vector<std::uint32_t>{4, 5, 6, 14}));
}

TEST(SurfaceIoStl, WeldsNegativeZeroWithZero) {
  const MeshBundle mesh = read_stl(
      "solid z\n" + std::string(kStlFacet) +
          "facet normal 0 0 1\nouter loop\nvertex -0 0 -0\nvertex 0 1 0\nvertex -1 0 0\nendloop\nendfacet\nendsolid\n",
      "zero.stl");
  EXPECT_EQ(mesh.points.size(), 4u);
  EXPECT_EQ(mesh.triangles[1][0], 0u);
}

TEST(SurfaceIoStl, Errors) {
  expect_error(read_stl, "", "bad.stl:", "empty file");
  expect_error(read_stl, "hello", "bad.stl:", "not an STL file");
  const std::string binary = write_stl(cube(false, true), Encoding::Binary);
  expect_error(read_stl, binary.substr(0, binary.size() - 1),
               "bad.stl:", "binary STL announces 12 triangles, which take 684 bytes, but the file has 683 bytes");
  std::string absurd = binary.substr(0, 134);
  set_le_uint32(absurd, 80, 0xffffffffu);
  expect_error(read_stl, absurd, "bad.stl:", "announces 4294967295 triangles");
  std::string empty = binary.substr(0, 84);
  set_le_uint32(empty, 80, 0);
  expect_error(read_stl, empty, "bad.stl:", "binary STL holds no triangles");
  std::string nan = binary;
  const float infinity = std::numeric_limits<float>::infinity();
  std::memcpy(nan.data() + 84 + 50 * 3 + 12 + 4 * 4, &infinity, sizeof infinity);
  expect_error(read_stl, nan, "bad.stl:", "triangle 3 has a non-finite coordinate");

  const std::string ascii = write_stl(cube(false, false), Encoding::Ascii);
  std::size_t fifth_line = 0;
  for (int n = 0; n < 5; ++n) fifth_line = ascii.find('\n', fifth_line) + 1;
  expect_error(read_stl, ascii.substr(0, fifth_line), "bad.stl:6:", "unexpected end of file, expected 'vertex'");
  expect_error(read_stl, "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 nan 0\n",
               "bad.stl:5:", "not finite");
  expect_error(read_stl, "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n",
               "bad.stl:6:", "expected 'vertex', found 'endloop'");
  expect_error(read_stl, "solid t\nfacet normal 0 0 1\nouter lop\n", "bad.stl:3:", "expected 'loop', found 'lop'");
  expect_error(read_stl, "solid t\nfacet normal 0 0\n", "bad.stl:3:", "in a facet normal");
  expect_error(read_stl, "solid t\n" + std::string(kStlFacet), "bad.stl:9:", "expected 'facet' or 'endsolid'");
  expect_error(read_stl, "solid t\n" + std::string(kStlFacet) + "facet\n", "bad.stl:10:", "expected 'normal'");
  expect_error(read_stl, "solid t\n" + std::string(kStlFacet) + "endsolid t\nsolid",
               "bad.stl:10:", "expected 'facet' or 'endsolid'");
  expect_error(read_stl, "solid empty\nendsolid empty\n", "bad.stl:", "ASCII STL holds no triangles");
  expect_error(read_stl, "solid t\n" + std::string(kStlFacet) + "endsolid t\ngarbage\n",
               "bad.stl:10:", "expected 'solid', found 'garbage'");
}

// ---------------------------------------------------------------- real data

// V and F per file, from the table in shared/data/README.md.
const std::map<std::string, std::pair<std::size_t, std::size_t>> kSurfaceTable{
    {"bunny_hr.obj", {29834, 59664}},
    {"rocker-arm.obj", {10044, 20088}},
    {"fertility.off", {23188, 46388}},
    {"kitten.off", {10000, 20000}},
    {"kitten_40k.off", {40000, 80000}},
    {"hand_closed.obj", {7993, 15982}},
    {"3holes.off", {3596, 7200}},
    {"eight.off", {766, 1536}},
    {"double-torus.obj", {2174, 4352}},
    {"torus.obj", {2304, 4608}},
    {"screwdriver.off", {3395, 6786}},
    {"wingnut.obj", {3047, 6090}},
    {"horse.off", {48485, 96966}},
    {"happy_buddha_13k.off", {13295, 26999}},
    {"tosca_centaur.off", {10000, 19996}},
    {"tosca_dog0.off", {25290, 50528}},
    {"tosca_dog0_closed.off", {25292, 50580}},
    {"tosca_gorilla.off", {25438, 50868}},
    {"tosca_michael.off", {52565, 105028}},
    {"tosca_victoria.off", {45659, 91208}},
};

std::filesystem::path surface_folder() { return test::data_dir() / "surfaces"; }

TEST(SurfaceIoData, EverySurfaceMatchesTheReadmeTable) {
  const std::filesystem::path folder = surface_folder();
  if (!std::filesystem::is_directory(folder))
    FAIL() << "test data folder " << folder << " is missing; set STRUCTMESH_DATA to the folder holding surfaces/";
  std::set<std::string> seen;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    const auto row = kSurfaceTable.find(name);
    if (row == kSurfaceTable.end()) {
      ADD_FAILURE() << "not in the README table";
      continue;
    }
    seen.insert(name);
    const MeshBundle mesh = read_mesh(entry.path());
    EXPECT_EQ(mesh.points.size(), row->second.first);
    EXPECT_EQ(mesh.triangles.size(), row->second.second);
    EXPECT_TRUE(mesh.quads.empty());
    EXPECT_EQ(mesh.lines.point_lines.size(), mesh.points.size());
    EXPECT_EQ(mesh.lines.triangle_lines.size(), mesh.triangles.size());
    // Real sizes through the binary PLY path too.
    expect_same_mesh(mesh, read_ply(write_ply(mesh, Encoding::Binary), name + ".ply"));
  }
  for (const auto& [name, counts] : kSurfaceTable) EXPECT_TRUE(seen.contains(name)) << name << " is missing";
}

// ---------------------------------------------------------------- adjacency

TEST(SurfaceAdjacency, TriangulatedCube) {
  const TriMesh mesh = to_tri_mesh(cube(false, true));
  const EdgeAdjacency adjacency = build_edges(mesh);
  ASSERT_EQ(adjacency.edges.size(), 18u);  // 12 cube edges + one diagonal per side
  ASSERT_EQ(adjacency.edge_elements.row_count(), 18u);
  for (std::size_t e = 0; e < adjacency.edges.size(); ++e) {
    EXPECT_LT(adjacency.edges[e][0], adjacency.edges[e][1]);
    EXPECT_EQ(adjacency.edge_elements.row(e).size(), 2u) << "edge " << e;
  }
  EXPECT_TRUE(std::is_sorted(adjacency.edges.begin(), adjacency.edges.end()));

  // Valence: 3 cube edges per corner plus the side diagonals (0-2 of each side) that end there.
  std::vector<std::size_t> valence(8, 3);
  for (const auto& side : kHexFaces) ++valence[side[0]], ++valence[side[2]];
  const CompressedRows neighbors = build_vertex_neighbors(adjacency, mesh.points.size());
  const CompressedRows incident = build_vertex_elements(mesh.triangles, mesh.points.size());
  ASSERT_EQ(neighbors.row_count(), 8u);
  ASSERT_EQ(incident.row_count(), 8u);
  for (Index v = 0; v < 8; ++v) {
    const auto ring = neighbors.row(v);
    EXPECT_EQ(ring.size(), valence[v]) << "vertex " << v;
    EXPECT_TRUE(std::is_sorted(ring.begin(), ring.end()));
    for (const Index w : ring) {
      const std::array<Index, 2> edge{std::min(v, w), std::max(v, w)};
      EXPECT_TRUE(std::binary_search(adjacency.edges.begin(), adjacency.edges.end(), edge));
    }
    // A closed manifold surface: as many triangles around a vertex as neighbours.
    const auto triangles = incident.row(v);
    EXPECT_EQ(triangles.size(), valence[v]) << "vertex " << v;
    EXPECT_TRUE(std::is_sorted(triangles.begin(), triangles.end()));
    for (const Index t : triangles)
      EXPECT_NE(std::find(mesh.triangles[t].begin(), mesh.triangles[t].end(), v), mesh.triangles[t].end());
  }
}

TEST(SurfaceAdjacency, QuadCube) {
  QuadMesh mesh;
  mesh.points = cube(false, true).points;
  for (const auto& side : kHexFaces)
    mesh.quads.push_back({static_cast<Index>(side[0]), static_cast<Index>(side[1]), static_cast<Index>(side[2]),
                          static_cast<Index>(side[3])});
  const EdgeAdjacency adjacency = build_edges(mesh);
  ASSERT_EQ(adjacency.edges.size(), 12u);
  for (std::size_t e = 0; e < 12; ++e) EXPECT_EQ(adjacency.edge_elements.row(e).size(), 2u);
  const CompressedRows neighbors = build_vertex_neighbors(adjacency, mesh.points.size());
  const CompressedRows incident = build_vertex_elements(mesh.quads, mesh.points.size());
  for (Index v = 0; v < 8; ++v) {
    EXPECT_EQ(neighbors.row(v).size(), 3u);
    EXPECT_EQ(incident.row(v).size(), 3u);
  }
}

// True when the face's normal (right-hand rule over its vertex order) points
// away from the centroid of `cell`.
template <std::size_t N, std::size_t K>
bool points_away(const std::vector<Vec3>& points, const std::array<Index, N>& face, const std::array<Index, K>& cell) {
  Vec3 face_centre = Vec3::Zero();
  for (const Index v : face) face_centre += points[v];
  face_centre /= static_cast<double>(N);
  Vec3 cell_centre = Vec3::Zero();
  for (const Index v : cell) cell_centre += points[v];
  cell_centre /= static_cast<double>(K);
  // Triangle: the cross product of two edges; quad: of the two diagonals.
  const Vec3 normal = N == 3 ? Vec3((points[face[1]] - points[face[0]]).cross(points[face[2]] - points[face[0]]))
                             : Vec3((points[face[2]] - points[face[0]]).cross(points[face[N - 1]] - points[face[1]]));
  return normal.dot(face_centre - cell_centre) > 0.0;
}

double tet_volume(const std::vector<Vec3>& p, const std::array<Index, 4>& t) {
  return (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).dot(p[t[3]] - p[t[0]]) / 6.0;
}

TEST(SurfaceAdjacency, TwoTetsSharingAFace) {
  TetMesh mesh;
  mesh.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.2, 1), Vec3(0.3, 0.3, -1)};
  mesh.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};  // both positive: 3 above the shared face, 4 below
  for (const auto& t : mesh.tets) ASSERT_GT(tet_volume(mesh.points, t), 0.0);

  const FaceAdjacency<3> faces = build_faces(mesh);
  ASSERT_EQ(faces.faces.size(), 7u);
  ASSERT_EQ(faces.face_cells.size(), 7u);
  EXPECT_TRUE(faces.extra_cells.empty());
  int interior = 0;
  for (std::size_t f = 0; f < faces.faces.size(); ++f) {
    const auto [first, second] = faces.face_cells[f];
    EXPECT_TRUE(points_away(mesh.points, faces.faces[f], mesh.tets[first])) << "face " << f;
    if (second == kInvalidIndex) continue;
    ++interior;
    EXPECT_EQ(std::set<Index>({first, second}), std::set<Index>({0, 1}));
    EXPECT_FALSE(points_away(mesh.points, faces.faces[f], mesh.tets[second]));
    std::array<Index, 3> sorted = faces.faces[f];
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, (std::array<Index, 3>{0, 1, 2}));
  }
  EXPECT_EQ(interior, 1);
  EXPECT_EQ(build_edges(mesh).edges.size(), 9u);  // 6 + 6 - the 3 shared
}

TEST(SurfaceAdjacency, TwoHexesSharingAFace) {
  HexMesh mesh;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x) mesh.points.emplace_back(x, y, z);
  const auto id = [](int x, int y, int z) { return static_cast<Index>(x + 3 * y + 6 * z); };
  for (int x = 0; x < 2; ++x)
    mesh.hexes.push_back({id(x, 0, 0), id(x + 1, 0, 0), id(x + 1, 1, 0), id(x, 1, 0), id(x, 0, 1), id(x + 1, 0, 1),
                          id(x + 1, 1, 1), id(x, 1, 1)});

  const FaceAdjacency<4> faces = build_faces(mesh);
  ASSERT_EQ(faces.faces.size(), 11u);
  EXPECT_TRUE(faces.extra_cells.empty());
  int interior = 0;
  for (std::size_t f = 0; f < faces.faces.size(); ++f) {
    const auto [first, second] = faces.face_cells[f];
    EXPECT_TRUE(points_away(mesh.points, faces.faces[f], mesh.hexes[first])) << "face " << f;
    if (second == kInvalidIndex) continue;
    ++interior;
    EXPECT_EQ(std::set<Index>({first, second}), std::set<Index>({0, 1}));
    EXPECT_FALSE(points_away(mesh.points, faces.faces[f], mesh.hexes[second]));
    for (const Index v : faces.faces[f]) EXPECT_EQ(mesh.points[v].x(), 1.0);
  }
  EXPECT_EQ(interior, 1);
  const EdgeAdjacency edges = build_edges(mesh);
  ASSERT_EQ(edges.edges.size(), 20u);  // 12 + 12 - the 4 shared
  int shared = 0;
  for (std::size_t e = 0; e < edges.edges.size(); ++e) shared += edges.edge_elements.row(e).size() == 2;
  EXPECT_EQ(shared, 4);
}

}  // namespace
}  // namespace structmesh
