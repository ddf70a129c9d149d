// check_volume(): validity of a tet and/or hex mesh.
//
// Cells are named "tet i" / "hex i" (0-based within their kind); Problem::element
// is the cell's index in bundle cell order (triangles, quads, tets, hexes).
// Triangles and quads beside volume cells (MEDIT boundary elements) are counted
// and otherwise ignored.
#include "check/problem_log.hpp"
#include "structmesh/check.hpp"
#include "structmesh/quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace structmesh {
namespace {

using detail::line_of;
using detail::ProblemLog;
using detail::repeats_vertex;

// A tet counts as inverted when its volume is below this fraction of the cube of
// its longest edge: such a tet is flat within rounding even if the sign is positive.
constexpr double kFlatTetTolerance = 1e-12;

template <std::size_t N>
bool in_range(const std::array<Index, N>& v, std::size_t point_count) {
  return std::all_of(v.begin(), v.end(), [&](Index u) { return u < point_count; });
}

std::string number(double x) {
  std::ostringstream out;
  out.precision(6);
  out << x;
  return out.str();
}

template <std::size_t N>
std::string vertex_list(const std::array<Index, N>& v) {
  std::string s = std::to_string(v[0]);
  for (std::size_t i = 1; i < N; ++i) s.append("-").append(std::to_string(v[i]));
  return s;
}

// Faces shared by more than two cells; `cell_of` maps the adjacency's cell ids
// (positions among the checked cells) back to cell indices.
template <std::size_t N>
void report_non_manifold_faces(const FaceAdjacency<N>& adjacency, const std::vector<Index>& cell_of, const char* plural,
                               const std::vector<std::uint32_t>& lines, std::size_t element_offset,
                               VolumeReport& report, ProblemLog& log) {
  // extra_faces lists each face once per cell beyond the second, grouped by face.
  for (std::size_t k = 0; k < adjacency.extra_faces.size();) {
    const Index face = adjacency.extra_faces[k];
    std::size_t end = k + 1;
    while (end < adjacency.extra_faces.size() && adjacency.extra_faces[end] == face) ++end;
    ++report.non_manifold_faces;
    if (log.wants("non-manifold-face")) {
      const Index first = cell_of[adjacency.face_cells[face][0]];
      std::string cells = std::to_string(first) + ", " + std::to_string(cell_of[adjacency.face_cells[face][1]]);
      for (std::size_t x = k; x < end; ++x) cells += ", " + std::to_string(cell_of[adjacency.extra_cells[x]]);
      log.add("non-manifold-face",
              "face " + vertex_list(adjacency.faces[face]) + " is shared by " + std::to_string(end - k + 2) + " " +
                  plural + ": " + cells,
              line_of(lines, first), std::int64_t(element_offset + first));
    }
    k = end;
  }
}

// What the per-cell pass over the tets and the one over the hexes share.
struct CellPass {
  const MeshBundle& mesh;
  VolumeReport& report;
  ProblemLog& log;
  std::vector<std::uint8_t> used;  // per point
  std::size_t out_of_range = 0;
};

// The checks every kind of cell gets: a cell naming a vertex beyond the points or
// repeating a vertex is reported and skipped. Every other cell is added to `kept`
// (its index to `kept_of`) for the face test, then given to the kind's own
// geometric test, `geometry(v, name, line, element)`.
template <std::size_t N, typename Geometry>
void check_cells(const std::vector<std::array<Index, N>>& cells, const char* kind,
                 const std::vector<std::uint32_t>& lines, std::size_t element_offset, CellPass& pass,
                 std::vector<std::array<Index, N>>& kept, std::vector<Index>& kept_of, const Geometry& geometry) {
  const std::size_t n = pass.mesh.points.size();
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const auto& v = cells[c];
    const std::uint32_t line = line_of(lines, c);
    const std::int64_t element = std::int64_t(element_offset + c);
    const std::string name = std::string(kind) + " " + std::to_string(c) + " (" + vertex_list(v) + ")";
    if (!in_range(v, n)) {
      ++pass.out_of_range;
      pass.log.add("index-out-of-range", name + " refers to a vertex beyond the " + std::to_string(n) + " points", line,
                   element);
      continue;
    }
    for (Index u : v) pass.used[u] = 1;
    if (repeats_vertex(v)) {
      ++pass.report.degenerate;
      pass.log.add("degenerate-cell", name + " repeats a vertex", line, element);
      continue;
    }
    kept.push_back(v);
    kept_of.push_back(Index(c));
    geometry(v, name, line, element);
  }
}

}  // namespace

VolumeReport check_volume(const MeshBundle& mesh, const CheckOptions& options) {
  VolumeReport report;
  ProblemLog log(report.problems, options.max_problems_per_kind);
  const std::size_t n = mesh.points.size();
  report.vertices = n;
  report.triangles = mesh.triangles.size();
  report.quads = mesh.quads.size();
  report.tets = mesh.tets.size();
  report.hexes = mesh.hexes.size();
  if (report.tets == 0 && report.hexes == 0) {
    log.add("no-cells", "the mesh has no tets or hexes");
    return report;
  }
  // NaN or infinite coordinates make every measure below meaningless: report and stop.
  if (detail::report_non_finite_points(mesh, log) > 0) return report;
  const std::size_t tet_offset = report.triangles + report.quads;
  const std::size_t hex_offset = tet_offset + report.tets;

  CellPass pass{mesh, report, log, std::vector<std::uint8_t>(n, 0)};
  // Connectivity of the non-degenerate cells for the face test (build_faces reads
  // only the cells, so the points are not copied).
  TetMesh tets;
  HexMesh hexes;
  std::vector<Index> tet_of, hex_of;
  double min_volume = std::numeric_limits<double>::infinity();
  double min_jacobian = std::numeric_limits<double>::infinity();

  // Tets: the signed volume, measured against the longest edge.
  const auto check_tet = [&](const std::array<Index, 4>& v, const std::string& name, std::uint32_t line,
                             std::int64_t element) {
    const std::array<Vec3, 4> p{mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], mesh.points[v[3]]};
    const double volume = tet_signed_volume(p[0], p[1], p[2], p[3]);
    min_volume = std::min(min_volume, volume);
    double longest = 0;
    for (const auto& [i, j] : kTetEdges) longest = std::max(longest, (p[i] - p[j]).norm());
    if (volume <= kFlatTetTolerance * longest * longest * longest) {
      ++report.inverted;
      log.add("inverted-cell",
              name + " has volume " + number(volume) + (volume > 0 ? " (flat within rounding)" : " (inverted)"), line,
              element);
    }
  };
  // Hexes: the scaled Jacobian.
  const auto check_hex = [&](const std::array<Index, 8>& v, const std::string& name, std::uint32_t line,
                             std::int64_t element) {
    std::array<Vec3, 8> p;
    for (std::size_t i = 0; i < 8; ++i) p[i] = mesh.points[v[i]];
    const std::optional<double> jacobian = hex_scaled_jacobian(p);
    if (!jacobian) {
      ++report.degenerate;
      log.add("degenerate-cell", name + " has a zero-length edge or principal axis", line, element);
      return;
    }
    min_jacobian = std::min(min_jacobian, *jacobian);
    if (*jacobian <= 0) {
      ++report.inverted;
      log.add("inverted-cell", name + " has scaled Jacobian " + number(*jacobian) + " (inverted)", line, element);
    }
  };
  check_cells(mesh.tets, "tet", mesh.lines.tet_lines, tet_offset, pass, tets.tets, tet_of, check_tet);
  check_cells(mesh.hexes, "hex", mesh.lines.hex_lines, hex_offset, pass, hexes.hexes, hex_of, check_hex);
  report.min_tet_volume = tets.tets.empty() ? 0 : min_volume;
  report.min_hex_scaled_jacobian = std::isfinite(min_jacobian) ? min_jacobian : 0;

  report_non_manifold_faces(build_faces(tets), tet_of, "tets", mesh.lines.tet_lines, tet_offset, report, log);
  report_non_manifold_faces(build_faces(hexes), hex_of, "hexes", mesh.lines.hex_lines, hex_offset, report, log);

  for (std::size_t v = 0; v < n; ++v) {
    if (pass.used[v]) continue;
    ++report.unused_vertices;
    if (log.wants("unused-vertex"))
      log.add("unused-vertex", "vertex " + std::to_string(v) + " is used by no tet or hex",
              line_of(mesh.lines.point_lines, v));
  }

  report.valid =
      pass.out_of_range == 0 && report.degenerate == 0 && report.inverted == 0 && report.non_manifold_faces == 0;
  return report;
}

}  // namespace structmesh
