// triangulate_region(): constrained Delaunay triangulation of a Polygon2, optionally
// refined to a quality mesh of about N triangles (design/partition2d.md §2.1).
// The only translation unit of the partition2d module that includes the CGAL
// triangulation headers (§4.2): they are heavy, and everything downstream works on
// the flat arrays of RegionTriangulation.
#include "structmesh/triangulate.hpp"

#include "structmesh/error.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <utility>

namespace structmesh {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_2;

// Vertices created by refinement are default-constructed, hence kInvalidIndex:
// that is how Steiner points are told apart from input points.
struct VertexInfo {
  Index id = kInvalidIndex;
};
// Nesting level of the flood fill; -1 = not reached yet.
struct FaceInfo {
  int level = -1;
};

using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fbc =
    CGAL::Constrained_Delaunay_triangulation_face_base_2<K, CGAL::Constrained_triangulation_face_base_2<K, Fbi>>;
// Delaunay_mesh_face_base_2 adds the in_domain flag the mesher reads (§2.1: the
// flood fill's result is copied into set_in_domain).
using Fb = CGAL::Delaunay_mesh_face_base_2<K, Fbc>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// The default tag, spelled out: a proper crossing of two constraints would need a
// constructed (inexact) intersection point, and this tag throws instead. Unlike
// No_constraint_intersection_tag it still lets the mesher insert points on
// constrained edges, which refinement must do.
using Cdt =
    CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;
using FaceHandle = Cdt::Face_handle;
using VertexHandle = Cdt::Vertex_handle;

std::string point_text(const Vec2& p) { return "(" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ")"; }

std::string segment_text(const Polygon2& region, std::size_t ring, Index a, Index b) {
  return "segment " + std::to_string(a) + "-" + std::to_string(b) + " " + point_text(region.points[a]) + "-" +
         point_text(region.points[b]) + " of ring " + std::to_string(ring);
}

void check_rings(const Polygon2& region) {
  if (region.ring_count() == 0) throw InputError("triangulate_region: the region has no rings");
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    if (region.ring(r).size() < 3) {
      throw InputError("triangulate_region: ring " + std::to_string(r) + " has " +
                       std::to_string(region.ring(r).size()) + " points, fewer than 3");
    }
  }
  for (std::size_t i = 0; i < region.points.size(); ++i) {
    if (!region.points[i].allFinite()) {
      throw InputError("triangulate_region: point " + std::to_string(i) + " is not finite");
    }
  }
}

// The index of the first point at the same coordinates as each point (itself when
// it is the first): sorting, O(n log n).
std::vector<Index> first_at_same_place(const Polygon2& region) {
  std::vector<Index> order(region.points.size());
  std::iota(order.begin(), order.end(), Index{0});
  const auto less = [&](Index a, Index b) {
    const Vec2 &p = region.points[a], &q = region.points[b];
    return p.x() != q.x() ? p.x() < q.x() : p.y() != q.y() ? p.y() < q.y() : a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<Index> first(region.points.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const bool same = k > 0 && region.points[order[k - 1]] == region.points[order[k]];
    first[order[k]] = same ? first[order[k - 1]] : order[k];
  }
  return first;
}

// The CDT inserted n points but holds fewer vertices: name two coincident points.
[[noreturn]] void throw_duplicate(const Polygon2& region) {
  const std::vector<Index> first = first_at_same_place(region);
  for (Index i = 0; i < first.size(); ++i) {
    if (first[i] != i) {
      throw InputError("triangulate_region: points " + std::to_string(first[i]) + " and " + std::to_string(i) +
                       " coincide at " + point_text(region.points[i]) + " (repeated point or touching rings)");
    }
  }
  throw Error("triangulate_region: the triangulation lost input points for no visible reason");
}

// Inside/outside by parity (RECIPES.md: mark_domain_in_triangulation is not in CGAL
// 5.5): flood fill from the infinite face across unconstrained edges keeps the
// nesting level, crossing a constrained edge starts a new fill at level + 1; a face
// is inside iff its level is odd (outer ring crossed once, a hole twice).
void mark_domain(Cdt& cdt) {
  for (const FaceHandle f : cdt.all_face_handles()) f->info().level = -1;
  std::vector<FaceHandle> stack;
  std::vector<Cdt::Edge> border;
  const auto fill = [&](FaceHandle start, int level) {
    if (start->info().level != -1) return;
    start->info().level = level;
    stack.push_back(start);
    while (!stack.empty()) {
      const FaceHandle f = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        const FaceHandle n = f->neighbor(i);
        if (n->info().level != -1) continue;
        if (f->is_constrained(i)) {
          border.emplace_back(f, i);
        } else {
          n->info().level = level;
          stack.push_back(n);
        }
      }
    }
  };
  fill(cdt.infinite_face(), 0);
  // `border` grows while it is scanned; the index loop keeps the order deterministic.
  for (std::size_t k = 0; k < border.size(); ++k) {
    const auto [f, i] = border[k];
    fill(f->neighbor(i), f->info().level + 1);
  }
  for (const FaceHandle f : cdt.all_face_handles()) f->set_in_domain(!cdt.is_infinite(f) && f->info().level % 2 == 1);
}

double squared_distance_to_segment(const Point& p, const Point& a, const Point& b) {
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  const double length2 = dx * dx + dy * dy;
  double t = length2 > 0 ? ((p.x() - a.x()) * dx + (p.y() - a.y()) * dy) / length2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const double ex = a.x() + t * dx - p.x(), ey = a.y() + t * dy - p.y();
  return ex * ex + ey * ey;
}

// Steiner grid (§2.1): the points of a square grid over the bounding box that are
// at least spacing/4 from every boundary segment (near the boundary the boundary
// points themselves bound the triangle size, and a grid point next to a segment
// would only make slivers). Points outside the region are kept too: they are
// inserted with the boundary points before the constraints, end up in outside
// faces, and are never numbered. Locating each point in the constrained
// triangulation instead would walk across the long slivers of a fine boundary
// (measured: 4.7 s for 16k points on a 1M-segment Key). Segments are binned into
// a bucket grid of the same spacing, so the distance test is O(n + grid).
std::vector<Point> steiner_grid(const Polygon2& region, double spacing) {
  const BoundingBox2 box = region.bounding_box();
  const auto columns = static_cast<long long>(std::floor((box.max.x() - box.min.x()) / spacing)) + 1;
  const auto rows = static_cast<long long>(std::floor((box.max.y() - box.min.y()) / spacing)) + 1;
  if (columns * rows > 100'000'000LL) throw InputError("triangulate_region: Steiner grid too fine");
  // Centre the grid in the box so symmetric regions get symmetric grids.
  const double x0 = 0.5 * (box.min.x() + box.max.x()) - 0.5 * static_cast<double>(columns - 1) * spacing;
  const double y0 = 0.5 * (box.min.y() + box.max.y()) - 0.5 * static_cast<double>(rows - 1) * spacing;
  const auto bucket_of = [&](double v, double origin, long long count) {
    return std::clamp(static_cast<long long>(std::floor((v - origin) / spacing + 0.5)), 0LL, count - 1);
  };
  // Bucket (c, r) holds the segments whose bounding box, widened by a quarter
  // spacing, overlaps the grid point (c, r)'s cell.
  std::vector<std::uint32_t> count(static_cast<std::size_t>(columns * rows) + 1, 0);
  std::vector<std::array<Index, 2>> segments;
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const Index begin = region.ring_offsets[r], end = region.ring_offsets[r + 1];
    for (Index a = begin; a < end; ++a) segments.push_back({a, a + 1 == end ? begin : a + 1});
  }
  const double margin = 0.25 * spacing;
  const auto for_buckets = [&](const std::array<Index, 2>& segment, const auto& visit) {
    const Vec2 &p = region.points[segment[0]], &q = region.points[segment[1]];
    const long long c0 = bucket_of(std::min(p.x(), q.x()) - margin, x0, columns);
    const long long c1 = bucket_of(std::max(p.x(), q.x()) + margin, x0, columns);
    const long long r0 = bucket_of(std::min(p.y(), q.y()) - margin, y0, rows);
    const long long r1 = bucket_of(std::max(p.y(), q.y()) + margin, y0, rows);
    for (long long r = r0; r <= r1; ++r) {
      for (long long c = c0; c <= c1; ++c) visit(static_cast<std::size_t>(r * columns + c));
    }
  };
  for (const auto& segment : segments) for_buckets(segment, [&](std::size_t b) { ++count[b + 1]; });
  for (std::size_t b = 1; b < count.size(); ++b) count[b] += count[b - 1];
  std::vector<Index> bucket_segments(count.back());
  std::vector<std::uint32_t> fill(count.begin(), count.end() - 1);
  for (Index s = 0; s < segments.size(); ++s) {
    for_buckets(segments[s], [&](std::size_t b) { bucket_segments[fill[b]++] = s; });
  }
  const double clearance2 = margin * margin;
  std::vector<Point> points;
  for (long long r = 0; r < rows; ++r) {
    for (long long c = 0; c < columns; ++c) {
      const Point p(x0 + static_cast<double>(c) * spacing, y0 + static_cast<double>(r) * spacing);
      const std::size_t b = static_cast<std::size_t>(r * columns + c);
      bool clear = true;
      for (std::uint32_t i = count[b]; i < count[b + 1] && clear; ++i) {
        const auto& segment = segments[bucket_segments[i]];
        const Vec2 &a = region.points[segment[0]], &q = region.points[segment[1]];
        clear = squared_distance_to_segment(p, Point(a.x(), a.y()), Point(q.x(), q.y())) >= clearance2;
      }
      if (clear) points.push_back(p);
    }
  }
  return points;
}

// Builds the CDT of the rings (§2.1): points with their input index in bulk (spatially
// sorted by CGAL), then one constraint per ring segment between vertex handles.
void build(const Polygon2& region, double steiner_spacing, bool merge_repeated, Cdt& cdt) {
  const std::size_t n = region.points.size();
  // Without merging every point is its own vertex (a repeat is reported below).
  std::vector<Index> vertex_of(n);
  if (merge_repeated) {
    vertex_of = first_at_same_place(region);
  } else {
    std::iota(vertex_of.begin(), vertex_of.end(), Index{0});
  }
  const std::vector<Point> steiner = steiner_spacing > 0 ? steiner_grid(region, steiner_spacing) : std::vector<Point>{};
  std::vector<std::pair<Point, VertexInfo>> pairs;
  pairs.reserve(n + steiner.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (vertex_of[i] != i) continue;
    pairs.emplace_back(Point(region.points[i].x(), region.points[i].y()), VertexInfo{static_cast<Index>(i)});
  }
  // Steiner points keep the default info (kInvalidIndex) and are numbered later by first use.
  for (const Point& p : steiner) pairs.emplace_back(p, VertexInfo{});
  cdt.insert(pairs.begin(), pairs.end());
  if (cdt.number_of_vertices() != pairs.size()) throw_duplicate(region);

  std::vector<VertexHandle> handle(n);
  for (const VertexHandle v : cdt.finite_vertex_handles()) {
    if (v->info().id != kInvalidIndex) handle[v->info().id] = v;
  }
  for (std::size_t i = 0; i < n; ++i) handle[i] = handle[vertex_of[i]];

  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const Index begin = region.ring_offsets[r], end = region.ring_offsets[r + 1];
    for (Index a = begin; a < end; ++a) {
      const Index b = a + 1 == end ? begin : a + 1;
      if (handle[a] == handle[b]) continue;  // a merged zero-length segment
      try {
        cdt.insert_constraint(handle[a], handle[b]);
      } catch (const Cdt::Intersection_of_constraints_exception&) {
        throw InputError("triangulate_region: " + segment_text(region, r, a, b) +
                         " crosses or overlaps another segment (self-crossing ring or crossing rings; "
                         "check_region lists every crossing)");
      }
    }
  }
  // Constraints through an existing vertex are split there silently (no construction
  // needed, so no exception): a vertex touching another segment. The segment is then
  // not a single edge.
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const Index begin = region.ring_offsets[r], end = region.ring_offsets[r + 1];
    for (Index a = begin; a < end; ++a) {
      const Index b = a + 1 == end ? begin : a + 1;
      if (handle[a] != handle[b] && !cdt.is_edge(handle[a], handle[b])) {
        throw InputError("triangulate_region: a vertex of the region lies on " + segment_text(region, r, a, b) +
                         " (touching rings)");
      }
    }
  }
  if (cdt.number_of_vertices() != pairs.size()) {
    throw Error("triangulate_region: constraint insertion added vertices");
  }
  mark_domain(cdt);
}

std::size_t inside_count(const Cdt& cdt) {
  std::size_t count = 0;
  for (const FaceHandle f : cdt.finite_face_handles()) count += f->is_in_domain() ? 1 : 0;
  return count;
}

// Delaunay refinement to about `target` triangles (§2.1, for the METIS/MADD
// baselines). B = 0.125 is CGAL's default shape bound: minimum angle arcsin(√B) ≈
// 20.7°. The angle bound alone already grades the mesh from the boundary segments
// (measured on the Key and the Pipe at 2k and 20k segments: 2.8–3.2 triangles per
// boundary segment), so that count is a floor; when the target is above it, an
// edge-length bound adds interior triangles. The bound is an upper bound on edge length, so triangles
// average less than the equilateral triangle of that edge (area √3/4 s²): the
// factor 1.45 was measured on the Key and the Pipe (3–6% over target when the size
// bound dominates; with the floor estimate below, first attempts land 0–26% off).
// The count is then corrected (count ∝ 1/s²) until within ±25%, at most 4 attempts
// (best effort); refining further works in place, coarsening needs a rebuild.
void refine(const Polygon2& region, std::size_t target, double steiner_spacing, bool bound_size_above_floor,
            bool merge_repeated, Cdt& cdt) {
  using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
  constexpr double kShapeBound = 0.125;
  CGAL::refine_Delaunay_mesh_2(cdt, Criteria(kShapeBound, 0), true);
  mark_domain(cdt);
  const auto wanted = static_cast<double>(target);
  const auto floor_count = static_cast<double>(inside_count(cdt));
  if (floor_count >= 0.8 * wanted) {
    if (bound_size_above_floor) {
      CGAL::refine_Delaunay_mesh_2(
          cdt, Criteria(kShapeBound, 1.45 * std::sqrt(4.0 * std::abs(area(region)) / (std::sqrt(3.0) * wanted))), true);
      mark_domain(cdt);
    }
    return;
  }

  // About half the boundary-graded triangles survive inside the size-bounded mesh.
  const double interior = std::max(wanted - 0.5 * floor_count, 0.5 * wanted);
  double size = 1.45 * std::sqrt(4.0 * std::abs(area(region)) / (std::sqrt(3.0) * interior));
  constexpr int kAttempts = 4;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    CGAL::refine_Delaunay_mesh_2(cdt, Criteria(kShapeBound, size), true);
    mark_domain(cdt);
    const double ratio = static_cast<double>(inside_count(cdt)) / wanted;
    if (ratio > 0.8 && ratio < 1.25) return;
    size *= std::sqrt(ratio);
    if (ratio >= 1.25 && attempt + 1 < kAttempts) {
      cdt.clear();
      build(region, steiner_spacing, merge_repeated, cdt);
    }
  }
}

// The input segments, each with the region on its left (merge_repeated_points:
// touching rings cannot be walked). Needs an unrefined triangulation, where every
// segment is one edge.
std::vector<std::array<Index, 2>> oriented_segments(const Polygon2& region, const Cdt& cdt) {
  const std::vector<Index> vertex_of = first_at_same_place(region);
  std::vector<VertexHandle> handle(region.points.size());
  for (const VertexHandle v : cdt.finite_vertex_handles()) {
    if (v->info().id < handle.size() && vertex_of[v->info().id] == v->info().id) handle[v->info().id] = v;
  }
  std::vector<std::array<Index, 2>> edges;
  edges.reserve(region.points.size());
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const Index begin = region.ring_offsets[r], end = region.ring_offsets[r + 1];
    for (Index a = begin; a < end; ++a) {
      const Index va = vertex_of[a], vb = vertex_of[a + 1 == end ? begin : a + 1];
      if (va == vb) continue;
      FaceHandle face;
      int i = 0;
      if (!cdt.is_edge(handle[va], handle[vb], face, i)) {
        throw Error("triangulate_region: segment " + std::to_string(a) + " is not an edge of the triangulation");
      }
      // In a counter-clockwise face the edge opposite vertex i runs from ccw(i) to cw(i).
      const bool face_on_left_of_ab = face->vertex(Cdt::ccw(i)) == handle[va];
      const bool left_inside = face_on_left_of_ab == face->is_in_domain();
      edges.push_back(left_inside ? std::array<Index, 2>{va, vb} : std::array<Index, 2>{vb, va});
    }
  }
  return edges;
}

}  // namespace

RegionTriangulation triangulate_region(const Polygon2& region, const TriangulateOptions& options) {
  check_rings(region);
  if (options.merge_repeated_points && options.target_triangles > 0) {
    throw InputError("triangulate_region: merge_repeated_points cannot be combined with refinement");
  }
  Cdt cdt;
  build(region, options.steiner_spacing, options.merge_repeated_points, cdt);
  if (options.target_triangles > 0)
    refine(region, options.target_triangles, options.steiner_spacing, options.bound_size_above_floor,
           options.merge_repeated_points, cdt);

  // Deterministic, spatially local triangle order (§2.1): Hilbert order of centroids.
  std::vector<FaceHandle> faces;
  std::vector<Point> centroids;
  for (const FaceHandle f : cdt.finite_face_handles()) {
    if (!f->is_in_domain()) continue;
    faces.push_back(f);
    centroids.push_back(CGAL::centroid(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()));
  }
  std::vector<std::size_t> order(faces.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  using SortTraits = CGAL::Spatial_sort_traits_adapter_2<K, CGAL::Pointer_property_map<Point>::const_type>;
  CGAL::hilbert_sort(order.begin(), order.end(), SortTraits(CGAL::make_property_map(std::as_const(centroids))));

  RegionTriangulation result;
  // Input points by index from the input array: bit-identical boundary vertices.
  result.points = region.points;
  const auto id_of = [&](VertexHandle v) {
    if (v->info().id == kInvalidIndex) {
      v->info().id = static_cast<Index>(result.points.size());
      result.points.emplace_back(v->point().x(), v->point().y());
    }
    return v->info().id;
  };
  result.triangles.reserve(faces.size());
  for (const std::size_t k : order) {
    const FaceHandle f = faces[k];
    std::array<Index, 3> t{id_of(f->vertex(0)), id_of(f->vertex(1)), id_of(f->vertex(2))};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    result.triangles.push_back(t);
  }

  if (options.merge_repeated_points) {
    // Rings may touch, so a vertex can have several outgoing boundary edges and the
    // rings cannot be walked: every input segment instead, turned so that the face on
    // its left is inside. Refinement may have split a segment; then its first piece
    // decides the direction and the pieces are listed in order.
    result.boundary_edges = oriented_segments(region, cdt);
    return result;
  }
  // Constrained edges with the region on their left: in a counter-clockwise face the
  // edge opposite vertex i runs from ccw(i) to cw(i). Each boundary vertex has one
  // outgoing boundary edge (rings neither touch nor cross), so the rings can be walked.
  std::vector<Index> next(result.points.size(), kInvalidIndex);
  std::size_t constrained = 0;
  for (const FaceHandle f : faces) {
    for (int i = 0; i < 3; ++i) {
      if (!f->is_constrained(i)) continue;
      const Index a = f->vertex(Cdt::ccw(i))->info().id, b = f->vertex(Cdt::cw(i))->info().id;
      if (next[a] != kInvalidIndex)
        throw Error("triangulate_region: boundary vertex " + std::to_string(a) + " pinched");
      next[a] = b;
      ++constrained;
    }
  }
  result.boundary_edges.reserve(constrained);
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const Index start = region.ring_offsets[r];
    Index a = start;
    do {
      const Index b = next[a];
      if (b == kInvalidIndex || result.boundary_edges.size() == constrained) {
        throw Error("triangulate_region: the constrained edges of ring " + std::to_string(r) + " do not close");
      }
      result.boundary_edges.push_back({a, b});
      a = b;
    } while (a != start);
  }
  if (result.boundary_edges.size() != constrained) {
    throw Error("triangulate_region: constrained edges left over after walking the rings");
  }
  return result;
}

}  // namespace structmesh
