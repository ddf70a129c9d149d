// morse_voxel_size(): the voxelization resolution eta of §4.4.1, from a Morse analysis
// of the three height functions on the pseudo-polycube. Written here: it is a few
// lines over the mesh, and no library offers "critical values of a PL height function".
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace structmesh {

namespace {

// Heights compared with the vertex index as tie-breaker (symbolic perturbation), so
// flat facets of Q, whose vertices share a height up to rounding, are decided
// consistently and every vertex is regular, an extremum or a saddle.
bool higher(double height_a, Index a, double height_b, Index b) {
  return height_a != height_b ? height_a > height_b : a > b;
}

}  // namespace

MorseResolution morse_voxel_size(const TriMesh& surface, double epsilon, double max_size) {
  if (surface.triangles.empty()) throw InputError("morse_voxel_size: the surface has no triangles");
  if (!(epsilon > 0) || !(max_size > 0)) throw InputError("morse_voxel_size: epsilon and max_size must be positive");
  const std::size_t n = surface.points.size();
  MorseResolution result;
  result.size = max_size;
  std::vector<std::uint32_t> sign_changes(n);
  std::vector<double> critical;
  for (int axis = 0; axis < 3; ++axis) {
    // A vertex's link is a cycle of edges (a, b), one per incident triangle; the height
    // changes side (above/below the vertex) along the link an even number of times:
    // 0 at an extremum, 2 at a regular vertex, 4 or more at a saddle.
    std::fill(sign_changes.begin(), sign_changes.end(), 0);
    for (const auto& t : surface.triangles)
      for (int k = 0; k < 3; ++k) {
        const Index v = t[k], a = t[(k + 1) % 3], b = t[(k + 2) % 3];
        const double hv = surface.points[v][axis];
        if (higher(surface.points[a][axis], a, hv, v) != higher(surface.points[b][axis], b, hv, v)) ++sign_changes[v];
      }
    critical.clear();
    for (std::size_t v = 0; v < n; ++v)
      if (sign_changes[v] != 2) critical.push_back(surface.points[v][axis]);
    std::sort(critical.begin(), critical.end());
    // Group by chaining (heights closer than epsilon are one level, §4.4.1); a level is
    // represented by its mean.
    std::vector<double>& levels = result.levels[axis];
    double sum = 0;
    std::size_t members = 0;
    for (std::size_t i = 0; i < critical.size(); ++i) {
      if (members > 0 && critical[i] - critical[i - 1] >= epsilon) {
        levels.push_back(sum / static_cast<double>(members));
        sum = 0;
        members = 0;
      }
      sum += critical[i];
      ++members;
    }
    if (members > 0) levels.push_back(sum / static_cast<double>(members));
    for (std::size_t i = 1; i < levels.size(); ++i)
      result.size = std::min(result.size, (levels[i] - levels[i - 1]) / 3);
  }
  return result;
}

}  // namespace structmesh
