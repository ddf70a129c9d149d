// --repair of a closed-surface input (guard, hex): holes closed, an inward surface turned.
#include "cli.hpp"
#include "structmesh/error.hpp"
#include "structmesh/tetmesh.hpp"

namespace structmesh::cli {

nlohmann::json repair_surface(TriMesh& surface, const std::string& input, const GlobalOptions& global) {
  SurfaceRepair repair;
  try {
    repair = repair_solid_surface(surface);
  } catch (const InputError& e) {
    throw InputError(input + ": --repair: " + e.what());
  }
  if (repair.holes > 0 || repair.turned)
    say(global, "--repair: " + std::to_string(repair.holes) + " holes closed with " +
                    std::to_string(repair.added_faces) + " faces" + (repair.turned ? "; surface turned outward" : ""));
  return {{"holes_filled", repair.holes}, {"faces_added", repair.added_faces}, {"flipped", repair.turned}};
}

}  // namespace structmesh::cli
