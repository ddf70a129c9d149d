// Wavefront OBJ: `v` and `f` statements. Everything else in the format (texture
// coordinates, normals, groups, materials, free-form geometry) carries nothing a
// surface mesh needs and is skipped.
#include "mesh/surface_io.hpp"
#include "mesh/text_scanner.hpp"
#include "structmesh/io.hpp"

#include <algorithm>
#include <array>
#include <string_view>
#include <vector>

namespace structmesh {

namespace {

// Statements of the OBJ specification that are skipped. Anything else is
// reported, so that a file that is not OBJ at all does not read as empty.
constexpr std::array<std::string_view, 35> kIgnoredStatements{
    "vt",       "vn",     "vp",     "g",      "o",          "s",         "usemtl", "mtllib", "l",
    "p",        "cstype", "deg",    "bmat",   "step",       "curv",      "curv2",  "surf",   "parm",
    "trim",     "hole",   "scrv",   "sp",     "end",        "con",       "mg",     "bevel",  "c_interp",
    "d_interp", "lod",    "maplib", "usemap", "shadow_obj", "trace_obj", "ctech",  "stech"};

// Positive indices may refer to vertices defined later in the file, so they are
// checked once all vertices are known. Reports the earliest offending line.
template <std::size_t N>
void find_first_bad_index(const std::vector<std::array<Index, N>>& elements, const std::vector<std::uint32_t>& lines,
                          std::size_t point_count, std::uint32_t& bad_line, Index& bad_vertex) {
  for (std::size_t e = 0; e < elements.size(); ++e) {
    if (bad_line != 0 && lines[e] >= bad_line) return;  // lines ascend within one element kind
    for (const Index v : elements[e]) {
      if (v >= point_count) {
        bad_line = lines[e];
        bad_vertex = v;
        return;
      }
    }
  }
}

}  // namespace

MeshBundle read_obj(std::string_view data, const std::string& source_name) {
  if (detail::is_blank(data)) throw InputError(located_message(source_name, 0, "empty file"));
  detail::TextScanner in(data, source_name);
  in.set_comment_char('#');
  MeshBundle mesh;
  mesh.source_name = source_name;
  std::vector<Index> corners;
  while (!in.at_end()) {
    const std::uint32_t line = in.line();
    const std::string_view keyword = in.token_on_line();
    if (keyword == "v") {
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        const std::string_view tok = in.token_on_line();
        if (tok.empty()) in.fail("vertex has fewer than 3 coordinates");
        p[k] = in.parse_real(tok, "vertex coordinate");
      }
      if (mesh.points.size() >= detail::kMaxCount) in.fail("too many vertices for 32-bit indices");
      mesh.points.push_back(p);
      mesh.lines.point_lines.push_back(line);
      in.skip_line();  // an optional w, or the widespread "x y z r g b" colour extension
    } else if (keyword == "f") {
      corners.clear();
      for (std::string_view tok = in.token_on_line(); !tok.empty(); tok = in.token_on_line()) {
        // "v", "v/vt", "v//vn" or "v/vt/vn": only the vertex index matters.
        const std::string_view number = tok.substr(0, tok.find('/'));
        if (number.empty()) in.fail("expected a vertex index, found '" + in.clip(tok) + "'");
        const std::int64_t value = in.parse_integer(number, "vertex index");
        const auto count = static_cast<std::int64_t>(mesh.points.size());
        if (value > 0) {
          if (value > static_cast<std::int64_t>(detail::kMaxCount))
            in.fail("face refers to vertex " + std::to_string(value) + " of " + std::to_string(count));
          corners.push_back(static_cast<Index>(value - 1));
        } else if (value < 0) {
          // Relative: -1 is the most recently defined vertex.
          if (value < -count)
            in.fail("face refers to vertex " + std::to_string(value) + ", but only " + std::to_string(count) +
                    " vertices precede it");
          corners.push_back(static_cast<Index>(count + value));
        } else {
          in.fail("vertex index 0 is invalid (OBJ indices start at 1)");
        }
      }
      if (corners.size() < 3)
        in.fail("face has " + std::to_string(corners.size()) + " vertices; at least 3 are needed");
      detail::add_polygon(mesh, corners, line);
      in.skip_line();
    } else if (std::find(kIgnoredStatements.begin(), kIgnoredStatements.end(), keyword) != kIgnoredStatements.end()) {
      in.skip_line();
    } else {
      in.fail("unknown OBJ statement '" + in.clip(keyword) + "'");
    }
  }
  if (mesh.points.empty()) throw InputError(located_message(source_name, 0, "holds no vertices"));
  if (mesh.cell_count() > detail::kMaxCount)
    throw InputError(located_message(source_name, 0, "too many faces for 32-bit indices"));

  std::uint32_t bad_line = 0;
  Index bad_vertex = 0;
  find_first_bad_index(mesh.triangles, mesh.lines.triangle_lines, mesh.points.size(), bad_line, bad_vertex);
  find_first_bad_index(mesh.quads, mesh.lines.quad_lines, mesh.points.size(), bad_line, bad_vertex);
  if (bad_line != 0)
    throw InputError(located_message(source_name, bad_line,
                                     "face refers to vertex " + std::to_string(std::uint64_t{bad_vertex} + 1) + " of " +
                                         std::to_string(mesh.points.size())));
  return mesh;
}

std::string write_obj(const MeshBundle& mesh) {
  detail::check_writable_surface(mesh, "OBJ");
  std::string out;
  out.reserve(mesh.points.size() * 64 + mesh.triangles.size() * 24 + mesh.quads.size() * 32 + 64);
  out += "# written by structmesh: ";
  detail::append_integer(out, mesh.points.size());
  out += " vertices, ";
  detail::append_integer(out, mesh.triangles.size() + mesh.quads.size());
  out += " faces\n";
  detail::append_point_lines(out, mesh.points, "v ");
  const auto write_faces = [&](const auto& elements) {
    for (const auto& element : elements) {
      out += 'f';
      for (const Index v : element) {
        out += ' ';
        detail::append_integer(out, std::uint64_t{v} + 1);
      }
      out += '\n';
    }
  };
  write_faces(mesh.triangles);
  write_faces(mesh.quads);
  return out;
}

}  // namespace structmesh
