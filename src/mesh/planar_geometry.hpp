// Internal: exact planar predicates and ring containment queries shared by the
// .poly reader (grouping loops into polygons) and check_region() (hole tests).
//
// Why exact: region boundaries are full of collinear runs (sampled straight
// edges, box sides of coastal regions) and near-touching rings; a floating-point
// orientation test answers those cases at random, and then a valid region is
// reported broken or a touching pair is missed.
#pragma once

#include "structmesh/mesh.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace structmesh::detail {

/// Sign of the orientation of (a, b, c): +1 counter-clockwise, -1 clockwise, 0 collinear.
/// Exact for finite inputs whose products neither overflow nor underflow
/// (|coordinates| roughly within 1e-140 .. 1e140): a floating-point filter
/// (Shewchuk's bound) with an exact expansion-arithmetic fallback.
int orient2d(const Vec2& a, const Vec2& b, const Vec2& c);

/// True when the ring holds at least three distinct points (stops at the third).
bool has_three_distinct_points(std::span<const Vec2> ring);

/// Orients ring 0 counter-clockwise and the holes clockwise (the Polygon2
/// convention), reversing a ring in place but keeping its first point first.
void normalize_orientation(Polygon2& polygon);

/// Whether p lies inside the closed ring, by the parity of crossings of a ray
/// towards -x (half-open rule: a segment counts when one end is strictly above p's
/// y and the other is not); a point on the ring gets an arbitrary answer. O(ring).
bool point_in_ring(std::span<const Vec2> ring, const Vec2& p);

enum class SegmentContact { None, Cross, Touch };

/// How closed segments [a,b] and [c,d] meet: Cross when they cross at one point
/// interior to both, Touch for any other contact (an endpoint on the other
/// segment, shared endpoints, collinear overlap). Both segments must be non-degenerate.
SegmentContact segment_contact(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d);

/// For query points, the rings whose interior contains the point, by the parity
/// of crossings of a ray towards -x (exact half-open rule: a segment counts when
/// one end is strictly above the point's y and the other is not). Segments are
/// bucketed into horizontal bands, so a query costs about the number of segments
/// in one band rather than all of them.
class RingLocator {
 public:
  explicit RingLocator(std::vector<std::span<const Vec2>> rings);

  /// Indices (ascending) of the rings, other than `skip`, whose interior holds p.
  /// A point on a ring's boundary gets an arbitrary but deterministic answer.
  std::vector<std::uint32_t> containing(const Vec2& p, std::uint32_t skip) const;

 private:
  struct SegmentRef {
    std::uint32_t ring, index;  // from rings_[ring][index] to the next vertex of the ring
  };
  std::vector<std::span<const Vec2>> rings_;
  std::vector<std::uint32_t> band_offsets_;
  std::vector<SegmentRef> band_items_;  // the non-horizontal segments meeting each band
  double y0_ = 0, band_height_ = 1;
  std::size_t band_count_ = 0;

  std::size_t band_of(double y) const;
};

}  // namespace structmesh::detail
