// visible_faces(): the visibility regions V(p) of §2.2.1 for many candidates, with
// the face rule of §2.2 (a face is visible when its three vertices are).
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <string>

namespace structmesh {

CompressedRows visible_faces(const VisibilityOracle& oracle, const TriMesh& surface, std::span<const Vec3> candidates) {
  if (surface.points.size() != oracle.vertex_count() || surface.triangles.size() != oracle.face_count())
    throw InputError("visible_faces: the surface (" + std::to_string(surface.points.size()) + " vertices, " +
                     std::to_string(surface.triangles.size()) + " faces) is not the oracle's (" +
                     std::to_string(oracle.vertex_count()) + ", " + std::to_string(oracle.face_count()) + ")");
  // Vertices used by some face: each is tested once per candidate, not once per face.
  std::vector<std::uint8_t> used(surface.points.size(), 0);
  for (const auto& t : surface.triangles)
    for (const Index v : t) used[v] = 1;
  std::vector<Index> vertices;
  std::vector<Index> slot(surface.points.size(), kInvalidIndex);  // position in `vertices`
  for (Index v = 0; v < used.size(); ++v)
    if (used[v] != 0) {
      slot[v] = static_cast<Index>(vertices.size());
      vertices.push_back(v);
    }

  std::vector<std::vector<Index>> rows(candidates.size());
  // Candidates in parallel, and the vertices of one candidate too, so that a handful
  // of candidates still uses every core. The vertices go in fixed chunks, each traced
  // as one stream of rays (sees_many): Embree's packet kernels may decide a grazing ray
  // otherwise than its single-ray one, so the chunks must not depend on how the work
  // was split. Every row is written by one task in face order, so the result does not
  // depend on the thread count.
  constexpr std::size_t kChunk = 1024;
  const std::size_t chunks = (vertices.size() + kChunk - 1) / kChunk;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 1), [&](const auto& range) {
    std::vector<std::uint8_t> visible(vertices.size(), 0);
    for (std::size_t c = range.begin(); c != range.end(); ++c) {
      const Vec3 p = candidates[c];
      tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t chunk) {
        const std::size_t first = chunk * kChunk, n = std::min(kChunk, vertices.size() - first);
        oracle.sees_many(p, std::span<const Index>(vertices).subspan(first, n), std::span(visible).subspan(first, n));
      });
      std::vector<Index>& row = rows[c];
      for (Index f = 0; f < surface.triangles.size(); ++f) {
        const auto& t = surface.triangles[f];
        if (visible[slot[t[0]]] != 0 && visible[slot[t[1]]] != 0 && visible[slot[t[2]]] != 0) row.push_back(f);
      }
    }
  });

  CompressedRows result;
  std::size_t total = 0;
  for (const auto& row : rows) total += row.size();
  result.items.reserve(total);
  result.offsets.reserve(rows.size() + 1);
  for (const auto& row : rows) {
    result.items.insert(result.items.end(), row.begin(), row.end());
    result.offsets.push_back(static_cast<Index>(result.items.size()));
  }
  return result;
}

}  // namespace structmesh
