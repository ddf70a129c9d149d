// MEDIT .mesh (ASCII) reader and writer.
//
// A MEDIT file (INRIA libMeshb) is a sequence of keyword sections:
// "MeshVersionFormatted 2", "Dimension 3", "Vertices n" + n rows, "Tetrahedra n"
// + n rows, ..., "End". Element rows are 1-based vertex indices followed by a
// reference number, which becomes the element label. Keywords are matched
// case-insensitively and '#' starts a comment, as libMeshb does.
//
// Node order: MEDIT hexes and tets use VTK's order. Checked on Gmsh 4.8.4's .mesh
// output: all 1125 tets of a meshed unit box have det(p1-p0, p2-p0, p3-p0) > 0, and the
// hexes of an extruded transfinite box have nodes 0-3 counter-clockwise at the bottom
// with node i+4 above node i (tests/mesh/test_io_volume.cpp repeats the check).
#include "mesh/io_volume_common.hpp"
#include "mesh/text_scanner.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <array>
#include <cctype>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace structmesh {
namespace {

using detail::TextScanner;

// Sections read only to be skipped, with their row widths from libMeshb's keyword
// table (ints or reals per row; `dim_factor` adds that many times the dimension).
// Knowing the widths lets a wrong count be reported instead of silently misread.
struct SkippedSection {
  std::string_view name;  // lower case
  int width;
  int dim_factor;
  bool counted;  // false: a fixed number of values follows the keyword, no count
};
constexpr SkippedSection kSkippedSections[] = {
    {"edges", 3, 0, true},
    {"corners", 1, 0, true},
    {"ridges", 1, 0, true},
    {"requiredvertices", 1, 0, true},
    {"requirededges", 1, 0, true},
    {"requiredtriangles", 1, 0, true},
    {"requiredquadrilaterals", 1, 0, true},
    {"requiredtetrahedra", 1, 0, true},
    {"requiredhexahedra", 1, 0, true},
    {"tangentatedgevertices", 3, 0, true},
    {"normalatvertices", 2, 0, true},
    {"normalattrianglevertices", 3, 0, true},
    {"normalatquadrilateralvertices", 4, 0, true},
    {"tangentatvertices", 2, 0, true},
    {"normals", 0, 1, true},
    {"tangents", 0, 1, true},
    {"subdomainfromgeom", 3, 0, true},
    {"angleofcornerbound", 1, 0, false},
    {"boundingbox", 0, 2, false},
};

// Element sections structmesh cannot represent. Skipping them would silently drop
// part of a volume, so they are an error.
constexpr std::string_view kUnsupportedSections[] = {"prisms", "pentahedra", "pyramids"};
constexpr std::string_view kElementSectionStems[] = {"triangles", "quadrilaterals", "tetrahedra", "hexahedra"};

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool is_keyword(std::string_view token) {
  return !token.empty() && std::isalpha(static_cast<unsigned char>(token.front()));
}

/// Rejects a negative count, or one the rest of the buffer cannot hold (each value
/// needs at least one character and one separator), before anything is allocated.
std::size_t checked_count(TextScanner& in, std::int64_t count, std::int64_t width, std::string_view section) {
  if (count < 0) in.fail("negative count " + std::to_string(count) + " for section '" + std::string(section) + "'");
  const std::uint64_t remaining = in.rest().size();
  if (width > 0 && static_cast<std::uint64_t>(count) > (remaining + 1) / (2 * static_cast<std::uint64_t>(width)))
    in.fail("section '" + std::string(section) + "' declares " + std::to_string(count) +
            " rows but the file is too short for them (truncated?)");
  return static_cast<std::size_t>(count);
}

std::int32_t read_reference(TextScanner& in) {
  const std::int64_t ref = in.integer("reference number");
  if (ref < std::numeric_limits<std::int32_t>::min() || ref > std::numeric_limits<std::int32_t>::max())
    in.fail("reference number " + std::to_string(ref) + " does not fit in 32 bits");
  return static_cast<std::int32_t>(ref);
}

template <std::size_t N>
void read_elements(TextScanner& in, std::size_t count, std::vector<std::array<Index, N>>& elements,
                   std::vector<std::int32_t>& labels, std::vector<std::uint32_t>& lines, const char* kind) {
  elements.reserve(elements.size() + count);
  labels.reserve(labels.size() + count);
  lines.reserve(lines.size() + count);
  for (std::size_t i = 0; i < count; ++i) {
    in.skip_space();
    lines.push_back(in.line());
    std::array<Index, N> element;
    for (std::size_t k = 0; k < N; ++k) {
      const std::int64_t v = in.integer("vertex index");
      // Range against the vertex count is checked once all sections are read
      // (libMeshb does not require Vertices to come first).
      if (v < 1 || v >= static_cast<std::int64_t>(kInvalidIndex))
        in.fail(std::string(kind) + " " + std::to_string(elements.size() + 1) + " refers to vertex " +
                std::to_string(v) + " (MEDIT vertex indices start at 1)");
      element[k] = static_cast<Index>(v - 1);
    }
    elements.push_back(element);
    labels.push_back(read_reference(in));
  }
}

template <std::size_t N>
void check_vertex_range(const std::vector<std::array<Index, N>>& elements, const std::vector<std::uint32_t>& lines,
                        std::size_t point_count, const char* kind, const std::string& source) {
  for (std::size_t e = 0; e < elements.size(); ++e)
    for (const Index v : elements[e])
      if (v >= point_count)
        throw InputError(located_message(source, lines[e],
                                         std::string(kind) + " " + std::to_string(e + 1) + " refers to vertex " +
                                             std::to_string(std::uint64_t{v} + 1) + " of " +
                                             std::to_string(point_count)));
}

}  // namespace

MeshBundle read_medit(std::string_view data, const std::string& source_name) {
  TextScanner in(data, source_name);
  in.set_comment_char('#');
  if (in.at_end()) in.fail("empty file");
  // libMeshb's binary files start with the integer 1, in either byte order.
  const std::string_view magic = data.substr(0, 4);
  if (magic == std::string_view("\1\0\0\0", 4) || magic == std::string_view("\0\0\0\1", 4))
    in.fail("binary MEDIT (.meshb) is not supported; save as ASCII .mesh");

  MeshBundle mesh;
  mesh.source_name = source_name;
  int dimension = 3;
  bool have_version = false;
  bool have_vertices = false;
  std::string previous_section;  // for "wrong count" messages

  while (!in.at_end()) {
    const std::uint32_t keyword_line = in.line();
    const std::string_view token = in.token();
    if (!is_keyword(token)) {
      if (previous_section.empty())
        in.fail("not a MEDIT file: expected 'MeshVersionFormatted', found '" + TextScanner::clip(token) + "'");
      in.fail("expected a keyword after section '" + previous_section + "', found '" + TextScanner::clip(token) +
              "' (does the section's count match its rows?)");
    }
    const std::string key = lower(token);
    if (!have_version && key != "meshversionformatted")
      in.fail("not a MEDIT file: expected 'MeshVersionFormatted', found '" + TextScanner::clip(token) + "'");
    previous_section = std::string(token);

    if (key == "end") break;
    if (key == "meshversionformatted") {
      const std::int64_t version = in.integer("format version");
      if (version < 1 || version > 4) in.fail("unsupported MeshVersionFormatted " + std::to_string(version));
      have_version = true;
    } else if (key == "dimension") {
      const std::int64_t d = in.integer("dimension");
      if (d != 2 && d != 3) in.fail("Dimension must be 2 or 3, found " + std::to_string(d));
      if (have_vertices) in.fail("Dimension after Vertices");
      dimension = static_cast<int>(d);
    } else if (key == "vertices") {
      const std::size_t count = checked_count(in, in.integer("vertex count"), dimension + 1, token);
      if (mesh.points.size() + count >= kInvalidIndex) in.fail("too many vertices for 32-bit indices");
      mesh.points.reserve(mesh.points.size() + count);
      mesh.lines.point_lines.reserve(mesh.points.size() + count);
      for (std::size_t i = 0; i < count; ++i) {
        in.skip_space();
        mesh.lines.point_lines.push_back(in.line());
        Vec3 p = Vec3::Zero();
        for (int k = 0; k < dimension; ++k) p[k] = in.real("vertex coordinate");
        in.integer("vertex reference");  // vertex references carry no meaning for structmesh
        mesh.points.push_back(p);
      }
      have_vertices = true;
    } else if (key == "triangles") {
      const std::size_t count = checked_count(in, in.integer("triangle count"), 4, token);
      read_elements(in, count, mesh.triangles, mesh.triangle_labels, mesh.lines.triangle_lines, "triangle");
    } else if (key == "quadrilaterals") {
      const std::size_t count = checked_count(in, in.integer("quadrilateral count"), 5, token);
      read_elements(in, count, mesh.quads, mesh.quad_labels, mesh.lines.quad_lines, "quadrilateral");
    } else if (key == "tetrahedra") {
      const std::size_t count = checked_count(in, in.integer("tetrahedron count"), 5, token);
      read_elements(in, count, mesh.tets, mesh.tet_labels, mesh.lines.tet_lines, "tetrahedron");
    } else if (key == "hexahedra") {
      const std::size_t count = checked_count(in, in.integer("hexahedron count"), 9, token);
      read_elements(in, count, mesh.hexes, mesh.hex_labels, mesh.lines.hex_lines, "hexahedron");
    } else {
      for (const std::string_view unsupported : kUnsupportedSections)
        if (key == unsupported)
          throw InputError(located_message(source_name, keyword_line,
                                           "MEDIT section '" + std::string(token) +
                                               "' is not supported: structmesh reads triangles, quadrilaterals, "
                                               "tetrahedra and hexahedra"));
      for (const std::string_view stem : kElementSectionStems)
        if (key.size() > stem.size() && key.compare(0, stem.size(), stem) == 0)
          throw InputError(located_message(source_name, keyword_line,
                                           "MEDIT section '" + std::string(token) +
                                               "' (higher-order elements) is not supported; export linear elements"));
      const SkippedSection* known = nullptr;
      for (const SkippedSection& s : kSkippedSections)
        if (key == s.name) known = &s;
      if (known != nullptr) {
        const std::int64_t width = known->width + known->dim_factor * dimension;
        const std::size_t rows = known->counted ? checked_count(in, in.integer("row count"), width, token) : 1;
        for (std::size_t i = 0; i < rows; ++i)
          for (std::int64_t k = 0; k < width; ++k) in.real("value");
      } else {
        // An unknown section: its layout is not known, so skip values up to the next
        // keyword (keywords are the only tokens that start with a letter).
        while (!in.at_end()) {
          const std::string_view rest = in.rest();
          if (std::isalpha(static_cast<unsigned char>(rest.front()))) break;
          in.token();
        }
      }
    }
  }
  if (!have_vertices) in.fail("no Vertices section");

  const std::size_t n = mesh.points.size();
  check_vertex_range(mesh.triangles, mesh.lines.triangle_lines, n, "triangle", source_name);
  check_vertex_range(mesh.quads, mesh.lines.quad_lines, n, "quadrilateral", source_name);
  check_vertex_range(mesh.tets, mesh.lines.tet_lines, n, "tetrahedron", source_name);
  check_vertex_range(mesh.hexes, mesh.lines.hex_lines, n, "hexahedron", source_name);
  return mesh;
}

namespace {

template <std::size_t N>
void write_section(std::string& out, const char* keyword, const std::vector<std::array<Index, N>>& elements,
                   const std::vector<std::int32_t>& labels) {
  if (elements.empty()) return;
  out += "\n";
  out += keyword;
  out += "\n";
  detail::volume_io::append_int(out, static_cast<std::int64_t>(elements.size()));
  out += "\n";
  for (std::size_t e = 0; e < elements.size(); ++e) {
    for (const Index v : elements[e]) {
      detail::volume_io::append_int(out, std::int64_t{v} + 1);
      out += ' ';
    }
    detail::volume_io::append_int(out, detail::volume_io::label_at(labels, e));
    out += '\n';
  }
}

}  // namespace

std::string write_medit(const MeshBundle& mesh) {
  detail::volume_io::check_writable(mesh, "MEDIT");
  std::string out;
  // Rough size guess: ~60 bytes per point, ~40 per element; avoids repeated regrowth.
  out.reserve(64 + 60 * mesh.points.size() + 40 * mesh.cell_count());
  // Version 2 means double-precision coordinates.
  out += "MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n";
  detail::volume_io::append_int(out, static_cast<std::int64_t>(mesh.points.size()));
  out += "\n";
  for (const Vec3& p : mesh.points) {
    for (int k = 0; k < 3; ++k) {
      detail::volume_io::append_real(out, p[k]);
      out += ' ';
    }
    out += "0\n";
  }
  write_section(out, "Triangles", mesh.triangles, mesh.triangle_labels);
  write_section(out, "Quadrilaterals", mesh.quads, mesh.quad_labels);
  write_section(out, "Tetrahedra", mesh.tets, mesh.tet_labels);
  write_section(out, "Hexahedra", mesh.hexes, mesh.hex_labels);
  out += "\nEnd\n";
  return out;
}

}  // namespace structmesh
