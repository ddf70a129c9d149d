// Private to restricted_voronoi.cpp and lp_cvt.cpp: the clipping engine of the
// restricted Voronoi diagram (design/partition2d.md §2.2). Pieces = (CDT triangle ∩
// Voronoi cell) as convex polygons whose vertices carry symbolic keys.
#pragma once

#include "partition2d/partition_internal.hpp"

#include <compare>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace structmesh::partition2d::rvd {

/// Symbolic vertex (§2.2 step 3). Coordinates are a function of the key only, so a
/// vertex met in two triangles or two cells gets bit-identical coordinates.
struct VertexKey {
  enum Kind : std::uint32_t {
    TriVertex = 0,     ///< a = CDT vertex
    EdgeBisector = 1,  ///< CDT edge [a, b] (a < b) crossed by bisector(c, d) (c < d)
    Voronoi = 2,       ///< circumcentre of sites a < b < c
  };
  std::uint32_t kind = TriVertex;
  std::uint32_t a = 0, b = 0, c = 0, d = 0;
  friend auto operator<=>(const VertexKey&, const VertexKey&) = default;
};

/// What an edge of a piece lies on: a CDT edge [cdt_a, cdt_b], the bisector of the
/// piece's site and site `neighbor`, or both (exact degeneracy: a bisector along a
/// CDT edge, which still carries the bisector term of §1.7). kInvalidIndex = no.
struct EdgeTag {
  Index cdt_a = kInvalidIndex, cdt_b = kInvalidIndex;
  Index neighbor = kInvalidIndex;
  bool on_cdt_edge() const { return cdt_a != kInvalidIndex; }
  bool on_bisector() const { return neighbor != kInvalidIndex; }
};

/// One piece handed to the visitor; spans are valid during the call only. Vertices
/// are counter-clockwise; edge k goes from vertex k to vertex k+1 (cyclically).
struct PieceView {
  Index triangle = 0;
  Index site = 0;
  std::span<const VertexKey> keys;
  std::span<const EdgeTag> tags;
  std::span<const Vec2> positions;
};

/// The Delaunay triangulation of the sites, as needed by the clipping (§2.2 step 1).
class Engine {
 public:
  Engine(const DomainMesh& domain, std::span<const Vec2> sites);
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  /// Fixed blocks of triangles (independent of the thread count).
  std::size_t block_count() const;
  /// Clips every domain triangle in parallel over blocks; `visit(block, piece)` is
  /// called for each positive-area piece, in a deterministic order within a block,
  /// from one thread per block at a time.
  void for_each_piece(const std::function<void(std::size_t, const PieceView&)>& visit) const;

  Vec2 position(const VertexKey& key) const;

  /// The key of the same point under the canonical naming for exact degeneracies
  /// (one name per point): a point equidistant from three or more sites (several
  /// co-circular sites, or a Voronoi vertex exactly on a CDT edge) becomes Voronoi of
  /// the three lowest such sites. Only valid for vertices of the final diagram (no
  /// site strictly closer), which is all restricted_voronoi needs; the clipping
  /// itself never needs it, since exact predicates already give consistent pieces.
  VertexKey canonical(const VertexKey& key) const;

 private:
  struct Data;
  std::unique_ptr<Data> data_;
};

}  // namespace structmesh::partition2d::rvd
