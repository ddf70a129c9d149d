// points_to_lonlat(): the inverse of the projection partition_region() uses for
// lon/lat regions, so meshes can be written back in degrees (--lonlat-output).
#include "partition2d/partition_internal.hpp"

#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"

#include <oneapi/tbb/parallel_for.h>

namespace structmesh {

void points_to_lonlat(const Polygon2& region, std::vector<Vec3>& points) {
  const partition2d::Projection projection = partition2d::choose_projection(region);
  if (!projection.active) throw InputError("--lonlat-output needs a lon/lat region (this one is planar)");
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
    const Vec2 lonlat = projection.inverse(points[i].head<2>());
    points[i] = Vec3(lonlat.x(), lonlat.y(), 0.0);
  });
}

}  // namespace structmesh
