// check_surface(): topology and geometry checks of a triangle/quad surface that
// may be anything from a clean closed manifold to a polygon soup.
//
// Nothing here assumes manifold input: adjacency is one sort of directed edge
// uses, fans are found with a union-find over face corners, and the
// self-intersection search (self_intersections.cpp) needs no topology at all.
//
// Conventions of the report (see check.hpp):
// - Faces are numbered in bundle cell order: all triangles, then all quads.
//   Vertex and face indices in messages are 0-based; `line` is the file line.
// - Faces that repeat a vertex index ("collapsed") are reported as degenerate and
//   left out of the topology (edges, fans, components, Euler characteristic,
//   orientation, volume): their "edges" are not edges of a surface. Zero-area faces
//   with distinct indices are degenerate too but stay in the topology.
// - Non-manifold vertex: its faces do not form one fan joined through manifold
//   (two-face) edges. So the end points of a non-manifold edge count as well.
// - Genus is reported for closed, edge-manifold, vertex-manifold, oriented
//   surfaces only; with several components it is the sum of their genera,
//   (2 * components - chi) / 2.
#include "check/problem_log.hpp"
#include "check/self_intersections.hpp"
#include "structmesh/check.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <numeric>
#include <string>
#include <tuple>

namespace structmesh {
namespace {

using detail::line_of;
using detail::ProblemLog;
using detail::repeats_vertex;

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), Index{0}); }
  Index find(Index x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<Index> parent_;
};

// Triangles and quads seen as one list of faces with 3 or 4 corners each.
// Face f < T is triangle f, otherwise quad f - T; corner k of face f has the
// global corner id first_corner(f) + k.
class Faces {
 public:
  explicit Faces(const MeshBundle& mesh) : mesh_(mesh), t_(mesh.triangles.size()) {}
  std::size_t size() const { return t_ + mesh_.quads.size(); }
  std::size_t corner_count() const { return 3 * t_ + 4 * mesh_.quads.size(); }
  bool is_triangle(std::size_t f) const { return f < t_; }
  int degree(std::size_t f) const { return f < t_ ? 3 : 4; }
  std::size_t first_corner(std::size_t f) const { return f < t_ ? 3 * f : 3 * t_ + 4 * (f - t_); }
  std::span<const Index> vertices(std::size_t f) const {
    if (f < t_) return mesh_.triangles[f];
    return mesh_.quads[f - t_];
  }
  std::uint32_t line(std::size_t f) const {
    return f < t_ ? line_of(mesh_.lines.triangle_lines, f) : line_of(mesh_.lines.quad_lines, f - t_);
  }
  std::string name(std::size_t f) const {
    if (f < t_) return "face " + std::to_string(f);
    return "face " + std::to_string(f) + " (quad " + std::to_string(f - t_) + ")";
  }

 private:
  const MeshBundle& mesh_;
  std::size_t t_;
};

bool zero_area(const std::vector<Vec3>& p, std::span<const Index> v) {
  using detail::collinear;
  if (v.size() == 3) return collinear(p[v[0]], p[v[1]], p[v[2]]);
  // A quad has zero area when either diagonal splits it into two zero-area triangles.
  return (collinear(p[v[0]], p[v[1]], p[v[2]]) && collinear(p[v[0]], p[v[2]], p[v[3]])) ||
         (collinear(p[v[1]], p[v[2]], p[v[3]]) && collinear(p[v[1]], p[v[3]], p[v[0]]));
}

std::string edge_name(Index a, Index b) { return "edge " + std::to_string(a) + "-" + std::to_string(b); }

// One use of an undirected edge by a face: slot k is the edge from corner k to k+1.
struct EdgeUse {
  Index lo, hi, face;
  std::uint8_t slot;
  bool forward;  // the face runs lo -> hi
};

}  // namespace

SurfaceReport check_surface(const MeshBundle& mesh, const CheckOptions& options) {
  SurfaceReport report;
  ProblemLog log(report.problems, options.max_problems_per_kind);
  const Faces faces(mesh);
  const std::size_t face_count = faces.size();
  const std::size_t point_count = mesh.points.size();
  report.faces = face_count;
  if (face_count == 0) {
    log.add("no-faces", "the mesh has no triangles or quads");
    return report;
  }

  // Readers reject bad indices, but a hand-made bundle may have them: report and stop.
  std::size_t out_of_range = 0;
  for (std::size_t f = 0; f < face_count; ++f) {
    for (Index v : faces.vertices(f)) {
      if (v < point_count) continue;
      ++out_of_range;
      if (!log.wants("index-out-of-range")) break;
      log.add("index-out-of-range",
              faces.name(f) + " refers to vertex " + std::to_string(v) + " but there are only " +
                  std::to_string(point_count) + " points",
              faces.line(f), std::int64_t(f));
      break;
    }
  }
  if (out_of_range > 0) return report;
  // Likewise NaN or infinite coordinates, which the exact predicates cannot take.
  if (detail::report_non_finite_points(mesh, log) > 0) return report;

  // --- degenerate faces, used vertices ---
  std::vector<std::uint8_t> collapsed(face_count, 0);
  std::vector<std::uint8_t> used(point_count, 0), used_topo(point_count, 0);
  for (std::size_t f = 0; f < face_count; ++f) {
    const auto v = faces.vertices(f);
    collapsed[f] = repeats_vertex(v) ? 1 : 0;
    for (Index u : v) {
      used[u] = 1;
      if (!collapsed[f]) used_topo[u] = 1;
    }
    if (collapsed[f]) {
      ++report.degenerate_faces;
      if (log.wants("degenerate-face"))
        log.add("degenerate-face", faces.name(f) + " repeats a vertex index", faces.line(f), std::int64_t(f));
    } else if (zero_area(mesh.points, v)) {
      ++report.degenerate_faces;
      if (log.wants("degenerate-face"))
        log.add("degenerate-face", faces.name(f) + " has zero area (its vertices are collinear)", faces.line(f),
                std::int64_t(f));
    }
  }
  std::size_t topo_vertices = 0;
  for (std::size_t v = 0; v < point_count; ++v) {
    report.vertices += used[v];
    topo_vertices += used_topo[v];
    if (used[v]) continue;
    ++report.isolated_vertices;
    if (log.wants("isolated-vertex"))
      log.add("isolated-vertex", "vertex " + std::to_string(v) + " is used by no face",
              line_of(mesh.lines.point_lines, v));
  }

  // --- edges: sort every directed use once ---
  std::vector<EdgeUse> uses;
  uses.reserve(faces.corner_count());
  std::size_t topo_faces = 0;
  for (std::size_t f = 0; f < face_count; ++f) {
    if (collapsed[f]) continue;
    ++topo_faces;
    const auto v = faces.vertices(f);
    const int n = faces.degree(f);
    for (int k = 0; k < n; ++k) {
      const Index a = v[k], b = v[(k + 1) % n];
      uses.push_back({std::min(a, b), std::max(a, b), Index(f), std::uint8_t(k), a < b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.lo, x.hi, x.face, x.slot) < std::tie(y.lo, y.hi, y.face, y.slot);
  });

  // Per corner (= per edge slot): the face across a manifold edge and whether it
  // runs the edge in the same direction (an orientation conflict).
  std::vector<Index> across(faces.corner_count(), kInvalidIndex);
  std::vector<std::uint8_t> same_direction(faces.corner_count(), 0);
  UnionFind fans(faces.corner_count());  // corners joined around a vertex through manifold edges
  auto corner_of = [&](const EdgeUse& u, bool want_lo) {
    // The edge in slot k runs from corner k to corner k+1.
    const bool at_k = u.forward == want_lo;
    return Index(faces.first_corner(u.face) + (at_k ? u.slot : (u.slot + 1) % faces.degree(u.face)));
  };
  for (std::size_t b = 0; b < uses.size();) {
    std::size_t e = b + 1;
    while (e < uses.size() && uses[e].lo == uses[b].lo && uses[e].hi == uses[b].hi) ++e;
    const EdgeUse& u = uses[b];
    ++report.edges;
    const std::size_t count = e - b;
    if (count == 1) {
      ++report.boundary_edges;
      if (log.wants("open-edge"))
        log.add("open-edge", edge_name(u.lo, u.hi) + " is used by " + faces.name(u.face) + " only (boundary)",
                faces.line(u.face), std::int64_t(u.face));
    } else if (count > 2) {
      ++report.non_manifold_edges;
      if (log.wants("non-manifold-edge")) {
        std::string list;
        for (std::size_t k = b; k < e; ++k) list.append(k == b ? "" : ", ").append(std::to_string(uses[k].face));
        log.add("non-manifold-edge",
                edge_name(u.lo, u.hi) + " is shared by " + std::to_string(count) + " faces: " + list,
                faces.line(u.face), std::int64_t(u.face));
      }
    } else {
      const EdgeUse& w = uses[b + 1];
      const bool same = u.forward == w.forward;
      const std::size_t cu = faces.first_corner(u.face) + u.slot, cw = faces.first_corner(w.face) + w.slot;
      across[cu] = w.face;
      across[cw] = u.face;
      same_direction[cu] = same_direction[cw] = same ? 1 : 0;
      fans.unite(corner_of(u, true), corner_of(w, true));
      fans.unite(corner_of(u, false), corner_of(w, false));
      if (same) {
        ++report.inconsistent_edges;
        if (log.wants("inconsistent-edge"))
          log.add("inconsistent-edge",
                  faces.name(u.face) + " and " + faces.name(w.face) + " both run " + edge_name(u.lo, u.hi) +
                      " in the same direction (inconsistent orientation)",
                  faces.line(w.face), std::int64_t(w.face));
      }
    }
    b = e;
  }
  report.euler_characteristic = long(topo_vertices) - long(report.edges) + long(topo_faces);

  // --- non-manifold vertices: more than one fan of corners around the vertex ---
  {
    std::vector<Index> first_root(point_count, kInvalidIndex), first_face(point_count, kInvalidIndex);
    std::vector<std::uint8_t> flagged(point_count, 0);
    for (std::size_t f = 0; f < face_count; ++f) {
      if (collapsed[f]) continue;
      const auto v = faces.vertices(f);
      for (int k = 0; k < faces.degree(f); ++k) {
        const Index root = fans.find(Index(faces.first_corner(f) + k));
        const Index u = v[k];
        if (first_root[u] == kInvalidIndex) {
          first_root[u] = root;
          first_face[u] = Index(f);
        } else if (first_root[u] != root && !flagged[u]) {
          flagged[u] = 1;
          ++report.non_manifold_vertices;
          log.add("non-manifold-vertex",
                  "vertex " + std::to_string(u) + ": its faces do not form one fan (" + faces.name(first_face[u]) +
                      " and " + faces.name(f) + " meet only at this vertex or through a non-manifold edge)",
                  line_of(mesh.lines.point_lines, u));
        }
      }
    }
  }

  // --- connected components (through shared vertices) ---
  {
    UnionFind vertex_sets(point_count);
    for (std::size_t f = 0; f < face_count; ++f) {
      if (collapsed[f]) continue;
      const auto v = faces.vertices(f);
      for (std::size_t k = 1; k < v.size(); ++k) vertex_sets.unite(v[0], v[k]);
    }
    for (std::size_t v = 0; v < point_count; ++v)
      if (used_topo[v] && vertex_sets.find(Index(v)) == v) ++report.components;
  }

  // --- orientation: two-colour each part joined by manifold edges, name the minority ---
  if (report.inconsistent_edges > 0) {
    std::vector<std::int8_t> parity(face_count, -1);
    std::vector<Index> part;
    for (std::size_t seed = 0; seed < face_count; ++seed) {
      if (collapsed[seed] || parity[seed] >= 0) continue;
      part.assign(1, Index(seed));
      parity[seed] = 0;
      bool orientable = true;
      for (std::size_t head = 0; head < part.size(); ++head) {
        const Index f = part[head];
        for (int k = 0; k < faces.degree(f); ++k) {
          const std::size_t c = faces.first_corner(f) + k;
          const Index g = across[c];
          if (g == kInvalidIndex) continue;
          const std::int8_t want = std::int8_t(parity[f] ^ same_direction[c]);
          if (parity[g] < 0) {
            parity[g] = want;
            part.push_back(g);
          } else if (parity[g] != want) {
            orientable = false;
          }
        }
      }
      if (!orientable) {
        log.add("non-orientable",
                "the " + std::to_string(part.size()) + " faces joined to " + faces.name(seed) +
                    " cannot be oriented consistently (non-orientable, like a Moebius strip)",
                faces.line(seed), std::int64_t(seed));
        continue;
      }
      std::size_t ones = 0;
      for (Index f : part) ones += std::size_t(parity[f]);
      if (ones == 0) continue;
      // Flip the smaller side; on a tie, the side without the seed face.
      const std::int8_t flip = 2 * ones <= part.size() ? 1 : 0;
      const std::size_t flipped = flip ? ones : part.size() - ones;
      report.flipped_faces += flipped;
      for (Index f : part) {
        if (parity[f] != flip) continue;
        if (!log.wants("flipped-face")) break;
        log.add("flipped-face",
                faces.name(f) + " is oriented against its neighbours (" + std::to_string(flipped) + " of the " +
                    std::to_string(part.size()) + " faces joined to it would need flipping)",
                faces.line(f), std::int64_t(f));
      }
    }
  }

  // --- signed volume by the divergence theorem, relative to the box centre for conditioning ---
  {
    BoundingBox3 box;
    for (std::size_t v = 0; v < point_count; ++v)
      if (used_topo[v]) box.extend(mesh.points[v]);
    const Vec3 origin = box.empty() ? Vec3::Zero() : Vec3(0.5 * (box.min + box.max));
    double six_volume = 0;
    for (std::size_t f = 0; f < face_count; ++f) {
      if (collapsed[f]) continue;
      const auto v = faces.vertices(f);
      const Vec3 a = mesh.points[v[0]] - origin;
      for (std::size_t k = 1; k + 1 < v.size(); ++k)
        six_volume += a.dot((mesh.points[v[k]] - origin).cross(mesh.points[v[k + 1]] - origin));
    }
    report.signed_volume = six_volume / 6.0;
  }

  report.closed = report.boundary_edges == 0 && report.non_manifold_edges == 0;
  report.edge_manifold = report.non_manifold_edges == 0;
  report.oriented = report.inconsistent_edges == 0;
  const bool manifold = report.edge_manifold && report.non_manifold_vertices == 0;
  if (report.closed && manifold && report.oriented) {
    report.genus = int((2 * long(report.components) - report.euler_characteristic) / 2);
    if (report.signed_volume <= 0)
      log.add("negative-volume", "the surface is closed and consistently oriented but its signed volume is " +
                                     std::to_string(report.signed_volume) + ": the normals point inward");
  }

  // --- self-intersections ---
  if (options.self_intersections) {
    const detail::SelfIntersections hits =
        detail::find_self_intersections(mesh.points, mesh.triangles, mesh.quads, /*find_adjacent=*/true);
    report.self_intersections = hits.disjoint_pairs.size();
    report.adjacent_overlaps = hits.adjacent_overlaps.size();
    for (const auto& [f, g] : hits.disjoint_pairs) {
      if (!log.wants("self-intersection")) break;
      log.add("self-intersection", faces.name(f) + " and " + faces.name(g) + " intersect", faces.line(f),
              std::int64_t(f));
    }
    for (const auto& [f, g] : hits.adjacent_overlaps) {
      if (!log.wants("adjacent-overlap")) break;
      log.add("adjacent-overlap",
              faces.name(f) + " and " + faces.name(g) + " share vertices and overlap beyond them (a fold)",
              faces.line(f), std::int64_t(f));
    }
  }

  report.valid_solid_boundary = report.closed && manifold && report.oriented && report.signed_volume > 0 &&
                                report.self_intersections == 0 && report.adjacent_overlaps == 0 &&
                                report.degenerate_faces == 0;
  return report;
}

}  // namespace structmesh
