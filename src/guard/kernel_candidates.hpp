// Internal: candidate guards in the kernels of the faces a pair of chosen guards alone
// sees (guard_surface.cpp's refinement of the ILP cover).
#pragma once

#include "structmesh/mesh.hpp"

#include <span>
#include <vector>

namespace structmesh::guard_detail {

/// For every pair of guards in `chosen` (rows of `sets`, which list the surface faces each
/// candidate sees) whose faces meet along a surface edge: the faces only those two see.
/// A point that sees a face lies on the inner side of its plane, so a single guard that
/// replaces the two lies in the intersection of those faces' inner half-spaces (their
/// kernel). Returns, per pair whose kernel has room, its Chebyshev centre (the point
/// deepest inside every half-space, within the faces' bounding box) and the point of the
/// kernel nearest (L1) to the two guards' midpoint, a quarter of the centre's depth
/// inside. Occlusion is not looked at: the caller tests visibility.
std::vector<Vec3> kernel_candidates(const TriMesh& surface, const CompressedRows& sets,
                                    std::span<const Vec3> candidates, std::span<const Index> chosen);

}  // namespace structmesh::guard_detail
