// voxelize(): the initial polycube of §4.4.1, the voxels of a regular grid whose centres
// lie inside the pseudo-polycube Q. Written here rather than with CGAL's
// Side_of_triangle_mesh (one ray per query point): a scanline fill casts one ray per
// row of voxels and fills whole rows, millions of voxels in well under a second.
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"

#include <Eigen/Geometry>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace structmesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;

// Side of point p of the line through a and b, decided exactly, with the edge always
// taken in one canonical direction (lexicographically smaller end first) so the two
// triangles sharing an edge see the same sign, and a point exactly on the edge counted
// on its positive side: a ray through an edge or a vertex crosses the surface the right
// number of times (the tie-break is a symbolic perturbation of the ray).
int edge_side(const Point2& a, const Point2& b, const Point2& p) {
  const bool forward = a < b;
  const CGAL::Orientation o = forward ? CGAL::orientation(a, b, p) : CGAL::orientation(b, a, p);
  const int canonical = o == CGAL::NEGATIVE ? -1 : 1;
  return forward ? canonical : -canonical;
}

std::string describe(double value) { return std::to_string(value); }

}  // namespace

VoxelGrid voxelize(const TriMesh& surface, double size, std::size_t max_voxels) {
  if (surface.triangles.empty()) throw InputError("voxelize: the surface has no triangles");
  if (!(size > 0)) throw InputError("voxelize: the voxel size must be positive, not " + describe(size));
  const BoundingBox3 box = surface.bounding_box();
  std::array<int, 3> dims{};
  double voxels = 1;
  for (int a = 0; a < 3; ++a) {
    const double inner = std::ceil((box.max[a] - box.min[a]) / size);
    if (!(inner < 1e6)) throw InputError("voxelize: voxel size " + describe(size) + " is too small for the surface");
    dims[a] = std::max(1, static_cast<int>(inner)) + 2;  // one empty layer on each side
    voxels *= dims[a];
  }
  if (voxels > static_cast<double>(max_voxels))
    throw InputError("voxelize: voxel size " + describe(size) + " gives " + describe(voxels) + " voxels, more than " +
                     std::to_string(max_voxels));
  const Vec3 centre = 0.5 * (box.min + box.max);
  VoxelGrid grid(dims, centre - 0.5 * size * Vec3(dims[0], dims[1], dims[2]), size);

  // Rays along +x through the centre of every row (y, z) of voxels; each triangle is
  // binned into the rows its (y, z) bounding box covers.
  const int rows_y = dims[1], rows_z = dims[2];
  const auto row_of = [&](int y, int z) { return static_cast<std::size_t>(y) + static_cast<std::size_t>(rows_y) * z; };
  std::vector<Index> row_offsets(static_cast<std::size_t>(rows_y) * rows_z + 1, 0);
  std::vector<std::array<int, 4>> ranges(surface.triangles.size());
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    double lo_y = std::numeric_limits<double>::max(), hi_y = -lo_y, lo_z = lo_y, hi_z = -lo_y;
    for (const Index v : surface.triangles[t]) {
      lo_y = std::min(lo_y, surface.points[v].y());
      hi_y = std::max(hi_y, surface.points[v].y());
      lo_z = std::min(lo_z, surface.points[v].z());
      hi_z = std::max(hi_z, surface.points[v].z());
    }
    // Rows whose centre coordinate c = origin + (i + 1/2) size lies in [lo, hi].
    const auto first = [&](double lo, int a) {
      return std::max(0, static_cast<int>(std::ceil((lo - grid.origin[a]) / size - 0.5)));
    };
    const auto last = [&](double hi, int a, int count) {
      return std::min(count - 1, static_cast<int>(std::floor((hi - grid.origin[a]) / size - 0.5)));
    };
    ranges[t] = {first(lo_y, 1), last(hi_y, 1, rows_y), first(lo_z, 2), last(hi_z, 2, rows_z)};
    for (int z = ranges[t][2]; z <= ranges[t][3]; ++z)
      for (int y = ranges[t][0]; y <= ranges[t][1]; ++y) ++row_offsets[row_of(y, z) + 1];
  }
  for (std::size_t r = 1; r < row_offsets.size(); ++r) row_offsets[r] += row_offsets[r - 1];
  std::vector<Index> row_triangles(row_offsets.back());
  {
    std::vector<Index> next(row_offsets.begin(), row_offsets.end() - 1);
    for (std::size_t t = 0; t < surface.triangles.size(); ++t)
      for (int z = ranges[t][2]; z <= ranges[t][3]; ++z)
        for (int y = ranges[t][0]; y <= ranges[t][1]; ++y) row_triangles[next[row_of(y, z)]++] = static_cast<Index>(t);
  }

  tbb::parallel_for(tbb::blocked_range<int>(0, rows_z), [&](const tbb::blocked_range<int>& range) {
    std::vector<double> crossings;
    for (int z = range.begin(); z != range.end(); ++z)
      for (int y = 0; y < rows_y; ++y) {
        const double py = grid.origin.y() + (y + 0.5) * size, pz = grid.origin.z() + (z + 0.5) * size;
        const Point2 p(py, pz);
        crossings.clear();
        for (Index k = row_offsets[row_of(y, z)]; k < row_offsets[row_of(y, z) + 1]; ++k) {
          const auto& t = surface.triangles[row_triangles[k]];
          const Vec3 &a = surface.points[t[0]], &b = surface.points[t[1]], &c = surface.points[t[2]];
          const Point2 a2(a.y(), a.z()), b2(b.y(), b.z()), c2(c.y(), c.z());
          if (CGAL::orientation(a2, b2, c2) == CGAL::COLLINEAR) continue;  // parallel to the ray
          const int s0 = edge_side(a2, b2, p), s1 = edge_side(b2, c2, p), s2 = edge_side(c2, a2, p);
          if (s0 != s1 || s1 != s2) continue;
          // The crossing's x: the plane of the triangle at (py, pz).
          const Vec3 normal = (b - a).cross(c - a);
          if (normal.x() == 0) continue;  // only when rounding flattened a sliver
          crossings.push_back(a.x() - (normal.y() * (py - a.y()) + normal.z() * (pz - a.z())) / normal.x());
        }
        std::sort(crossings.begin(), crossings.end());
        // Voxel x is inside when an odd number of crossings lie before its centre.
        std::size_t passed = 0;
        for (int x = 0; x < dims[0]; ++x) {
          const double px = grid.origin.x() + (x + 0.5) * size;
          while (passed < crossings.size() && crossings[passed] < px) ++passed;
          if (passed % 2 == 1) grid.occupied[grid.index(x, y, z)] = 1;
        }
      }
  });
  return grid;
}

}  // namespace structmesh
