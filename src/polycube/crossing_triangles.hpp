// The intersection guard of the pre-deformation (§4.3): which triangles of a deformed
// closed surface cross another one, by the exact tests of check_surface(), fast enough to
// run after every deformation step.
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <vector>

namespace structmesh::polycube_detail {

/// Triangles (ascending) that are in a pair check_surface() would report: faces sharing
/// no vertex that touch or cross, or faces sharing a vertex or an edge that overlap
/// beyond it; also triangles of zero area. `vertex_triangles` is the surface's
/// build_vertex_elements(); the surface must be a closed manifold (every vertex fan a
/// closed disk) for the fan test. Exact: the same CGAL predicates decide, on the few
/// triangles that cheap conservative tests cannot clear.
std::vector<Index> crossing_triangles(const std::vector<Vec3>& points,
                                      const std::vector<std::array<Index, 3>>& triangles,
                                      const CompressedRows& vertex_triangles);

}  // namespace structmesh::polycube_detail
