// The Gmsh 4.8 all-quad baseline of the quad meshing benchmark (dissertation §3.4):
// Gmsh's best all-quad mesh of a planar region, set up as RECIPES.md says. Not a
// library: the benchmark executables compile it and link the Gmsh library.
#pragma once

#include "structmesh/mesh.hpp"

#include <cstddef>
#include <cstdint>
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

/// What the benchmark tables need of a Gmsh run, measured as we measure ours
/// (quad_quality: Verdict's scaled Jacobian, singular = interior valence != 4).
struct GmshQuadSummary {
  std::string failure;  // empty on success; else Gmsh's error, "crashed (...)" or "timed out"
  std::size_t quads = 0, leftover_triangles = 0, inverted = 0, singular_vertices = 0;
  double scaled_jacobian_avg = 0, scaled_jacobian_std = 0, scaled_jacobian_min = 0, seconds = 0;
};

/// gmsh_all_quad in a forked child process with a time limit: Gmsh can abort the
/// process (an odd 1D mesh, a segfault in a meshing algorithm), and one crash must
/// not end a benchmark run.
GmshQuadSummary gmsh_all_quad_isolated(const Polygon2& region, double h, int algorithm, unsigned timeout_seconds);

}  // namespace structmesh
