// Internal: outlines made of straight pieces and circular arcs, sampled at a
// requested total number of boundary segments (the Key and Pipe regions).
#pragma once

#include "structmesh/mesh.hpp"

#include <cstddef>
#include <vector>

namespace structmesh::detail {

/// One piece of a closed outline. It starts exactly at `start` (outline corners
/// are given, never computed) and ends at the next piece's start. A straight
/// piece when radius == 0; otherwise an arc around `center` from angle0 through
/// angle0 + sweep (positive sweep is counter-clockwise).
struct OutlinePiece {
  Vec2 start;
  Vec2 center = Vec2::Zero();
  double radius = 0;
  double angle0 = 0;
  double sweep = 0;
};

inline OutlinePiece line_from(const Vec2& start) { return {start}; }
inline OutlinePiece arc_from(const Vec2& start, const Vec2& center, double radius, double angle0, double sweep) {
  return {start, center, radius, angle0, sweep};
}

struct OutlineRing {
  std::vector<OutlinePiece> pieces;
  bool hole = false;
};

/// Samples ring 0 (outer) and the holes with `segments` segments in total, split
/// over the pieces by length (largest remainder), so segment lengths are nearly
/// uniform everywhere. Each piece keeps a minimum count that keeps the polygon
/// valid: arcs of the outer ring get at least one segment per 60 degrees (the chord
/// sagitta stays below the clearance of the designs), every ring at least 3.
/// When `segments` is below the sum of the minimums, that sum is used instead.
Polygon2 sample_outline(const std::vector<OutlineRing>& rings, std::size_t segments);

}  // namespace structmesh::detail
