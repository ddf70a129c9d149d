// Built-in procedural regions of §3.4 (our own reconstructions of the shapes the
// dissertation names; its exact outlines are not published): the Key, a key
// silhouette with one hole, and the Pipe, a pipe-bend plate with 9 holes.
// Both are generated at any boundary resolution.
#pragma once

#include "structmesh/mesh.hpp"

#include <cstddef>

namespace structmesh {

/// The Key: a round bow with a hole, a shaft and a toothed bit. About
/// `boundary_segments` segments in total, spread over all rings by arc length.
Polygon2 make_key_region(std::size_t boundary_segments = 2000);

/// The Pipe: a bent pipe plate with 9 circular holes. About `boundary_segments`
/// segments in total, spread over all rings by arc length.
Polygon2 make_pipe_region(std::size_t boundary_segments = 4000);

}  // namespace structmesh
