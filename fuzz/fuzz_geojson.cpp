// libFuzzer target for read_geojson: any input must give polygons or an InputError
// (nlohmann's own exceptions included, converted inside the reader), never a crash,
// a sanitizer report or another exception. Accepted polygons must be well formed
// and must read back with the same shape after write_geojson.
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace {

void require(bool condition) {
  if (!condition) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<structmesh::Polygon2> polygons;
  try {
    polygons = structmesh::read_geojson(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
  } catch (const structmesh::InputError&) {
    return 0;
  }
  require(!polygons.empty());
  for (const auto& polygon : polygons) {
    require(polygon.ring_count() >= 1 && polygon.ring_offsets.back() == polygon.points.size());
    for (std::size_t r = 0; r < polygon.ring_count(); ++r) require(polygon.ring(r).size() >= 3);
    for (const auto& p : polygon.points) require(p.allFinite());
  }
  // Whatever was accepted writes out and reads back (no exception may escape here).
  const auto again = structmesh::read_geojson(structmesh::write_geojson(polygons), "again");
  require(again.size() == polygons.size());
  for (std::size_t i = 0; i < again.size(); ++i) {
    require(again[i].ring_offsets == polygons[i].ring_offsets);
    require(again[i].coordinates == polygons[i].coordinates);
  }
  return 0;
}
