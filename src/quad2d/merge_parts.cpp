// merge_parts(): one conforming mesh from the paved parts. Boundary points of the
// parts are the shared samples (identified by index, never by coordinates), and
// every part's interior points follow in part order, so the result does not depend
// on which thread or rank meshed which part.
#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"

#include <string>

namespace structmesh {

MergedMesh merge_parts(const SampledPartition& sampled, std::span<const PavedPart> parts,
                       std::span<const std::vector<Index>> boundary_maps) {
  if (parts.size() != sampled.part_loops.size() || boundary_maps.size() != parts.size())
    throw InputError("merge_parts: expected one paved part and one boundary map per part");
  std::size_t point_count = sampled.points.size(), quad_count = 0;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    if (parts[p].points.size() < boundary_maps[p].size())
      throw InputError("merge_parts: part " + std::to_string(p) + " has fewer points than its boundary");
    point_count += parts[p].points.size() - boundary_maps[p].size();
    quad_count += parts[p].quads.size();
  }
  if (point_count > kInvalidIndex) throw Error("merge_parts: more points than 32-bit indices can address");

  MergedMesh merged;
  merged.size = sampled.size;
  merged.mesh.points.reserve(point_count);
  merged.mesh.quads.reserve(quad_count);
  merged.part_of_quad.reserve(quad_count);
  for (const Vec2& p : sampled.points) merged.mesh.points.emplace_back(p.x(), p.y(), 0.0);
  merged.fixed.assign(sampled.fixed.begin(), sampled.fixed.end());
  merged.separator.resize(sampled.points.size());
  for (std::size_t i = 0; i < sampled.points.size(); ++i) merged.separator[i] = sampled.on_region_boundary[i] ? 0 : 1;
  merged.fixed.resize(point_count, 0);
  merged.separator.resize(point_count, 0);

  std::vector<Index> global;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const PavedPart& part = parts[p];
    const std::vector<Index>& boundary = boundary_maps[p];
    global.assign(boundary.begin(), boundary.end());
    for (std::size_t i = boundary.size(); i < part.points.size(); ++i) {
      global.push_back(static_cast<Index>(merged.mesh.points.size()));
      merged.mesh.points.emplace_back(part.points[i].x(), part.points[i].y(), 0.0);
    }
    for (const auto& quad : part.quads) {
      std::array<Index, 4> mapped{};
      for (int k = 0; k < 4; ++k) {
        if (quad[k] >= global.size())
          throw Error("merge_parts: part " + std::to_string(p) + " has a quad with a point out of range");
        mapped[k] = global[quad[k]];
      }
      merged.mesh.quads.push_back(mapped);
      merged.part_of_quad.push_back(static_cast<std::int32_t>(p));
    }
  }
  return merged;
}

}  // namespace structmesh
