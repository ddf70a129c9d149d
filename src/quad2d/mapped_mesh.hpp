// Private pieces of the mapped mesher (mapped_mesh(), quad2d.hpp): the structured
// grid of a four-sided part, its transfinite interpolation and its elliptic smoothing,
// separated so that the tests can look at each stage.
#pragma once

#include "structmesh/mesh.hpp"
#include "structmesh/quad2d.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace structmesh::mapped {

/// Nodes (i, j), 0 <= i <= ni, 0 <= j <= nj, stored row by row (node i + j * (ni + 1));
/// i runs along the side corners[0] -> corners[1], j along corners[1] -> corners[2], so
/// the quad (i, j), (i+1, j), (i+1, j+1), (i, j+1) is counter-clockwise. Coordinates are
/// two flat arrays; `loop_index` gives a boundary node's position in the input loop
/// (kInvalidIndex inside).
struct StructuredGrid {
  std::size_t ni = 0, nj = 0;
  std::vector<double> x, y;
  std::vector<Index> loop_index;
  std::size_t node(std::size_t i, std::size_t j) const { return i + j * (ni + 1); }
};

/// The grid with its boundary nodes taken from the loop (bit-identical) and its
/// interior nodes placed by transfinite interpolation (a Coons patch) of the four
/// sides, each parameterised by its normalised arc length. InputError for anything
/// mapped_mesh() rejects.
StructuredGrid transfinite_grid(const Polygon2& boundary, const std::array<std::size_t, 4>& corners);

enum class Smoothing { Converged, IterationLimit, Diverged };

/// Gauss-Seidel sweeps (i fastest, then j) of the Winslow equations on the interior
/// nodes, with Thomas-Middlecoff control functions from the boundary spacing when
/// `control_functions`; `tolerance` is the largest move below which a sweep ends the
/// smoothing.
/// Diverged (the grid then partly smoothed: start again from a copy) when a coordinate
/// stops being finite or leaves the boundary's bounding box by more than its diagonal.
Smoothing winslow_smooth(StructuredGrid& grid, int iterations, double tolerance, bool control_functions);
/// The same with every interior node moved to the mean of its four neighbours.
Smoothing laplace_smooth(StructuredGrid& grid, int iterations, double tolerance);

/// Smallest scaled Jacobian (quad_scaled_jacobian with +z) over the grid's quads;
/// NaN when one is NaN.
double min_scaled_jacobian(const StructuredGrid& grid);

}  // namespace structmesh::mapped
