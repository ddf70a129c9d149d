// A structured grid in the interior of a large part, paving only along its boundary
// (private to the quad2d module; see grid_interior.cpp).
#pragma once

#include "structmesh/mesh.hpp"
#include "structmesh/quad2d.hpp"

#include <optional>

namespace structmesh::paving {

/// The part's all-quad mesh with a grid of squares of edge options.size inside and
/// paved bands between the grid and the part's loops; nullopt when the part has no room
/// for a grid or a band cannot be paved (the caller paves the whole part). The part's
/// boundary points come first, unchanged, as from pave().
std::optional<PavedPart> pave_with_grid_interior(const Polygon2& boundary, const PavingOptions& options);

}  // namespace structmesh::paving
