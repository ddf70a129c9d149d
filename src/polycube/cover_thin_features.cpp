// cover_thin_features(): the voxelization of §4.4.1 for shapes with parts thinner than a
// voxel. voxelize() keeps the voxels whose centres are inside, so a sheet-thin part (the
// TOSCA dog's ears) comes out as a sieve of voxels, every hole a handle the input does
// not have, and a thin neck can come out cut (an extra component); no refinement the
// resolution cap allows closes them all. Here the voxels the surface passes through may
// be added, nearest to the surface first, where the addition does not join a component
// to itself (that would make a handle): simple additions, merges of two components and
// closings of a sieve's holes. Voids that leaves are filled. Then the added voxels are
// removed again while they are simple (homotopic thinning, §4.4.2's simple-voxel test),
// farthest from the surface first, so only those the topology needs stay. Written here
// because no library grows and thins a voxel set under topological constraints; the
// triangle-box test and the distances are CGAL's.
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"
#include "voxel_neighbourhood.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numeric>

namespace structmesh {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Box = Kernel::Iso_cuboid_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

}  // namespace

std::size_t cover_thin_features(VoxelGrid& grid, const TriMesh& surface) {
  if (surface.triangles.empty()) throw InputError("cover_thin_features: the surface has no triangles");
  std::vector<Triangle> triangles;
  triangles.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles) {
    const Vec3 &a = surface.points[t[0]], &b = surface.points[t[1]], &c = surface.points[t[2]];
    triangles.emplace_back(Point(a.x(), a.y(), a.z()), Point(b.x(), b.y(), b.z()), Point(c.x(), c.y(), c.z()));
  }

  // The empty voxels whose closed cube a triangle meets. The grid keeps an empty layer
  // around the surface, so the ranges below stay inside it.
  std::vector<std::uint32_t> added;
  std::vector<std::uint8_t> marked(grid.occupied.size(), 0);
  for (const Triangle& t : triangles) {
    const auto bbox = t.bbox();
    const auto [x0, y0, z0] = grid.voxel_of(Vec3(bbox.xmin(), bbox.ymin(), bbox.zmin()));
    const auto [x1, y1, z1] = grid.voxel_of(Vec3(bbox.xmax(), bbox.ymax(), bbox.zmax()));
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const std::size_t i = grid.index(x, y, z);
          if (grid.occupied[i] || marked[i]) continue;
          const Vec3 lo = grid.vertex_position(x, y, z), hi = grid.vertex_position(x + 1, y + 1, z + 1);
          if (!CGAL::do_intersect(t, Box(Point(lo.x(), lo.y(), lo.z()), Point(hi.x(), hi.y(), hi.z())))) continue;
          marked[i] = 1;
          added.push_back(static_cast<std::uint32_t>(i));
        }
  }
  if (added.empty()) return 0;

  const Tree tree(triangles.begin(), triangles.end());
  std::vector<double> distance(added.size());
  for (std::size_t k = 0; k < added.size(); ++k) {
    const auto [x, y, z] = grid.coordinates(added[k]);
    const Vec3 c = grid.origin + grid.size * Vec3(x + 0.5, y + 0.5, z + 0.5);
    distance[k] = tree.squared_distance(Point(c.x(), c.y(), c.z()));
  }
  std::vector<std::size_t> order(added.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return distance[a] < distance[b]; });

  // The 26-connected components of the occupied voxels, as labels with a union-find
  // over them, so an addition can tell two of its neighbouring pieces apart globally.
  std::vector<std::int32_t> label(grid.occupied.size(), -1);
  std::vector<std::int32_t> parent;
  {
    std::vector<std::uint32_t> stack;
    for (std::size_t i = 0; i < grid.occupied.size(); ++i) {
      if (!grid.occupied[i] || label[i] >= 0) continue;
      const auto id = static_cast<std::int32_t>(parent.size());
      parent.push_back(id);
      label[i] = id;
      stack.assign(1, static_cast<std::uint32_t>(i));
      while (!stack.empty()) {
        const auto [x, y, z] = grid.coordinates(stack.back());
        stack.pop_back();
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              if (!grid.at(x + dx, y + dy, z + dz)) continue;
              const std::size_t j = grid.index(x + dx, y + dy, z + dz);
              if (label[j] >= 0) continue;
              label[j] = id;
              stack.push_back(static_cast<std::uint32_t>(j));
            }
      }
    }
  }
  const auto find = [&](std::int32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };

  // Growth, in passes until one adds nothing: a hole in a sieve closes from its rim.
  std::vector<std::uint8_t> grown(added.size(), 0);
  std::array<std::uint32_t, 26> pieces{};
  for (bool changed = true; changed;) {
    changed = false;
    for (const std::size_t k : order) {
      if (grown[k]) continue;
      const auto [x, y, z] = grid.coordinates(added[k]);
      const int count = voxel::occupied_components(voxel::neighbourhood(grid, x, y, z), pieces);
      if (count == 0) continue;  // a new component
      std::array<std::int32_t, 26> roots{};
      bool handle = false;
      for (int c = 0; c < count && !handle; ++c) {
        const int bit = std::countr_zero(pieces[c]);
        roots[c] = find(label[grid.index(x + bit % 3 - 1, y + (bit / 3) % 3 - 1, z + bit / 9 - 1)]);
        for (int d = 0; d < c; ++d) handle = handle || roots[d] == roots[c];
      }
      if (handle) continue;
      for (int c = 1; c < count; ++c) parent[roots[c]] = roots[0];
      grid.occupied[added[k]] = 1;
      label[added[k]] = roots[0];
      grown[k] = 1;
      changed = true;
    }
  }

  // Voids: the empty voxels that the empty space outside (6-connected) does not reach.
  std::size_t filled = 0;
  {
    std::vector<std::uint8_t> outside(grid.occupied.size(), 0);
    std::vector<std::uint32_t> stack;
    for (std::size_t i = 0; i < grid.occupied.size(); ++i) {
      const auto [x, y, z] = grid.coordinates(static_cast<std::uint32_t>(i));
      const bool border =
          x == 0 || y == 0 || z == 0 || x == grid.dims[0] - 1 || y == grid.dims[1] - 1 || z == grid.dims[2] - 1;
      if (!border || grid.occupied[i] || outside[i]) continue;
      outside[i] = 1;
      stack.assign(1, static_cast<std::uint32_t>(i));
      while (!stack.empty()) {
        const auto [cx, cy, cz] = grid.coordinates(stack.back());
        stack.pop_back();
        for (int a = 0; a < 3; ++a)
          for (const int step : {-1, 1}) {
            std::array<int, 3> n{cx, cy, cz};
            n[a] += step;
            if (!grid.inside(n[0], n[1], n[2])) continue;
            const std::size_t j = grid.index(n[0], n[1], n[2]);
            if (grid.occupied[j] || outside[j]) continue;
            outside[j] = 1;
            stack.push_back(static_cast<std::uint32_t>(j));
          }
      }
    }
    for (std::size_t i = 0; i < grid.occupied.size(); ++i)
      if (!grid.occupied[i] && !outside[i]) {
        grid.occupied[i] = 1;
        ++filled;
      }
  }

  // Thinning, farthest from the surface first, in passes until one removes nothing: a
  // voxel refused because a neighbour later in the order still held it gets another
  // chance. Filled voids are not candidates: they were outside the surface's reach.
  std::size_t kept = filled;
  for (const std::uint8_t g : grown) kept += g;
  for (bool removed = true; removed;) {
    removed = false;
    for (auto k = order.rbegin(); k != order.rend(); ++k) {
      const std::uint32_t i = added[*k];
      if (!grid.occupied[i]) continue;
      const auto [x, y, z] = grid.coordinates(i);
      if (!is_simple_voxel(grid, x, y, z)) continue;
      grid.occupied[i] = 0;
      --kept;
      removed = true;
    }
  }
  return kept;
}

}  // namespace structmesh
