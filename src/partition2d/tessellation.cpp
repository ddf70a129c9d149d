// Small helpers on the Tessellation of partition_internal.hpp.
#include "partition2d/partition_internal.hpp"

namespace structmesh::partition2d {

std::vector<double> face_areas(const Tessellation& tessellation) {
  std::vector<double> areas(tessellation.face_count(), 0.0);
  for (std::size_t f = 0; f < areas.size(); ++f) {
    // Shoelace formula around the face, relative to its first vertex (fewer
    // cancellation errors than around the origin for far-away faces).
    const Index begin = tessellation.face_offsets[f], end = tessellation.face_offsets[f + 1];
    const Vec2& origin = tessellation.vertices[tessellation.face_vertices[begin]];
    double twice = 0;
    for (Index h = begin + 1; h + 1 < end; ++h) {
      const Vec2 a = tessellation.vertices[tessellation.face_vertices[h]] - origin;
      const Vec2 b = tessellation.vertices[tessellation.face_vertices[h + 1]] - origin;
      twice += a.x() * b.y() - a.y() * b.x();
    }
    areas[f] = 0.5 * twice;
  }
  return areas;
}

}  // namespace structmesh::partition2d
