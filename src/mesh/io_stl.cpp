// STL, ASCII and binary. STL stores every triangle with its own three corners;
// the reader welds bitwise-equal coordinates into shared vertices so the result
// is an indexed mesh whose adjacency can be built.
#include "mesh/surface_io.hpp"
#include "mesh/text_scanner.hpp"
#include "structmesh/io.hpp"

#include <Eigen/Geometry>

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <string_view>
#include <vector>

namespace structmesh {

namespace {

constexpr std::size_t kBinaryHeaderSize = 84;    // 80 free bytes + uint32 triangle count
constexpr std::size_t kBinaryTriangleSize = 50;  // normal, 3 corners (12 floats), uint16 attribute

// Open-addressing hash set of point ids keyed by exact coordinates: points that
// compare equal (so 0.0 and -0.0 too) become one vertex, numbered in order of
// first appearance.
class PointWelder {
 public:
  explicit PointWelder(MeshBundle& mesh) : mesh_(mesh), slots_(1024, kInvalidIndex) {}

  /// The id of `p`, adding it (with its source line, 0 for none) when new.
  Index add(const Vec3& p, std::uint32_t line) {
    std::size_t slot = hash(p) & (slots_.size() - 1);
    while (slots_[slot] != kInvalidIndex) {
      if (mesh_.points[slots_[slot]] == p) return slots_[slot];
      slot = (slot + 1) & (slots_.size() - 1);
    }
    if (mesh_.points.size() >= detail::kMaxCount)
      throw InputError(located_message(mesh_.source_name, line, "too many vertices for 32-bit indices"));
    const auto id = static_cast<Index>(mesh_.points.size());
    mesh_.points.push_back(p);
    if (line != 0) mesh_.lines.point_lines.push_back(line);
    slots_[slot] = id;
    if (2 * mesh_.points.size() > slots_.size()) grow();  // keep the load factor at most 1/2
    return id;
  }

 private:
  static std::size_t hash(const Vec3& p) {
    std::uint64_t h = 0;
    for (int k = 0; k < 3; ++k) {
      // + 0.0 turns -0.0 into 0.0, so values that compare equal hash equal.
      h ^= std::bit_cast<std::uint64_t>(p[k] + 0.0) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    }
    // splitmix64 finaliser: spreads the bits of nearby coordinates over the table.
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
    return static_cast<std::size_t>(h ^ (h >> 31));
  }
  void grow() {
    slots_.assign(slots_.size() * 2, kInvalidIndex);
    for (Index id = 0; id < mesh_.points.size(); ++id) {
      std::size_t slot = hash(mesh_.points[id]) & (slots_.size() - 1);
      while (slots_[slot] != kInvalidIndex) slot = (slot + 1) & (slots_.size() - 1);
      slots_[slot] = id;
    }
  }

  MeshBundle& mesh_;
  std::vector<Index> slots_;
};

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if ((a[i] | 0x20) != (b[i] | 0x20)) return false;  // b is a lower-case keyword
  return true;
}

void expect(detail::TextScanner& in, std::string_view keyword) {
  const std::string_view tok = in.token();
  if (tok.empty()) in.fail("unexpected end of file, expected '" + std::string(keyword) + "'");
  if (!equals_ignoring_case(tok, keyword))
    in.fail("expected '" + std::string(keyword) + "', found '" + in.clip(tok) + "'");
}

MeshBundle read_binary(std::string_view data, const std::string& source_name, std::uint64_t triangle_count) {
  if (triangle_count == 0) throw InputError(located_message(source_name, 0, "binary STL holds no triangles"));
  if (triangle_count > detail::kMaxCount / 3)
    throw InputError(located_message(source_name, 0, "too many triangles for 32-bit indices"));
  MeshBundle mesh;
  mesh.source_name = source_name;
  mesh.triangles.reserve(triangle_count);  // the file size was checked against the count
  PointWelder welder(mesh);
  detail::ByteReader reader(data, source_name, false);
  reader.skip(kBinaryHeaderSize, "the header");
  for (std::uint64_t t = 0; t < triangle_count; ++t) {
    reader.skip(12, "a facet normal");
    std::array<Index, 3> triangle{};
    for (Index& corner : triangle) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        p[k] = reader.read<float>("a vertex");
        if (!std::isfinite(p[k]))
          throw InputError(
              located_message(source_name, 0, "triangle " + std::to_string(t) + " has a non-finite coordinate"));
      }
      corner = welder.add(p, 0);
    }
    reader.skip(2, "a facet attribute");
    mesh.triangles.push_back(triangle);
  }
  return mesh;
}

MeshBundle read_ascii(std::string_view data, const std::string& source_name) {
  detail::TextScanner in(data, source_name);
  MeshBundle mesh;
  mesh.source_name = source_name;
  PointWelder welder(mesh);
  // Some tools concatenate several solids in one file; all are read.
  do {
    expect(in, "solid");
    in.skip_line();  // the solid's name
    while (true) {
      in.skip_space();
      const std::uint32_t line = in.line();
      const std::string_view tok = in.token();
      if (tok.empty()) in.fail("unexpected end of file, expected 'facet' or 'endsolid'");
      if (equals_ignoring_case(tok, "endsolid")) break;
      if (!equals_ignoring_case(tok, "facet")) in.fail("expected 'facet' or 'endsolid', found '" + in.clip(tok) + "'");
      expect(in, "normal");
      // The normal is recomputed by whoever needs it; writers put "nan" in it for
      // degenerate facets, so its values are not parsed.
      for (int k = 0; k < 3; ++k)
        if (in.token().empty()) in.fail("unexpected end of file in a facet normal");
      expect(in, "outer");
      expect(in, "loop");
      std::array<Index, 3> triangle{};
      for (Index& corner : triangle) {
        expect(in, "vertex");
        const std::uint32_t vertex_line = in.line();
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = in.real("vertex coordinate");
        corner = welder.add(p, vertex_line);
      }
      expect(in, "endloop");
      expect(in, "endfacet");
      if (mesh.triangles.size() >= detail::kMaxCount) in.fail("too many triangles for 32-bit indices");
      mesh.triangles.push_back(triangle);
      mesh.lines.triangle_lines.push_back(line);
    }
    in.skip_line();  // the solid's name again
  } while (!in.at_end());
  if (mesh.triangles.empty()) throw InputError(located_message(source_name, 0, "ASCII STL holds no triangles"));
  return mesh;
}

bool starts_with_solid(std::string_view data) {
  const std::size_t start = data.find_first_not_of(" \t\r\n");
  if (start == std::string_view::npos || data.size() - start < 5) return false;
  if (!equals_ignoring_case(data.substr(start, 5), "solid")) return false;
  return data.size() - start == 5 || std::string_view(" \t\r\n").find(data[start + 5]) != std::string_view::npos;
}

void append_float_le(std::string& out, const Vec3& v) {
  for (int k = 0; k < 3; ++k) detail::append_le<float>(out, static_cast<float>(v[k]));
}

}  // namespace

MeshBundle read_stl(std::string_view data, const std::string& source_name) {
  if (detail::is_blank(data)) throw InputError(located_message(source_name, 0, "empty file"));
  // A binary STL may begin with "solid" too, so the size decides first: a binary
  // file is exactly 84 + 50 * (its triangle count) bytes long.
  if (data.size() >= kBinaryHeaderSize) {
    detail::ByteReader reader(data, source_name, false);
    reader.skip(80, "the header");
    const std::uint64_t count = reader.read<std::uint32_t>("the triangle count");
    if (data.size() - kBinaryHeaderSize == count * kBinaryTriangleSize) return read_binary(data, source_name, count);
    if (!starts_with_solid(data))
      throw InputError(located_message(source_name, 0,
                                       "binary STL announces " + std::to_string(count) + " triangles, which take " +
                                           std::to_string(kBinaryHeaderSize + count * kBinaryTriangleSize) +
                                           " bytes, but the file has " + std::to_string(data.size()) +
                                           " bytes (truncated?)"));
  }
  if (!starts_with_solid(data))
    throw InputError(located_message(source_name, 0, "not an STL file: too short for binary STL and no 'solid'"));
  return read_ascii(data, source_name);
}

std::string write_stl(const MeshBundle& mesh, Encoding encoding) {
  detail::check_writable_surface(mesh, "STL");
  // STL holds triangles only: each quad becomes two, split along its 0-2 diagonal.
  std::vector<std::array<Index, 3>> triangles = mesh.triangles;
  triangles.reserve(mesh.triangles.size() + 2 * mesh.quads.size());
  for (const auto& q : mesh.quads) {
    triangles.push_back({q[0], q[1], q[2]});
    triangles.push_back({q[0], q[2], q[3]});
  }
  const auto normal = [&](const std::array<Index, 3>& t) -> Vec3 {
    const Vec3 n = (mesh.points[t[1]] - mesh.points[t[0]]).cross(mesh.points[t[2]] - mesh.points[t[0]]);
    const double length = n.norm();
    return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
  };

  std::string out;
  if (encoding == Encoding::Binary) {
    if (triangles.size() > 0xffffffffu)
      throw InputError(located_message(mesh.source_name, 0, "too many triangles for a binary STL"));
    out.reserve(kBinaryHeaderSize + kBinaryTriangleSize * triangles.size());
    // The header must not start with "solid", or older readers take the file for ASCII.
    std::string header = "binary STL written by structmesh";
    header.resize(80, ' ');
    out += header;
    detail::append_le<std::uint32_t>(out, static_cast<std::uint32_t>(triangles.size()));
    for (const auto& t : triangles) {
      append_float_le(out, normal(t));
      for (const Index v : t) append_float_le(out, mesh.points[v]);
      detail::append_le<std::uint16_t>(out, 0);
    }
    return out;
  }
  out.reserve(triangles.size() * 300 + 64);
  const auto append_vector = [&](const Vec3& v) {
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      detail::append_real(out, v[k]);
    }
    out += '\n';
  };
  out += "solid structmesh\n";
  for (const auto& t : triangles) {
    out += "facet normal";
    append_vector(normal(t));
    out += " outer loop\n";
    for (const Index v : t) {
      out += "  vertex";
      append_vector(mesh.points[v]);
    }
    out += " endloop\nendfacet\n";
  }
  out += "endsolid structmesh\n";
  return out;
}

}  // namespace structmesh
