// Internal: pieces shared by the OBJ, OFF, PLY and STL readers and writers.
#pragma once

#include "mesh/binary_scalar.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <bit>
#include <charconv>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace structmesh::detail {

/// Largest point or element count a file may announce: every index must fit in
/// an Index and differ from kInvalidIndex.
inline constexpr std::uint64_t kMaxCount = kInvalidIndex - 1;

inline bool is_blank(std::string_view data) {
  for (const char c : data)
    if (c != ' ' && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != '\v') return false;
  return true;
}

/// Adds one polygon face: triangles and quads are kept as they are, larger
/// polygons are fan-triangulated around their first corner. `line` is recorded
/// per element when it is non-zero (text formats).
inline void add_polygon(MeshBundle& mesh, std::span<const Index> corners, std::uint32_t line) {
  if (corners.size() == 4) {
    mesh.quads.push_back({corners[0], corners[1], corners[2], corners[3]});
    if (line != 0) mesh.lines.quad_lines.push_back(line);
    return;
  }
  for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
    mesh.triangles.push_back({corners[0], corners[i], corners[i + 1]});
    if (line != 0) mesh.lines.triangle_lines.push_back(line);
  }
}

/// Surface writers store triangles and quads only, and every index they write
/// must name a point; anything else would silently lose cells or produce a file
/// the readers reject.
inline void check_writable_surface(const MeshBundle& mesh, const char* format) {
  if (!mesh.tets.empty() || !mesh.hexes.empty())
    throw InputError(located_message(mesh.source_name, 0,
                                     std::string(format) + " stores surfaces only, but the mesh has " +
                                         std::to_string(mesh.tets.size()) + " tetrahedra and " +
                                         std::to_string(mesh.hexes.size()) + " hexahedra"));
  const auto check = [&](const auto& elements, const char* kind) {
    for (std::size_t e = 0; e < elements.size(); ++e)
      for (const Index v : elements[e])
        if (v >= mesh.points.size())
          throw InputError(located_message(mesh.source_name, 0,
                                           std::string(kind) + " " + std::to_string(e) + " refers to point " +
                                               std::to_string(v) + " of " + std::to_string(mesh.points.size())));
  };
  check(mesh.triangles, "triangle");
  check(mesh.quads, "quad");
}

/// Shortest decimal form that reads back to the same double (std::to_chars
/// without a precision), so ASCII files round-trip exactly.
inline void append_real(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, static_cast<std::size_t>(result.ptr - buffer));
}

inline void append_integer(std::string& out, std::uint64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, static_cast<std::size_t>(result.ptr - buffer));
}

/// Appends one line per point, `prefix` (OBJ's "v ") then "x y z" in exact reals.
inline void append_point_lines(std::string& out, const std::vector<Vec3>& points, std::string_view prefix = {}) {
  for (const Vec3& p : points) {
    out += prefix;
    for (int k = 0; k < 3; ++k) {
      if (k != 0) out += ' ';
      append_real(out, p[k]);
    }
    out += '\n';
  }
}

/// Appends one line per triangle, then per quad: the corner count, then the
/// 0-based point indices (OFF, ASCII PLY).
inline void append_counted_face_lines(std::string& out, const MeshBundle& mesh) {
  const auto append_faces = [&](const auto& elements) {
    for (const auto& element : elements) {
      append_integer(out, element.size());
      for (const Index v : element) {
        out += ' ';
        append_integer(out, v);
      }
      out += '\n';
    }
  };
  append_faces(mesh.triangles);
  append_faces(mesh.quads);
}

/// A bounds-checked cursor over binary data. Every read checks the remaining
/// size first, so a truncated or lying file ends in an InputError, never in an
/// out-of-bounds read.
class ByteReader {
 public:
  ByteReader(std::string_view data, const std::string& source, bool big_endian)
      : data_(data), source_(source), swap_(big_endian != (std::endian::native == std::endian::big)) {}

  std::size_t remaining() const { return data_.size() - pos_; }
  std::string_view rest() const { return data_.substr(pos_); }

  /// Throws unless `count` more bytes are available; `what` names the data in the message.
  void require(std::uint64_t count, const char* what) const {
    if (count > remaining())
      throw InputError(located_message(source_, 0,
                                       std::string("file is truncated: ") + what + " needs " + std::to_string(count) +
                                           " bytes at offset " + std::to_string(pos_) + ", only " +
                                           std::to_string(remaining()) + " remain"));
  }
  void skip(std::uint64_t count, const char* what) {
    require(count, what);
    pos_ += static_cast<std::size_t>(count);
  }
  template <typename T>
  T read(const char* what) {
    require(sizeof(T), what);
    const T value = load_scalar<T>(data_.data() + pos_, swap_);
    pos_ += sizeof(T);
    return value;
  }

 private:
  std::string_view data_;
  const std::string& source_;
  std::size_t pos_ = 0;
  bool swap_;
};

}  // namespace structmesh::detail
