// Built-in closed surfaces for the 3D pipelines (`structmesh generate trefoil -o t.obj`):
// shapes made from formulas, so that guarding, star decomposition and hex meshing can be
// tried and benchmarked without any data set. `bench/run_hex.sh --unseen` meshes them all
// (they were first meshed after the hex pipeline's defaults were fixed: shapes it was never
// tuned on). Every one is a closed, outward, self-intersection-free triangle surface.
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace structmesh {

/// A built-in solid: its name for make_builtin_solid() and a one-line description.
struct BuiltinSolid {
  std::string_view name;
  std::string_view description;
  int genus;
};

/// The built-in solids, in a fixed order.
std::span<const BuiltinSolid> builtin_solids();

/// The surface of the built-in solid `name`; throws InputError naming the choices for an
/// unknown name.
TriMesh make_builtin_solid(std::string_view name);

/// The icosahedron's sphere after `subdivisions` 4:1 splits (10 * 4^s + 2 vertices), every
/// vertex then moved to radius(direction) along its unit direction from the origin: any
/// star-shaped solid.
TriMesh icosphere(int subdivisions, const std::function<double(const Vec3&)>& radius);

/// Boundary of a union of unit cubes [i, i+1] x [j, j+1] x [k, k+1], each boundary square
/// cut into n x n smaller squares (n = `subdivisions`), each split along its 0-2 diagonal.
/// Manifold when no two cells touch only along an edge or at a corner.
TriMesh voxel_union_surface(std::span<const std::array<int, 3>> cells, int subdivisions = 1);

/// Torus around the z axis (radii big, small), u x v vertices, vertex 0 at (big + small, 0, 0).
TriMesh torus_surface(double big, double small, int u, int v);

/// The surface swept by turning `profile` (at least 3 points (r, z)) about the z axis in
/// `around` (>= 3) steps, oriented outward. An open profile starts and ends on the axis
/// (r = 0: poles) and stays off it in between; a closed one (`closed`) stays off it
/// (r > 0) and sweeps a solid torus. Profile corners stay sharp edges. Throws InputError
/// otherwise. The profile must not cross itself (not checked).
TriMesh surface_of_revolution(std::span<const std::pair<double, double>> profile, int around, bool closed);

/// Taubin's lambda|mu smoothing (umbrella operator, lambda 0.5, mu -0.53), `iterations`
/// pairs of steps: rounds a voxel union's steps without shrinking it.
void taubin_smooth(TriMesh& mesh, int iterations);

}  // namespace structmesh
