// curve_skeleton(), resample_skeleton(), inside_solid(): the candidate guards of §2.2.
// The dissertation uses Dey and Sun's medial-geodesic skeleton [43]; Debian has no
// library for it, while CGAL 5.5 ships the mean-curvature-flow skeleton, which is also
// medially centred and keeps one node per absorbed vertex cluster.
#include "structmesh/error.hpp"
#include "structmesh/skeleton.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/extract_mean_curvature_flow_skeleton.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace structmesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

SurfaceMesh to_surface_mesh(const TriMesh& surface) {
  SurfaceMesh mesh;
  mesh.reserve(static_cast<SurfaceMesh::size_type>(surface.points.size()),
               static_cast<SurfaceMesh::size_type>(3 * surface.triangles.size() / 2),
               static_cast<SurfaceMesh::size_type>(surface.triangles.size()));
  for (const Vec3& p : surface.points) mesh.add_vertex(Point(p.x(), p.y(), p.z()));
  for (std::size_t f = 0; f < surface.triangles.size(); ++f) {
    const auto& t = surface.triangles[f];
    const auto face = mesh.add_face(SurfaceMesh::Vertex_index(t[0]), SurfaceMesh::Vertex_index(t[1]),
                                    SurfaceMesh::Vertex_index(t[2]));
    if (face == SurfaceMesh::null_face())
      throw InputError("curve_skeleton: triangle " + std::to_string(f) +
                       " makes the surface non-manifold or inconsistently oriented");
  }
  for (const auto h : mesh.halfedges())
    if (mesh.is_border(h)) throw InputError("curve_skeleton: the surface is open (it has boundary edges)");
  return mesh;
}

// Edge collapse (Lindstrom-Turk cost and placement, CGAL's default) keeps the shape
// and, by the link condition, the topology; a closed surface has about three edges per
// vertex.
void collapse_to(SurfaceMesh& mesh, std::size_t max_vertices) {
  namespace collapse = CGAL::Surface_mesh_simplification;
  const collapse::Count_stop_predicate<SurfaceMesh> stop(3 * max_vertices);
  collapse::edge_collapse(mesh, stop);
  mesh.collect_garbage();
}

}  // namespace

TriMesh simplify_surface(const TriMesh& surface, std::size_t max_vertices) {
  if (surface.triangles.empty()) throw InputError("simplify_surface: the surface has no triangles");
  if (max_vertices == 0 || surface.points.size() <= max_vertices) return surface;
  SurfaceMesh mesh = to_surface_mesh(surface);
  collapse_to(mesh, max_vertices);
  TriMesh result;
  result.points.reserve(mesh.number_of_vertices());
  for (const auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    result.points.emplace_back(p.x(), p.y(), p.z());
  }
  result.triangles.reserve(mesh.number_of_faces());
  for (const auto f : mesh.faces()) {
    std::array<Index, 3> triangle{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) triangle[k++] = static_cast<Index>(v);
    result.triangles.push_back(triangle);
  }
  return result;
}

CurveSkeleton curve_skeleton(const TriMesh& surface, std::size_t max_vertices) {
  if (surface.triangles.empty()) throw InputError("curve_skeleton: the surface has no triangles");
  SurfaceMesh mesh = to_surface_mesh(surface);
  const bool simplify = max_vertices > 0 && surface.points.size() > max_vertices;
  if (simplify) collapse_to(mesh, max_vertices);
  using Skeletonization = CGAL::Mean_curvature_flow_skeletonization<SurfaceMesh>;
  Skeletonization::Skeleton skeleton;
  CGAL::extract_mean_curvature_flow_skeleton(mesh, skeleton);

  CurveSkeleton result;
  result.vertex_node.assign(surface.points.size(), kInvalidIndex);
  for (const auto v : CGAL::make_range(boost::vertices(skeleton))) {
    const Point& p = skeleton[v].point;
    const auto node = static_cast<Index>(result.nodes.size());
    result.nodes.emplace_back(p.x(), p.y(), p.z());
    if (!simplify)
      for (const auto absorbed : skeleton[v].vertices) result.vertex_node[static_cast<std::size_t>(absorbed)] = node;
  }
  if (simplify)  // the collapsed vertices are gone: each input vertex goes to its nearest node
    for (std::size_t v = 0; v < surface.points.size(); ++v) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < result.nodes.size(); ++k) {
        const double distance = (result.nodes[k] - surface.points[v]).squaredNorm();
        if (distance < best) best = distance, result.vertex_node[v] = static_cast<Index>(k);
      }
    }
  for (const auto e : CGAL::make_range(boost::edges(skeleton))) {
    const auto a = static_cast<Index>(boost::source(e, skeleton)), b = static_cast<Index>(boost::target(e, skeleton));
    result.edges.push_back({std::min(a, b), std::max(a, b)});
  }
  std::sort(result.edges.begin(), result.edges.end());
  return result;
}

std::vector<Vec3> resample_skeleton(const CurveSkeleton& skeleton, double spacing) {
  if (!(spacing > 0)) throw InputError("resample_skeleton: the spacing must be positive");
  const std::size_t n = skeleton.nodes.size();
  // Edges as sorted (low, high) pairs: edge_index() looks them up by binary search
  // (a skeleton built by hand need not list them in order; found by ASan).
  std::vector<std::array<Index, 2>> edges;
  for (const auto& [a, b] : skeleton.edges) {
    if (a >= n || b >= n) throw InputError("resample_skeleton: an edge refers to a node past the last one");
    edges.push_back({std::min(a, b), std::max(a, b)});
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<Index>> neighbours(n);
  for (const auto& [a, b] : edges) {
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  }
  std::vector<Vec3> samples;
  std::vector<std::uint8_t> kept(n, 0);
  for (std::size_t v = 0; v < n; ++v)
    if (neighbours[v].size() != 2) {
      kept[v] = 1;
      samples.push_back(skeleton.nodes[v]);
    }
  // Each branch is walked once, from its lower end's side: an edge (a, b) is taken by
  // the walk that starts at a kept node and leaves along it.
  std::vector<std::uint8_t> edge_done;
  const auto edge_index = [&](Index a, Index b) {
    const std::array<Index, 2> key{std::min(a, b), std::max(a, b)};
    return static_cast<std::size_t>(std::lower_bound(edges.begin(), edges.end(), key) - edges.begin());
  };
  edge_done.assign(edges.size(), 0);
  const auto walk = [&](Index start, Index next) {
    std::vector<Index> path{start};
    Index previous = start, current = next;
    edge_done[edge_index(start, next)] = 1;
    while (true) {
      path.push_back(current);
      if (kept[current] || current == start) break;
      const Index following = neighbours[current][0] == previous ? neighbours[current][1] : neighbours[current][0];
      edge_done[edge_index(current, following)] = 1;
      previous = current;
      current = following;
    }
    double length = 0;
    for (std::size_t i = 1; i < path.size(); ++i)
      length += (skeleton.nodes[path[i]] - skeleton.nodes[path[i - 1]]).norm();
    const auto pieces = static_cast<std::size_t>(std::max(1.0, std::round(length / spacing)));
    // Interior samples at arc lengths k * length / pieces, k = 1 .. pieces - 1.
    std::size_t segment = 1;
    double before = 0;
    for (std::size_t k = 1; k < pieces; ++k) {
      const double s = length * static_cast<double>(k) / static_cast<double>(pieces);
      while (segment + 1 < path.size() &&
             before + (skeleton.nodes[path[segment]] - skeleton.nodes[path[segment - 1]]).norm() < s) {
        before += (skeleton.nodes[path[segment]] - skeleton.nodes[path[segment - 1]]).norm();
        ++segment;
      }
      const Vec3& a = skeleton.nodes[path[segment - 1]];
      const Vec3& b = skeleton.nodes[path[segment]];
      const double edge = (b - a).norm();
      const double t = edge > 0 ? std::clamp((s - before) / edge, 0.0, 1.0) : 0.0;
      samples.push_back(a + t * (b - a));
    }
  };
  for (std::size_t v = 0; v < n; ++v)
    if (kept[v])
      for (const Index w : neighbours[v])
        if (!edge_done[edge_index(static_cast<Index>(v), w)]) walk(static_cast<Index>(v), w);
  // Closed loops without a joint: start at their first node.
  for (std::size_t v = 0; v < n; ++v)
    if (!kept[v] && neighbours[v].size() == 2 && !edge_done[edge_index(static_cast<Index>(v), neighbours[v][0])]) {
      kept[v] = 1;
      samples.push_back(skeleton.nodes[v]);
      walk(static_cast<Index>(v), neighbours[v][0]);
    }
  return samples;
}

std::vector<std::uint8_t> inside_solid(const TriMesh& surface, std::span<const Vec3> points) {
  const SurfaceMesh mesh = to_surface_mesh(surface);
  const CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel> side(mesh);
  std::vector<std::uint8_t> inside(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i)
    inside[i] = side(Point(points[i].x(), points[i].y(), points[i].z())) == CGAL::ON_BOUNDED_SIDE ? 1 : 0;
  return inside;
}

}  // namespace structmesh
