// Validation of planar triangle/quad meshes: orientation, inversion and conformity.
// Every edge use is recorded as (lower vertex, higher vertex, direction, element) and
// sorted once, so counting uses and directions per edge is one linear pass.
#include "problem_log.hpp"
#include "structmesh/check.hpp"
#include "structmesh/quality.hpp"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace structmesh {

namespace {

struct EdgeUse {
  Index low, high;
  bool forward;  // traversed low -> high
  Index element;
};

// Union-find over elements, joined through shared edges, to count components.
Index find_root(std::vector<Index>& parent, Index x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

template <std::size_t N>
std::string describe(const char* kind, std::size_t index, const std::array<Index, N>& element) {
  std::string out = std::string(kind) + " " + std::to_string(index) + " (";
  for (std::size_t i = 0; i < N; ++i) out += (i ? " " : "") + std::to_string(element[i]);
  return out + ")";
}

}  // namespace

PlanarMeshReport check_planar_mesh(const MeshBundle& mesh, const CheckOptions& options) {
  PlanarMeshReport report;
  detail::ProblemLog log(report.problems, options.max_problems_per_kind);
  const std::size_t n = mesh.points.size();
  report.triangles = mesh.triangles.size();
  report.quads = mesh.quads.size();
  if (detail::report_non_finite_points(mesh, log) > 0) return report;
  report.planar = true;
  for (const Vec3& p : mesh.points) report.planar = report.planar && p.z() == mesh.points.front().z();
  if (!report.planar) log.add("not-planar", "points do not all have the same z: not a planar mesh");
  if (report.triangles + report.quads == 0 || !mesh.tets.empty() || !mesh.hexes.empty()) {
    log.add("no-elements", "a planar mesh holds triangles or quads and nothing else");
    return report;
  }

  const Vec3 up(0, 0, 1);
  std::vector<EdgeUse> uses;
  uses.reserve(3 * report.triangles + 4 * report.quads);
  std::vector<std::uint8_t> used(n, 0);
  std::vector<std::uint8_t> counted(report.triangles + report.quads, 0);  // elements that contribute edges
  std::size_t out_of_range = 0;
  report.min_quad_scaled_jacobian = std::numeric_limits<double>::infinity();

  const auto visit = [&](const auto& element, std::size_t index, const char* kind, std::uint32_t line) {
    constexpr std::size_t N = std::tuple_size_v<std::decay_t<decltype(element)>>;
    const Index id = static_cast<Index>(N == 3 ? index : report.triangles + index);
    for (Index v : element) {
      if (v >= n) {
        ++out_of_range;
        log.add("index-out-of-range",
                describe(kind, index, element) + " refers to a vertex beyond the " + std::to_string(n) + " points",
                line, id);
        return;
      }
    }
    for (Index v : element) used[v] = 1;
    if (detail::repeats_vertex(element)) {
      ++report.degenerate;
      log.add("degenerate-element", describe(kind, index, element) + " repeats a vertex", line, id);
      return;
    }
    counted[id] = 1;
    std::array<Vec2, N> corners;
    for (std::size_t i = 0; i < N; ++i) corners[i] = mesh.points[element[i]].template head<2>();
    const double area = signed_area(corners);
    report.area += area;
    double quality = area;
    if constexpr (N == 4) {
      quality = quad_scaled_jacobian(
          {mesh.points[element[0]], mesh.points[element[1]], mesh.points[element[2]], mesh.points[element[3]]}, &up);
      report.min_quad_scaled_jacobian = std::min(report.min_quad_scaled_jacobian, quality);
    }
    if (quality <= 0) {
      ++report.inverted;
      log.add("inverted-element",
              describe(kind, index, element) + (N == 4 ? " has scaled Jacobian " : " has signed area ") +
                  std::to_string(quality) + " (clockwise or non-convex seen from +z)",
              line, id);
    }
    for (std::size_t i = 0; i < N; ++i) {
      const Index a = element[i], b = element[(i + 1) % N];
      uses.push_back({std::min(a, b), std::max(a, b), a < b, id});
    }
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    visit(mesh.triangles[t], t, "triangle", detail::line_of(mesh.lines.triangle_lines, t));
  for (std::size_t q = 0; q < mesh.quads.size(); ++q)
    visit(mesh.quads[q], q, "quad", detail::line_of(mesh.lines.quad_lines, q));
  if (mesh.quads.empty()) report.min_quad_scaled_jacobian = 0;
  if (out_of_range > 0) return report;

  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.low, x.high, x.element) < std::tie(y.low, y.high, y.element);
  });
  std::vector<Index> parent(report.triangles + report.quads);
  std::iota(parent.begin(), parent.end(), Index{0});
  for (std::size_t k = 0; k < uses.size();) {
    std::size_t end = k + 1;
    while (end < uses.size() && uses[end].low == uses[k].low && uses[end].high == uses[k].high) ++end;
    ++report.edges;
    const std::size_t count = end - k;
    const std::string edge = "edge " + std::to_string(uses[k].low) + "-" + std::to_string(uses[k].high);
    if (count == 1) {
      ++report.boundary_edges;
    } else if (count > 2) {
      ++report.non_manifold_edges;
      log.add("non-manifold-edge", edge + " is used by " + std::to_string(count) + " elements", 0, uses[k].element);
    } else if (uses[k].forward == uses[k + 1].forward) {
      ++report.inconsistent_edges;
      log.add("inconsistent-edge",
              edge + " is traversed in the same direction by elements " + std::to_string(uses[k].element) + " and " +
                  std::to_string(uses[k + 1].element) + " (one of them is flipped)",
              0, uses[k + 1].element);
    }
    for (std::size_t j = k + 1; j < end; ++j)
      parent[find_root(parent, uses[j].element)] = find_root(parent, uses[k].element);
    k = end;
  }
  for (Index e = 0; e < parent.size(); ++e) report.components += counted[e] && find_root(parent, e) == e ? 1 : 0;
  for (std::size_t v = 0; v < n; ++v) {
    if (used[v]) {
      ++report.vertices;
    } else {
      ++report.unused_vertices;
      log.add("unused-vertex", "vertex " + std::to_string(v) + " is used by no element",
              detail::line_of(mesh.lines.point_lines, v));
    }
  }
  // Degenerate elements are left out of the edges, so they are left out of F too.
  const long faces = static_cast<long>(report.triangles + report.quads - report.degenerate);
  report.euler_characteristic = static_cast<long>(report.vertices) - static_cast<long>(report.edges) + faces;
  const long holes = static_cast<long>(report.components) - report.euler_characteristic;
  report.holes = holes > 0 ? static_cast<std::size_t>(holes) : 0;
  report.valid = report.planar && report.inverted == 0 && report.degenerate == 0 && report.non_manifold_edges == 0 &&
                 report.inconsistent_edges == 0;
  return report;
}

}  // namespace structmesh
