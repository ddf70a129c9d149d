// Curve skeleton of a closed surface: the candidate guard positions of shape
// guarding (§2.2: "medial axes usually have desirable visibility to the shape").
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace structmesh {

/// A curve skeleton: nodes joined by edges (a graph, usually a tree with loops around
/// handles). vertex_node[v] is the node that absorbed surface vertex v (every
/// surface vertex belongs to exactly one node).
struct CurveSkeleton {
  std::vector<Vec3> nodes;
  std::vector<std::array<Index, 2>> edges;
  std::vector<Index> vertex_node;
};

/// The mean-curvature-flow skeleton (Tagliasacchi et al. 2012, CGAL's
/// Mean_curvature_flow_skeletonization) of a closed, manifold, oriented triangle surface
/// with default parameters. A surface of more than `max_vertices` vertices (0: no
/// limit) is first simplified to about that many by edge collapse: the flow's cost
/// grows faster than linearly (measured here: 30k vertices 15 s, 5k under 1 s) while
/// the skeleton of a simplified surface runs along the same medial curves; every input
/// vertex then goes to its nearest node. InputError for an open or non-manifold surface.
CurveSkeleton curve_skeleton(const TriMesh& surface, std::size_t max_vertices = 0);

/// The surface simplified by edge collapse (CGAL, Lindstrom-Turk) to about
/// `max_vertices` vertices, keeping its topology; the surface itself when it has no more
/// (or max_vertices is 0). The levels of the progressive ILP (§2.2.3). InputError as for
/// curve_skeleton().
TriMesh simplify_surface(const TriMesh& surface, std::size_t max_vertices);

/// Points along the skeleton about `spacing` apart: every joint (degree != 2) and end is
/// kept (§2.2.3: "re-sampled with joints preserved"), each branch between two of them is
/// divided evenly by arc length. Nodes of a closed loop without joints are sampled from
/// their first node.
std::vector<Vec3> resample_skeleton(const CurveSkeleton& skeleton, double spacing);

/// 1 where the point lies strictly inside the closed surface (CGAL Side_of_triangle_mesh,
/// exact predicates), 0 on or outside it. Skeleton nodes of thin or noisy parts can fall
/// outside; a guard there would "see" faces from the outside.
std::vector<std::uint8_t> inside_solid(const TriMesh& surface, std::span<const Vec3> points);

}  // namespace structmesh
