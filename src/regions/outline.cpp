#include "regions/outline.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace structmesh::detail {

namespace {

struct Span {
  const OutlinePiece* piece;
  Vec2 end;
  double length;
  std::size_t minimum, count;
};

double piece_length(const OutlinePiece& piece, const Vec2& end) {
  return piece.radius == 0 ? (end - piece.start).norm() : piece.radius * std::abs(piece.sweep);
}

}  // namespace

Polygon2 sample_outline(const std::vector<OutlineRing>& rings, std::size_t segments) {
  std::vector<Span> spans;
  std::vector<std::size_t> ring_first{0};
  double total_length = 0;
  for (const OutlineRing& ring : rings) {
    for (std::size_t i = 0; i < ring.pieces.size(); ++i) {
      const OutlinePiece& piece = ring.pieces[i];
      // A single-piece ring is a full circle that ends where it starts.
      const Vec2 end = ring.pieces[(i + 1) % ring.pieces.size()].start;
      std::size_t minimum = 1;
      if (piece.radius != 0 && !ring.hole)
        minimum = static_cast<std::size_t>(std::ceil(std::abs(piece.sweep) / (std::numbers::pi / 3) - 1e-9));
      if (ring.pieces.size() == 1) minimum = std::max<std::size_t>(minimum, 3);
      spans.push_back({&piece, end, piece_length(piece, end), std::max<std::size_t>(minimum, 1), 0});
      total_length += spans.back().length;
    }
    ring_first.push_back(spans.size());
  }

  // Largest-remainder apportionment of `segments` by length, respecting the minimums.
  std::size_t assigned = 0;
  for (Span& span : spans) {
    const double quota = span.length * static_cast<double>(segments) / total_length;
    span.count = std::max(span.minimum, static_cast<std::size_t>(std::floor(quota)));
    assigned += span.count;
  }
  // The piece whose segments are currently the longest gets the next one (and the
  // one whose segments would stay the shortest gives one back): a handful of steps.
  while (assigned < segments) {
    Span* longest = &spans[0];
    for (Span& span : spans)
      if (span.length / static_cast<double>(span.count) > longest->length / static_cast<double>(longest->count))
        longest = &span;
    ++longest->count;
    ++assigned;
  }
  while (assigned > segments) {
    Span* shortest = nullptr;
    for (Span& span : spans)
      if (span.count > span.minimum &&
          (shortest == nullptr || span.length / static_cast<double>(span.count - 1) <
                                      shortest->length / static_cast<double>(shortest->count - 1)))
        shortest = &span;
    if (shortest == nullptr) break;
    --shortest->count;
    --assigned;
  }

  Polygon2 polygon;
  polygon.points.reserve(assigned);
  polygon.ring_offsets.reserve(rings.size() + 1);
  for (std::size_t r = 0; r < rings.size(); ++r) {
    for (std::size_t s = ring_first[r]; s < ring_first[r + 1]; ++s) {
      const Span& span = spans[s];
      const OutlinePiece& piece = *span.piece;
      polygon.points.push_back(piece.start);
      const double n = static_cast<double>(span.count);
      for (std::size_t k = 1; k < span.count; ++k) {
        const double t = static_cast<double>(k) / n;
        if (piece.radius == 0) {
          polygon.points.push_back(piece.start + t * (span.end - piece.start));
        } else {
          const double angle = piece.angle0 + t * piece.sweep;
          polygon.points.push_back(piece.center + piece.radius * Vec2(std::cos(angle), std::sin(angle)));
        }
      }
    }
    polygon.ring_offsets.push_back(static_cast<Index>(polygon.points.size()));
  }
  return polygon;
}

}  // namespace structmesh::detail
