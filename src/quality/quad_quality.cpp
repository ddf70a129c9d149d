// Quad mesh quality of §3.4.3 (Table 3.4): scaled Jacobian statistics and the
// number of singular vertices (interior vertices whose valence is not 4).
#include "structmesh/error.hpp"
#include "structmesh/quality.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>

namespace structmesh {

namespace {

struct QuadVertexClasses {
  std::vector<char> used, boundary, singular;
};

// Boundary vertices are the ends of boundary edges (edges with exactly one quad);
// an interior vertex is singular when its number of edges is not 4. Edges used by
// three or more quads (non-manifold input) are not boundary edges.
// Per vertex, from its quads: the edge v-w lies in as many of v's quads as w appears
// among their neighbours of v (a quad has w either after or before v, not both), so
// no global edge table is needed; the vertices are independent and go in parallel
// (the edge table was most of quad_quality() at 20M quads: 4 of 7 s).
QuadVertexClasses classify_vertices(const QuadMesh& mesh) {
  const std::size_t n = mesh.points.size();
  QuadVertexClasses classes{std::vector<char>(n, 0), std::vector<char>(n, 0), std::vector<char>(n, 0)};
  const CompressedRows vertex_quads = build_vertex_elements(mesh.quads, n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    std::vector<Index> around;
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const auto quads = vertex_quads.row(v);
      if (quads.empty()) continue;
      classes.used[v] = 1;
      around.clear();
      for (const Index q : quads) {
        const auto& quad = mesh.quads[q];
        for (int k = 0; k < 4; ++k)
          if (quad[k] == v) {
            around.push_back(quad[(k + 1) % 4]);
            around.push_back(quad[(k + 3) % 4]);
          }
      }
      std::sort(around.begin(), around.end());
      std::size_t edges = 0;
      bool boundary = false;
      for (std::size_t i = 0; i < around.size();) {
        std::size_t j = i;
        while (j < around.size() && around[j] == around[i]) ++j;
        ++edges;
        if (j - i == 1) boundary = true;
        i = j;
      }
      classes.boundary[v] = boundary ? 1 : 0;
      classes.singular[v] = !boundary && edges != 4 ? 1 : 0;
    }
  });
  return classes;
}

// A planar mesh lies in one plane z = const: the dissertation's 2D regions.
bool is_planar(const QuadMesh& mesh) {
  if (mesh.quads.empty()) return false;
  const double z = mesh.points[mesh.quads.front()[0]].z();
  for (const auto& q : mesh.quads)
    for (Index v : q)
      if (mesh.points[v].z() != z) return false;
  return true;
}

}  // namespace

QuadQuality quad_quality(const QuadMesh& mesh) {
  QuadQuality quality;
  quality.planar = is_planar(mesh);
  const Vec3 up = Vec3::UnitZ();
  const Vec3* reference = quality.planar ? &up : nullptr;

  // The vertex classes (a serial counting sort of the quads by vertex, then parallel
  // work) and the scaled Jacobians (parallel) are independent: computed side by side,
  // a second thread is not left idle during the sort.
  QuadVertexClasses classes;
  tbb::parallel_invoke(
      [&] { classes = classify_vertices(mesh); },
      [&] {
        quality.scaled_jacobian.resize(mesh.quads.size());
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.quads.size(), 1024),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                              const auto& q = mesh.quads[i];
                              const std::array<Vec3, 4> corners{mesh.points[q[0]], mesh.points[q[1]], mesh.points[q[2]],
                                                                mesh.points[q[3]]};
                              quality.scaled_jacobian[i] = quad_scaled_jacobian(corners, reference);
                            }
                          });
        quality.scaled_jacobian_stats = statistics(quality.scaled_jacobian);
        quality.scaled_jacobian_histogram = histogram(quality.scaled_jacobian, -1.0, 1.0, 20);
        quality.inverted = static_cast<std::size_t>(std::count_if(
            quality.scaled_jacobian.begin(), quality.scaled_jacobian.end(), [](double s) { return s <= 0; }));
      });

  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    if (!classes.used[v]) continue;
    if (classes.boundary[v])
      ++quality.boundary_vertices;
    else
      ++quality.interior_vertices;
    if (classes.singular[v]) ++quality.singular_vertices;
  }
  return quality;
}

std::vector<std::size_t> singular_vertices_per_part(const QuadMesh& mesh,
                                                    const std::vector<std::int32_t>& part_of_quad) {
  if (part_of_quad.size() != mesh.quads.size())
    throw InputError("singular_vertices_per_part: " + std::to_string(part_of_quad.size()) + " part ids for " +
                     std::to_string(mesh.quads.size()) + " quads");
  std::int32_t largest = -1;
  for (std::size_t i = 0; i < part_of_quad.size(); ++i) {
    if (part_of_quad[i] < 0)
      throw InputError("singular_vertices_per_part: quad " + std::to_string(i) + " has negative part id " +
                       std::to_string(part_of_quad[i]));
    largest = std::max(largest, part_of_quad[i]);
  }
  std::vector<std::size_t> counts(static_cast<std::size_t>(largest + 1), 0);
  const QuadVertexClasses classes = classify_vertices(mesh);
  const CompressedRows vertex_quads = build_vertex_elements(mesh.quads, mesh.points.size());
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    if (!classes.singular[v]) continue;
    // A vertex on a separator touches several parts; giving it to the smallest id
    // keeps the per-part counts summing to the mesh's total.
    std::int32_t part = largest;
    for (Index q : vertex_quads.row(v)) part = std::min(part, part_of_quad[q]);
    ++counts[static_cast<std::size_t>(part)];
  }
  return counts;
}

}  // namespace structmesh
