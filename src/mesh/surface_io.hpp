// Internal: pieces shared by the OBJ, OFF, PLY and STL readers and writers.
#pragma once

#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <utility>

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

/// Appends the bytes of an arithmetic value in little-endian order.
template <typename T>
void append_le(std::string& out, T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
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
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    if (swap_)
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }

 private:
  std::string_view data_;
  const std::string& source_;
  std::size_t pos_ = 0;
  bool swap_;
};

}  // namespace structmesh::detail
