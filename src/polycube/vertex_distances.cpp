// vertex_distances(): the distance field D_Q of §4.4.1 sampled at the voxel grid's
// vertices, for the geometric deviation E_g of (4.1). Closest points come from CGAL's
// AABB tree (exact closest point on the triangles); only the band where the polycube's
// boundary can move is queried, which keeps a 200^3 grid to a few hundred thousand
// queries.
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace structmesh {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

// Marks every vertex within `reach` steps along `axis` of a marked one (a sliding
// window over each grid line; three passes give the Chebyshev neighbourhood).
void dilate_along(std::vector<std::uint8_t>& mark, const std::array<int, 3>& n, int axis, int reach) {
  const int other_a = (axis + 1) % 3, other_b = (axis + 2) % 3;
  const std::array<std::size_t, 3> stride{1, static_cast<std::size_t>(n[0]), static_cast<std::size_t>(n[0]) * n[1]};
  std::vector<int> last_marked(static_cast<std::size_t>(n[axis]));
  std::vector<std::uint8_t> line(static_cast<std::size_t>(n[axis]));
  for (int b = 0; b < n[other_b]; ++b)
    for (int a = 0; a < n[other_a]; ++a) {
      const std::size_t base = a * stride[other_a] + b * stride[other_b];
      for (int i = 0; i < n[axis]; ++i) line[i] = mark[base + i * stride[axis]];
      // Distance to the nearest marked vertex on the line, forward then backward.
      int distance = reach + 1;
      for (int i = 0; i < n[axis]; ++i) {
        distance = line[i] ? 0 : std::min(distance + 1, reach + 1);
        last_marked[i] = distance;
      }
      distance = reach + 1;
      for (int i = n[axis] - 1; i >= 0; --i) {
        distance = line[i] ? 0 : std::min(distance + 1, reach + 1);
        if (std::min(distance, last_marked[i]) <= reach) mark[base + i * stride[axis]] = 1;
      }
    }
}

}  // namespace

std::vector<double> vertex_distances(const VoxelGrid& grid, const TriMesh& surface, int band) {
  if (surface.triangles.empty()) throw InputError("vertex_distances: the surface has no triangles");
  const std::array<int, 3> n{grid.dims[0] + 1, grid.dims[1] + 1, grid.dims[2] + 1};
  // The vertices of the boundary squares: each corner of a voxel that has an empty
  // 6-neighbour (those corners include all of the separating square's).
  std::vector<std::uint8_t> near(grid.vertex_count(), 0);
  for (int z = 0; z < grid.dims[2]; ++z)
    for (int y = 0; y < grid.dims[1]; ++y)
      for (int x = 0; x < grid.dims[0]; ++x) {
        if (!grid.at(x, y, z)) continue;
        if (grid.at(x - 1, y, z) && grid.at(x + 1, y, z) && grid.at(x, y - 1, z) && grid.at(x, y + 1, z) &&
            grid.at(x, y, z - 1) && grid.at(x, y, z + 1))
          continue;
        for (int k = 0; k < 8; ++k) near[grid.vertex_index(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1))] = 1;
      }
  const int reach = std::max(0, band);
  for (int axis = 0; axis < 3; ++axis) dilate_along(near, n, axis, reach);

  std::vector<Triangle> triangles;
  triangles.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles) {
    const auto point = [&](Index v) {
      const Vec3& p = surface.points[v];
      return Kernel::Point_3(p.x(), p.y(), p.z());
    };
    triangles.emplace_back(point(t[0]), point(t[1]), point(t[2]));
  }
  Tree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();

  std::vector<double> distance(grid.vertex_count(), reach * grid.size);
  tbb::parallel_for(tbb::blocked_range<int>(0, n[2]), [&](const tbb::blocked_range<int>& range) {
    for (int z = range.begin(); z != range.end(); ++z)
      for (int y = 0; y < n[1]; ++y)
        for (int x = 0; x < n[0]; ++x) {
          const std::size_t v = grid.vertex_index(x, y, z);
          if (!near[v]) continue;
          const Vec3 p = grid.vertex_position(x, y, z);
          distance[v] = std::sqrt(tree.squared_distance(Kernel::Point_3(p.x(), p.y(), p.z())));
        }
  });
  return distance;
}

}  // namespace structmesh
