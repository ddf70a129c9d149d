// Self-intersection search for check_surface().
//
// Why box_intersection_d + do_intersect rather than PMP::self_intersections:
// PMP works on a valid FaceGraph (a halfedge structure), which our bad inputs
// (non-manifold edges, bowtie vertices, flipped faces, polygon soups) cannot be
// turned into without repairing them first, and repairing is exactly what a
// checker must not do. Boxes and exact triangle predicates need no topology, so
// every face of any soup is tested.
//
// Epick: the predicates (do_intersect, orientation, collinear) are exact, which
// is all we need; nothing is constructed.
#include "check/self_intersections.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>

namespace structmesh::detail {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;
// One box per triangle (a quad gives two); info = the triangle's index in `Primitive`s.
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, Index>;

Point to_point(const Vec3& p) { return {p.x(), p.y(), p.z()}; }

// A triangle as the simplex it really spans, so zero-area faces are still tested
// (CGAL's triangle predicates require non-degenerate triangles).
struct Primitive {
  enum class Kind : std::uint8_t { Triangle, Segment, Point };
  Kind kind = Kind::Triangle;
  std::array<Point, 3> p;  // Triangle: all three; Segment: p[0], p[1]; Point: p[0]
  Index face = 0;
  std::array<Index, 3> vertices{};
  bool face_is_triangle = true;

  Triangle triangle() const { return {p[0], p[1], p[2]}; }
  Segment segment() const { return {p[0], p[1]}; }
};

Primitive make_primitive(std::span<const Vec3> points, const std::array<Index, 3>& v, Index face, bool is_triangle) {
  Primitive prim;
  prim.face = face;
  prim.vertices = v;
  prim.face_is_triangle = is_triangle;
  const Point a = to_point(points[v[0]]), b = to_point(points[v[1]]), c = to_point(points[v[2]]);
  prim.p = {a, b, c};
  if (!CGAL::collinear(a, b, c)) return prim;
  if (a == b && b == c) {
    prim.kind = Primitive::Kind::Point;
    return prim;
  }
  prim.kind = Primitive::Kind::Segment;
  // The two extreme points of three collinear points (exact ordering test).
  if (CGAL::collinear_are_ordered_along_line(a, b, c)) {
    prim.p = {a, c, c};
  } else if (CGAL::collinear_are_ordered_along_line(b, a, c)) {
    prim.p = {b, c, c};
  } else {
    prim.p = {a, b, b};
  }
  return prim;
}

bool intersect(const Primitive& x, const Primitive& y) {
  using K = Primitive::Kind;
  if (x.kind > y.kind) return intersect(y, x);  // now x.kind <= y.kind
  switch (x.kind) {
    case K::Triangle:
      switch (y.kind) {
        case K::Triangle:
          return CGAL::do_intersect(x.triangle(), y.triangle());
        case K::Segment:
          return CGAL::do_intersect(x.triangle(), y.segment());
        case K::Point:
          return CGAL::do_intersect(x.triangle(), y.p[0]);
      }
      break;
    case K::Segment:
      if (y.kind == K::Segment) return CGAL::do_intersect(x.segment(), y.segment());
      return CGAL::do_intersect(x.segment(), y.p[0]);
    case K::Point:
      return x.p[0] == y.p[0];
  }
  return false;
}

// Two non-degenerate triangles sharing `shared` (1..3) vertex indices: does their
// intersection go beyond the shared vertex or edge? Same tests as CGAL's PMP.
bool adjacent_overlap(const Primitive& x, const Primitive& y, int shared) {
  if (shared == 3) return true;  // the same three vertices: a duplicated face
  // Shared vertices first (same order in both, so a[i] == b[i] for i < shared).
  std::array<Point, 3> a, b;
  int na = 0, nb = shared;
  auto in = [](const std::array<Index, 3>& vs, Index v) { return std::find(vs.begin(), vs.end(), v) != vs.end(); };
  for (int i = 0; i < 3; ++i) {
    if (!in(y.vertices, x.vertices[i])) continue;
    a[na] = b[na] = x.p[i];
    ++na;
  }
  for (int i = 0; i < 3; ++i)
    if (!in(y.vertices, x.vertices[i])) a[na++] = x.p[i];
  for (int j = 0; j < 3; ++j)
    if (!in(x.vertices, y.vertices[j])) b[nb++] = y.p[j];
  if (shared == 2) {
    // Sharing edge a0-a1: they overlap only when coplanar and folded onto the same side.
    return CGAL::coplanar(a[0], a[1], a[2], b[2]) &&
           CGAL::coplanar_orientation(a[0], a[1], a[2], b[2]) == CGAL::POSITIVE;
  }
  // Sharing vertex a0: the planes meet in a line through a0; if both triangles
  // cover a piece of it beyond a0, the shorter piece ends on an opposite edge
  // that lies in the other triangle.
  return CGAL::do_intersect(Segment(a[1], a[2]), y.triangle()) || CGAL::do_intersect(Segment(b[1], b[2]), x.triangle());
}

int shared_vertex_count(std::span<const Index> f, std::span<const Index> g) {
  int shared = 0;
  for (Index u : f) shared += std::find(g.begin(), g.end(), u) != g.end() ? 1 : 0;
  return shared;
}

}  // namespace

bool collinear(const Vec3& p, const Vec3& q, const Vec3& r) {
  return CGAL::collinear(to_point(p), to_point(q), to_point(r));
}

SelfIntersections find_self_intersections(std::span<const Vec3> points, std::span<const std::array<Index, 3>> triangles,
                                          std::span<const std::array<Index, 4>> quads, bool find_adjacent) {
  const std::size_t t_count = triangles.size();
  auto face_vertices = [&](Index face) -> std::span<const Index> {
    if (face < t_count) return triangles[face];
    return quads[face - t_count];
  };

  std::vector<Primitive> prims;
  prims.reserve(t_count + 2 * quads.size());
  for (std::size_t f = 0; f < t_count; ++f) prims.push_back(make_primitive(points, triangles[f], Index(f), true));
  for (std::size_t q = 0; q < quads.size(); ++q) {
    const auto& v = quads[q];
    const Index face = Index(t_count + q);
    prims.push_back(make_primitive(points, {v[0], v[1], v[2]}, face, false));
    prims.push_back(make_primitive(points, {v[0], v[2], v[3]}, face, false));
  }

  std::vector<Box> boxes;
  boxes.reserve(prims.size());
  for (std::size_t i = 0; i < prims.size(); ++i) {
    CGAL::Bbox_3 bbox = prims[i].p[0].bbox() + prims[i].p[1].bbox() + prims[i].p[2].bbox();
    boxes.emplace_back(bbox, Index(i));
  }

  // Box overlaps are cheap and few per face; collect them serially (the callback
  // order is deterministic), then run the exact tests in parallel.
  std::vector<std::array<Index, 2>> candidates, adjacent;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    const Primitive& x = prims[a.info()];
    const Primitive& y = prims[b.info()];
    if (x.face == y.face) return;
    const int shared = shared_vertex_count(face_vertices(x.face), face_vertices(y.face));
    if (shared == 0) {
      candidates.push_back({a.info(), b.info()});
    } else if (find_adjacent && x.face_is_triangle && y.face_is_triangle && x.kind == Primitive::Kind::Triangle &&
               y.kind == Primitive::Kind::Triangle) {
      adjacent.push_back({a.info(), b.info()});
    }
  });

  std::vector<std::uint8_t> hit(candidates.size(), 0), adjacent_hit(adjacent.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 256), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k)
      hit[k] = intersect(prims[candidates[k][0]], prims[candidates[k][1]]) ? 1 : 0;
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, adjacent.size(), 256), [&](const auto& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const Primitive& x = prims[adjacent[k][0]];
      const Primitive& y = prims[adjacent[k][1]];
      adjacent_hit[k] = adjacent_overlap(x, y, shared_vertex_count(x.vertices, y.vertices)) ? 1 : 0;
    }
  });

  auto face_pairs = [&](const std::vector<std::array<Index, 2>>& pairs, const std::vector<std::uint8_t>& flags) {
    std::vector<std::array<Index, 2>> out;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      if (!flags[k]) continue;
      const Index f = prims[pairs[k][0]].face, g = prims[pairs[k][1]].face;
      out.push_back({std::min(f, g), std::max(f, g)});
    }
    // A quad pair can be found through several of their triangles.
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  };
  SelfIntersections result;
  result.disjoint_pairs = face_pairs(candidates, hit);
  result.adjacent_overlaps = face_pairs(adjacent, adjacent_hit);
  return result;
}

}  // namespace structmesh::detail
