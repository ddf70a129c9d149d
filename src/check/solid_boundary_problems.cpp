// solid_boundary_problems() (check.hpp): the reasons the commands that need a solid give.
#include "structmesh/check.hpp"

#include <string>

namespace structmesh {

std::string solid_boundary_problems(const SurfaceReport& report) {
  if (report.valid_solid_boundary) return {};
  std::string what;
  if (!report.closed) what += " open (" + std::to_string(report.boundary_edges) + " boundary edges);";
  if (report.non_manifold_edges + report.non_manifold_vertices > 0)
    what += " non-manifold (" + std::to_string(report.non_manifold_edges) + " edges, " +
            std::to_string(report.non_manifold_vertices) + " vertices);";
  if (report.self_intersections + report.adjacent_overlaps > 0)
    what +=
        " self-intersecting (" + std::to_string(report.self_intersections + report.adjacent_overlaps) + " face pairs);";
  if (!report.oriented) what += " inconsistently oriented;";
  if (report.closed && report.oriented && report.signed_volume < 0) what += " oriented inward (negative volume);";
  if (report.degenerate_faces > 0) what += " " + std::to_string(report.degenerate_faces) + " degenerate faces;";
  if (!report.problems.empty()) what += " first problem: " + report.problems.front().message;
  return what;
}

}  // namespace structmesh
