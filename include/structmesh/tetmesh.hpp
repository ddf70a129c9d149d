// Tetrahedral mesh of the solid bounded by a closed triangle surface (TetGen 1.5 as a
// library), keeping the surface: its points come first, unchanged and in input
// order, and the boundary faces of the tets are exactly its triangles.
#pragma once

#include "structmesh/mesh.hpp"

#include <cstddef>

namespace structmesh {

struct TetmeshOptions {
  double size = 0;                 // target tet edge length; 0 = mean edge length of the surface
  double radius_edge_ratio = 1.5;  // TetGen -q bound on circumradius / shortest edge; at least 1
  bool check_input = true;         // check_surface() first and reject anything but a valid solid boundary
};

struct TetmeshResult {
  TetMesh mesh;                     // surface points first (bit-identical, input order), then interior points
  std::size_t boundary_faces = 0;   // faces with one tet (equal to the surface's triangle count)
  std::size_t interior_points = 0;  // points TetGen added (all strictly inside)
  double size = 0;                  // the target edge length used
  double surface_volume = 0;        // enclosed by the surface (divergence theorem)
  double mesh_volume = 0;           // sum of the tet volumes
  double min_tet_volume = 0;
  double min_dihedral_deg = 0, max_dihedral_deg = 0;  // over all tets
  double seconds = 0;                                 // wall time of the whole call (checks included)
};

/// Throws InputError for an empty surface, invalid options, or (with check_input) a surface
/// that is not a valid solid boundary: open, non-manifold, inconsistently oriented,
/// self-intersecting, degenerate, inward (negative signed volume) or with unused points.
/// Throws Error when TetGen fails or its output breaks the contract above. Without
/// check_input the caller vouches for the surface: TetGen 1.5.0 (Debian) crashes in its
/// own clean-up when it gives up on a bad surface (e.g. a self-intersecting one).
/// A surface enclosing a cavity (a shell nested in another) is an InputError too.
TetmeshResult tetrahedralize(const TriMesh& surface, const TetmeshOptions& options = {});

/// Mean length of a surface's triangle edges (each shared edge counted twice); 0 without
/// triangles. The default tet size.
double mean_edge_length(const TriMesh& surface);

/// What repair_solid_surface() changed.
struct SurfaceRepair {
  std::size_t holes = 0, added_faces = 0;  ///< holes closed, triangles added to close them
  bool turned = false;                     ///< every face turned: the normals pointed inward
};

/// The `--repair` of guard and hex: every hole closed (fill_holes(), CGAL's minimum-area
/// hole triangulation), then every face turned if the enclosed volume is negative.
/// Self-intersections are left as they are. InputError when a hole cannot be closed.
SurfaceRepair repair_solid_surface(TriMesh& surface);

}  // namespace structmesh
