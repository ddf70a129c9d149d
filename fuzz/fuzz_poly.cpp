// libFuzzer target for read_poly: any input must give polygons or an InputError,
// never a crash, a sanitizer report or another exception. Accepted polygons must
// be well formed and must read back with the same number of points after write_poly.
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace {

void require(bool condition) {
  if (!condition) __builtin_trap();
}

std::size_t point_count(const std::vector<structmesh::Polygon2>& polygons) {
  std::size_t count = 0;
  for (const auto& polygon : polygons) count += polygon.points.size();
  return count;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<structmesh::Polygon2> polygons;
  try {
    polygons = structmesh::read_poly(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
  } catch (const structmesh::InputError&) {
    return 0;
  }
  for (const auto& polygon : polygons) {
    require(polygon.ring_count() >= 1 && polygon.ring_offsets.back() == polygon.points.size());
    for (std::size_t r = 0; r < polygon.ring_count(); ++r) require(polygon.ring(r).size() >= 3);
    for (const auto& p : polygon.points) require(p.allFinite());
  }
  // Whatever was accepted writes out and reads back (no exception may escape here).
  const auto again = structmesh::read_poly(structmesh::write_poly(polygons), "again");
  require(point_count(again) == point_count(polygons));
  return 0;
}
