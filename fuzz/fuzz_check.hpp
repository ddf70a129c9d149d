// Shared by the fuzz targets: what must hold for every input a reader accepts.
// A violation traps, so libFuzzer records the input as a crash.
#pragma once

#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace structmesh::fuzz {

using Reader = MeshBundle (*)(std::string_view, const std::string&);

inline void require(bool condition) {
  if (!condition) __builtin_trap();
}

/// Reads `data`; InputError is the only acceptable failure. An accepted mesh must
/// have finite points and in-range indices, and must come back unchanged from
/// `write` followed by `read` (any exception there escapes and counts as a crash).
template <typename Write>
void check_reader(const std::uint8_t* data, std::size_t size, Reader read, Write write) {
  MeshBundle mesh;
  try {
    mesh = read(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
  } catch (const InputError&) {
    return;
  }
  require(!mesh.points.empty());
  for (const Vec3& p : mesh.points) require(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()));
  for (const auto& t : mesh.triangles)
    for (const Index v : t) require(v < mesh.points.size());
  for (const auto& q : mesh.quads)
    for (const Index v : q) require(v < mesh.points.size());
  const MeshBundle again = read(write(mesh), "fuzz round trip");
  require(again.points == mesh.points && again.triangles == mesh.triangles && again.quads == mesh.quads);
}

}  // namespace structmesh::fuzz
