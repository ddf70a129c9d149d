// fill_holes(): closes the holes of a manifold, oriented surface so that the guarding
// of §2.2 (which needs a closed surface) can run on scanned models such as the TOSCA
// ones (the dissertation's Table 2.1), whose eyes or mouths are open.
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <string>
#include <vector>

namespace structmesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

}  // namespace

HoleFilling fill_holes(const TriMesh& surface) {
  SurfaceMesh mesh;
  for (const Vec3& p : surface.points) mesh.add_vertex(Point(p.x(), p.y(), p.z()));
  for (std::size_t f = 0; f < surface.triangles.size(); ++f) {
    const auto& t = surface.triangles[f];
    for (const Index v : t)
      if (v >= surface.points.size())
        throw InputError("fill_holes: triangle " + std::to_string(f) + " refers to a missing point");
    if (mesh.add_face(SurfaceMesh::Vertex_index(t[0]), SurfaceMesh::Vertex_index(t[1]),
                      SurfaceMesh::Vertex_index(t[2])) == SurfaceMesh::null_face())
      throw InputError("fill_holes: triangle " + std::to_string(f) +
                       " makes the surface non-manifold or inconsistently oriented; holes can only be filled in "
                       "a manifold, oriented surface");
  }
  // One border halfedge per hole, collected before any face is added.
  std::vector<SurfaceMesh::Halfedge_index> holes;
  std::vector<bool> seen(mesh.number_of_halfedges(), false);
  for (const auto h : mesh.halfedges()) {
    if (!mesh.is_border(h) || seen[h]) continue;
    holes.push_back(h);
    for (const auto g : CGAL::halfedges_around_face(h, mesh)) seen[g] = true;
  }
  HoleFilling result;
  for (const auto h : holes) {
    std::vector<SurfaceMesh::Face_index> added;
    // The minimum-area (Liepa) triangulation of the hole's boundary polygon, no new
    // vertices: the hole is closed, not faired.
    CGAL::Polygon_mesh_processing::triangulate_hole(mesh, h, std::back_inserter(added));
    if (added.empty()) {
      // Fallback: a fan around a new vertex at the centroid of the hole's boundary.
      Vec3 centre = Vec3::Zero();
      std::vector<SurfaceMesh::Vertex_index> ring;
      for (const auto g : CGAL::halfedges_around_face(h, mesh)) {
        ring.push_back(mesh.target(g));
        const Point& p = mesh.point(mesh.target(g));
        centre += Vec3(p.x(), p.y(), p.z());
      }
      centre /= static_cast<double>(ring.size());
      const auto apex = mesh.add_vertex(Point(centre.x(), centre.y(), centre.z()));
      ++result.added_vertices;
      // The border halfedges run along the hole the other way round from its faces.
      for (std::size_t i = 0; i < ring.size(); ++i)
        if (mesh.add_face(ring[i], ring[(i + 1) % ring.size()], apex) == SurfaceMesh::null_face())
          throw Error("fill_holes: a hole of " + std::to_string(ring.size()) + " edges could not be closed");
      result.added_faces += ring.size();
    } else {
      result.added_faces += added.size();
    }
    ++result.holes;
  }
  // Vertices and faces keep their indices (nothing was removed), new ones come last.
  result.surface = surface;
  for (std::size_t v = surface.points.size(); v < mesh.number_of_vertices(); ++v) {
    const Point& p = mesh.point(SurfaceMesh::Vertex_index(static_cast<SurfaceMesh::size_type>(v)));
    result.surface.points.emplace_back(p.x(), p.y(), p.z());
  }
  for (std::size_t f = surface.triangles.size(); f < mesh.number_of_faces(); ++f) {
    std::array<Index, 3> triangle{};
    int k = 0;
    const auto face = SurfaceMesh::Face_index(static_cast<SurfaceMesh::size_type>(f));
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(face), mesh)) triangle[k++] = static_cast<Index>(v);
    result.surface.triangles.push_back(triangle);
  }
  return result;
}

}  // namespace structmesh
