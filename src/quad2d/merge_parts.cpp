// merge_parts(): one conforming mesh from the paved parts. Boundary points of the
// parts are the shared samples (identified by index, never by coordinates), and
// every part's interior points follow in part order, so the result does not depend
// on which thread or rank meshed which part.
#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"

#include <tbb/parallel_for.h>

#include <cstdint>
#include <string>
#include <vector>

namespace structmesh {

MergedMesh merge_parts(const SampledPartition& sampled, std::span<const PavedPart> parts,
                       std::span<const std::vector<Index>> boundary_maps) {
  if (parts.size() != sampled.part_loops.size() || boundary_maps.size() != parts.size())
    throw InputError("merge_parts: expected one paved part and one boundary map per part");
  // Where each part's interior points and quads go: prefix sums, so the parts are
  // copied in parallel into their own ranges and the result is the same as copying
  // them in turn (a 20M-quad merge is memory traffic, not work).
  std::vector<std::size_t> point_start(parts.size() + 1, sampled.points.size()), quad_start(parts.size() + 1, 0);
  for (std::size_t p = 0; p < parts.size(); ++p) {
    if (parts[p].points.size() < boundary_maps[p].size())
      throw InputError("merge_parts: part " + std::to_string(p) + " has fewer points than its boundary");
    point_start[p + 1] = point_start[p] + parts[p].points.size() - boundary_maps[p].size();
    quad_start[p + 1] = quad_start[p] + parts[p].quads.size();
  }
  const std::size_t point_count = point_start.back(), quad_count = quad_start.back();
  if (point_count > kInvalidIndex) throw Error("merge_parts: more points than 32-bit indices can address");

  MergedMesh merged;
  merged.size = sampled.size;
  merged.mesh.points.resize(point_count);
  merged.mesh.quads.resize(quad_count);
  merged.part_of_quad.resize(quad_count);
  for (std::size_t i = 0; i < sampled.points.size(); ++i)
    merged.mesh.points[i] = Vec3(sampled.points[i].x(), sampled.points[i].y(), 0.0);
  merged.fixed.assign(sampled.fixed.begin(), sampled.fixed.end());
  merged.separator.resize(sampled.points.size());
  for (std::size_t i = 0; i < sampled.points.size(); ++i) merged.separator[i] = sampled.on_region_boundary[i] ? 0 : 1;
  merged.fixed.resize(point_count, 0);
  merged.separator.resize(point_count, 0);

  std::vector<std::uint8_t> out_of_range(parts.size(), 0);
  tbb::parallel_for(std::size_t{0}, parts.size(), [&](std::size_t p) {
    const PavedPart& part = parts[p];
    const std::vector<Index>& boundary = boundary_maps[p];
    const std::size_t interior = part.points.size() - boundary.size();
    // Local point i: boundary[i] for the boundary, then the part's own interior range.
    const auto global = [&](Index i) {
      return i < boundary.size() ? boundary[i] : static_cast<Index>(point_start[p] + (i - boundary.size()));
    };
    for (std::size_t i = 0; i < interior; ++i) {
      const Vec2& q = part.points[boundary.size() + i];
      merged.mesh.points[point_start[p] + i] = Vec3(q.x(), q.y(), 0.0);
    }
    for (std::size_t k = 0; k < part.quads.size(); ++k) {
      std::array<Index, 4> mapped{};
      for (int c = 0; c < 4; ++c) {
        if (part.quads[k][c] >= part.points.size()) out_of_range[p] = 1;
        mapped[c] = global(part.quads[k][c]);
      }
      merged.mesh.quads[quad_start[p] + k] = mapped;
      merged.part_of_quad[quad_start[p] + k] = static_cast<std::int32_t>(p);
    }
  });
  for (std::size_t p = 0; p < parts.size(); ++p)
    if (out_of_range[p])
      throw Error("merge_parts: part " + std::to_string(p) + " has a quad with a point out of range");
  return merged;
}

}  // namespace structmesh
