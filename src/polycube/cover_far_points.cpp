// cover_far_points(): the voxels that bring the parts of Q no voxel reaches back into the
// polycube. voxelize() keeps the voxels whose centres lie inside Q, so a part of Q thinner
// than a voxel and hanging off the rest (the TOSCA dog's tail, which the pre-deformation
// flattens to a plate 0.99 voxels thick) has no voxel at all, and as the topology does not
// notice (an appendage has none of its own), neither the refinement of §4.4.1 nor
// cover_thin_features() brings it back: the polycube, and the hex mesh, lack it, 0.2 of
// the diagonal away. Where some vertex of Q has no occupied voxel within five voxels of its
// own (by index), each vertex with none within one is "far", and the empty voxels that the
// triangles at far vertices pass through are added, in passes from the voxels already there
// outwards, each where it touches the set (a 26-neighbour) and its addition is simple
// (§4.4.2's test), so the topology stays as it was. Written here because no library grows a
// voxel set under that constraint; the triangle-box test is CGAL's.
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace structmesh {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;

constexpr int kTriggerRadius = 5;

}  // namespace

std::size_t cover_far_points(VoxelGrid& grid, const TriMesh& surface) {
  if (grid.occupied.empty()) throw InputError("cover_far_points: the grid has no voxels");
  // Only where some vertex is kTriggerRadius voxels from every voxel: a vertex a voxel or
  // two out is the rounding of a curved surface (the kittens and the screwdriver have a
  // dozen), which the hex mesh's projection onto the input takes care of; the dog's tail
  // has 217 vertices five voxels out and 200 eight.
  bool triggered = false;
  for (std::size_t v = 0; v < surface.points.size() && !triggered; ++v) {
    const auto [x, y, z] = grid.voxel_of(surface.points[v]);
    triggered = !grid.occupied_within(x, y, z, kTriggerRadius);
  }
  if (!triggered) return 0;
  std::vector<std::uint8_t> far(surface.points.size(), 0);
  for (std::size_t v = 0; v < surface.points.size(); ++v) {
    const auto [x, y, z] = grid.voxel_of(surface.points[v]);
    far[v] = !grid.occupied_within(x, y, z, 1);
  }

  // The empty voxels whose closed cube a triangle with a far vertex meets.
  std::vector<std::uint32_t> candidates;
  std::vector<std::uint8_t> marked(grid.occupied.size(), 0);
  for (const auto& t : surface.triangles) {
    if (!far[t[0]] && !far[t[1]] && !far[t[2]]) continue;
    const Vec3 &a = surface.points[t[0]], &b = surface.points[t[1]], &c = surface.points[t[2]];
    const Kernel::Triangle_3 triangle({a.x(), a.y(), a.z()}, {b.x(), b.y(), b.z()}, {c.x(), c.y(), c.z()});
    const Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    const auto first = grid.voxel_of(lo), last = grid.voxel_of(hi);
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y)
        for (int x = first[0]; x <= last[0]; ++x) {
          const std::size_t i = grid.index(x, y, z);
          if (grid.occupied[i] || marked[i]) continue;
          const Vec3 box_lo = grid.vertex_position(x, y, z), box_hi = grid.vertex_position(x + 1, y + 1, z + 1);
          if (!CGAL::do_intersect(triangle, Kernel::Iso_cuboid_3({box_lo.x(), box_lo.y(), box_lo.z()},
                                                                 {box_hi.x(), box_hi.y(), box_hi.z()})))
            continue;
          marked[i] = 1;
          candidates.push_back(static_cast<std::uint32_t>(i));
        }
  }
  std::sort(candidates.begin(), candidates.end());

  // Growth in passes: a pass adds the candidates that touch the set as it was at the
  // pass's start (so the set grows one ring per pass, the same whatever the order) and
  // are simple to add, checked in index order on the set as it grows.
  std::size_t added = 0;
  std::vector<std::uint32_t> touching;
  for (bool grew = true; grew;) {
    grew = false;
    touching.clear();
    for (const std::uint32_t i : candidates) {
      if (grid.occupied[i]) continue;
      const auto [x, y, z] = grid.coordinates(i);
      if (grid.occupied_within(x, y, z, 1)) touching.push_back(i);  // i itself is empty
    }
    for (const std::uint32_t i : touching) {
      const auto [x, y, z] = grid.coordinates(i);
      if (!is_simple_voxel(grid, x, y, z)) continue;
      grid.occupied[i] = 1;
      ++added;
      grew = true;
    }
  }
  return added;
}

}  // namespace structmesh
