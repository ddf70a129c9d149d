// Geomview OFF: header, counts, one vertex per line, one face per line.
// The ST/C/N variants (texture coordinates, colours, normals after x y z) are
// read with their extra vertex values ignored; 4D, n-dimensional and binary OFF
// are rejected by name.
#include "mesh/surface_io.hpp"
#include "mesh/text_scanner.hpp"
#include "structmesh/io.hpp"

#include <string_view>
#include <vector>

namespace structmesh {

namespace {

std::uint64_t read_count(detail::TextScanner& in, const char* what) {
  const std::string_view tok = in.token_on_line();
  if (tok.empty()) in.fail(std::string("the counts line lacks the ") + what + " count");
  const std::int64_t value = in.parse_integer(tok, what);
  if (value < 0) in.fail(std::string("negative ") + what + " count " + std::to_string(value));
  if (static_cast<std::uint64_t>(value) > detail::kMaxCount)
    in.fail(std::string(what) + " count " + std::to_string(value) + " does not fit 32-bit indices");
  return static_cast<std::uint64_t>(value);
}

}  // namespace

MeshBundle read_off(std::string_view data, const std::string& source_name) {
  if (detail::is_blank(data)) throw InputError(located_message(source_name, 0, "empty file"));
  detail::TextScanner in(data, source_name);
  in.set_comment_char('#');
  if (in.at_end()) in.fail("holds only comments, no OFF header");

  // Header: [ST][C][N][4][n]OFF, optionally followed by the counts on the same line.
  const std::string_view header = in.token_on_line();
  if (header.size() < 3 || header.substr(header.size() - 3) != "OFF")
    in.fail("expected the OFF header, found '" + in.clip(header) + "'");
  std::string_view prefix = header.substr(0, header.size() - 3);
  for (const std::string_view known : {"ST", "C", "N"})
    if (prefix.starts_with(known)) prefix.remove_prefix(known.size());
  if (prefix == "4" || prefix == "n" || prefix == "4n")
    in.fail(std::string(header) + " (4D or n-dimensional OFF) is not supported");
  if (!prefix.empty()) in.fail("unknown OFF variant '" + in.clip(header) + "'");
  const bool vertex_extras = header.size() > 3;
  if (!in.at_line_end()) {
    const std::string_view rest = in.rest();
    if (rest.substr(0, rest.find_first_of(" \t\r\n")) == "BINARY")
      in.fail("binary OFF is not supported; convert it to ASCII OFF or PLY");
  } else {
    in.skip_line();
    if (in.at_end()) in.fail("missing the vertex, face and edge counts after the header");
  }

  const std::uint32_t counts_line = in.line();
  const std::uint64_t vertex_count = read_count(in, "vertex");
  const std::uint64_t face_count = read_count(in, "face");
  if (!in.at_line_end()) in.parse_integer(in.token_on_line(), "edge count");  // unused, but must be a number
  if (!in.at_line_end()) in.fail("unexpected value after the vertex, face and edge counts");
  in.skip_line();
  // The shortest vertex line is "0 0 0\n" and the shortest face line "3 0 0 0\n".
  // Half of that bounds the counts before anything is reserved, and leaves a file
  // that is only slightly short to the precise messages below.
  const std::uint64_t remaining = in.rest().size();
  const auto fail_counts = [&](const std::string& message) {
    throw InputError(located_message(source_name, counts_line, message));
  };
  if (vertex_count * 3 + face_count * 4 > remaining + 1)
    fail_counts("the header announces " + std::to_string(vertex_count) + " vertices and " + std::to_string(face_count) +
                " faces, more than the remaining " + std::to_string(remaining) + " bytes can hold");
  if (vertex_count == 0) fail_counts("the header announces no vertices");

  MeshBundle mesh;
  mesh.source_name = source_name;
  mesh.points.reserve(vertex_count);
  mesh.lines.point_lines.reserve(vertex_count);
  for (std::uint64_t i = 0; i < vertex_count; ++i) {
    if (in.at_end())
      in.fail("file ends after " + std::to_string(i) + " of " + std::to_string(vertex_count) + " vertices");
    mesh.lines.point_lines.push_back(in.line());
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      const std::string_view tok = in.token_on_line();
      if (tok.empty()) in.fail("vertex has fewer than 3 coordinates");
      p[k] = in.parse_real(tok, "vertex coordinate");
    }
    // Plain OFF vertices have exactly 3 values; catching a 4th points at a wrong
    // vertex count on the right line instead of at a confusing face error later.
    if (!vertex_extras && !in.at_line_end())
      in.fail("vertex line has more than 3 values (wrong vertex count in the header?)");
    mesh.points.push_back(p);
    in.skip_line();
  }

  mesh.triangles.reserve(face_count);
  std::vector<Index> corners;
  for (std::uint64_t f = 0; f < face_count; ++f) {
    if (in.at_end()) in.fail("file ends after " + std::to_string(f) + " of " + std::to_string(face_count) + " faces");
    const std::uint32_t line = in.line();
    const std::int64_t k = in.parse_integer(in.token_on_line(), "face vertex count");
    if (k < 3) in.fail("face has " + std::to_string(k) + " vertices; at least 3 are needed");
    corners.clear();
    for (std::int64_t j = 0; j < k; ++j) {
      const std::string_view tok = in.token_on_line();
      if (tok.empty()) in.fail("face announces " + std::to_string(k) + " vertices but lists only " + std::to_string(j));
      const std::int64_t v = in.parse_integer(tok, "vertex index");
      if (v < 0 || static_cast<std::uint64_t>(v) >= vertex_count)
        in.fail("face refers to vertex " + std::to_string(v) + ", but vertices are numbered 0 to " +
                std::to_string(vertex_count - 1));
      corners.push_back(static_cast<Index>(v));
    }
    detail::add_polygon(mesh, corners, line);
    in.skip_line();  // optional colour values
  }
  if (!in.at_end()) in.fail("unexpected data after the " + std::to_string(face_count) + " faces the header announces");
  if (mesh.cell_count() > detail::kMaxCount) in.fail("too many faces for 32-bit indices");
  return mesh;
}

std::string write_off(const MeshBundle& mesh) {
  detail::check_writable_surface(mesh, "OFF");
  std::string out;
  out.reserve(mesh.points.size() * 64 + mesh.triangles.size() * 24 + mesh.quads.size() * 32 + 64);
  out += "OFF\n";
  detail::append_integer(out, mesh.points.size());
  out += ' ';
  detail::append_integer(out, mesh.triangles.size() + mesh.quads.size());
  out += " 0\n";
  detail::append_point_lines(out, mesh.points);
  detail::append_counted_face_lines(out, mesh);
  return out;
}

}  // namespace structmesh
