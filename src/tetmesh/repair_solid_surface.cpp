// repair_solid_surface() (tetmesh.hpp): what --repair fixes in a closed-surface input.
#include "structmesh/check.hpp"
#include "structmesh/tetmesh.hpp"

#include <utility>

namespace structmesh {

SurfaceRepair repair_solid_surface(TriMesh& surface) {
  HoleFilling filled = fill_holes(surface);
  surface = std::move(filled.surface);
  SurfaceRepair repair{filled.holes, filled.added_faces, enclosed_volume(surface) < 0};
  if (repair.turned)
    for (auto& t : surface.triangles) std::swap(t[1], t[2]);
  return repair;
}

}  // namespace structmesh
