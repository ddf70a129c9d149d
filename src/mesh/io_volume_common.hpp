// Internal helpers shared by the MEDIT, Gmsh and VTU readers and writers:
// exact number formatting, labels lookup and validating a bundle before writing.
// The nested namespace keeps these inline definitions apart from other readers'
// helpers in structmesh::detail (same-named inline functions would break the ODR).
#pragma once

#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <array>
#include <charconv>
#include <cstdint>
#include <string>
#include <vector>

namespace structmesh::detail::volume_io {

/// Appends the shortest decimal text that reads back as exactly `value`
/// (std::to_chars guarantees the round trip, so written meshes keep every bit).
inline void append_real(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

inline void append_int(std::string& out, std::int64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

/// The label of element i, 0 when the bundle carries no labels for that kind.
inline std::int32_t label_at(const std::vector<std::int32_t>& labels, std::size_t i) {
  return labels.empty() ? 0 : labels[i];
}

template <std::size_t N>
void check_writable_elements(const std::vector<std::array<Index, N>>& elements, const std::vector<std::int32_t>& labels,
                             std::size_t point_count, const char* kind, const char* format) {
  if (!labels.empty() && labels.size() != elements.size())
    throw Error(std::string("cannot write ") + format + ": " + std::to_string(labels.size()) + " " + kind +
                " labels for " + std::to_string(elements.size()) + " elements");
  for (std::size_t e = 0; e < elements.size(); ++e)
    for (const Index v : elements[e])
      if (v >= point_count)
        throw Error(std::string("cannot write ") + format + ": " + kind + " " + std::to_string(e) +
                    " refers to point " + std::to_string(v) + " of " + std::to_string(point_count));
}

/// Throws Error for a bundle that would produce an invalid file: indices out of
/// range, label arrays of the wrong length, more points than 32-bit indices address.
inline void check_writable(const MeshBundle& mesh, const char* format) {
  if (mesh.points.size() >= kInvalidIndex)
    throw Error(std::string("cannot write ") + format + ": too many points (" + std::to_string(mesh.points.size()) +
                ")");
  check_writable_elements(mesh.triangles, mesh.triangle_labels, mesh.points.size(), "triangle", format);
  check_writable_elements(mesh.quads, mesh.quad_labels, mesh.points.size(), "quad", format);
  check_writable_elements(mesh.tets, mesh.tet_labels, mesh.points.size(), "tetrahedron", format);
  check_writable_elements(mesh.hexes, mesh.hex_labels, mesh.points.size(), "hexahedron", format);
}

}  // namespace structmesh::detail::volume_io
