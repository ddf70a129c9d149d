// The Gmsh 4.8 all-quad baseline of the quad meshing benchmark (dissertation §3.4):
// Gmsh's best all-quad mesh of a planar region, set up as RECIPES.md says. Not a
// library: the benchmark executables compile it and link the Gmsh library.
#pragma once

#include "structmesh/mesh.hpp"

#include <cstddef>
#include <string>

namespace structmesh {

struct GmshQuadResult {
  QuadMesh mesh;                       // z = 0, counter-clockwise quads (Gmsh's orientation flipped if clockwise)
  std::size_t leftover_triangles = 0;  // triangles Gmsh could not recombine (not in `mesh`)
  double seconds = 0;                  // mesh generation only (geometry setup excluded)
  std::string error;                   // Gmsh's message when it failed; empty on success
};

/// Gmsh's all-quad meshing of a planar region at element size h: Mesh.Algorithm =
/// `algorithm` (8 = Frontal-Delaunay for quads, with Mesh.CrossFieldClosestPoint = 0,
/// which Debian's build needs; 6 = Frontal-Delaunay), RecombineAll = 1,
/// RecombinationAlgorithm = 3 (Blossom full-quad), single thread. Every ring becomes
/// polyline curves through its points, split at corners (turning angle > 30 degrees,
/// at least 4 curves per ring), each meshed transfinitely with an even number of
/// segments of length about h (Blossom full-quad aborts on an odd count). Gmsh keeps
/// global state: it is initialized and finalized inside the call, so calls must not
/// run concurrently. Gmsh errors are returned in `error`; a Gmsh crash (it can abort
/// the process) is not caught here: run the call in a child process to survive one.
GmshQuadResult gmsh_all_quad(const Polygon2& region, double h, int algorithm);

}  // namespace structmesh
