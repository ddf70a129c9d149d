// tetrahedralize(): TetGen 1.5 as a library on a closed triangle surface.
//
// Switches (TetGen 1.5 user's manual, §4.2):
//   p  tetrahedralize the piecewise linear complex given by the triangles;
//   Y  keep the input surface mesh: no Steiner point on the boundary, so the boundary
//      faces of the tets are the input triangles (interior Steiner points are allowed);
//   q  Delaunay refinement to a radius-edge ratio bound (the manual warns that bounds
//      below 1 may keep TetGen from terminating, hence the lower limit of 1);
//   a  maximum tet volume, from the target edge length (a regular tet of edge h has
//      volume h^3 / (6 sqrt 2));
//   J  keep every input point in the output (TetGen otherwise jettisons unused points,
//      which would renumber the ones after them);
//   z  number from zero;  Q  print nothing.
// The numeric bounds are set on tetgenbehavior after parsing rather than printed into
// the switch string, so they reach TetGen exactly.
//
// Nothing of TetGen's output is taken on trust: the surface points must come back first
// and bit-identical, every tet must have positive volume in VTK order, and the boundary
// faces must be the input triangles. A violation is a structmesh::Error (exit 1).
#include "structmesh/tetmesh.hpp"

#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <tetgen.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace structmesh {
namespace {

std::string count_of(std::size_t n, const char* singular, const char* plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

// The first problem of a kind as "(first: ...)", or "" when none was logged.
std::string first_problem(const SurfaceReport& report, const char* kind) {
  for (const Problem& p : report.problems)
    if (p.kind == kind) return " (first: " + p.message + ")";
  return "";
}

// Every reason the surface cannot bound a solid, in one message a user can act on.
void check_solid_boundary(const TriMesh& surface) {
  const SurfaceReport r = check_surface(to_bundle(surface));
  // Bad indices or coordinates stop check_surface() before the other counts.
  for (const char* kind : {"index-out-of-range", "non-finite-point"})
    for (const Problem& p : r.problems)
      if (p.kind == kind) throw InputError("the surface is not usable: " + p.message);
  if (r.valid_solid_boundary && r.isolated_vertices == 0) return;

  std::vector<std::string> reasons;
  if (r.boundary_edges > 0)
    reasons.push_back("it is open: " + count_of(r.boundary_edges, "boundary edge", "boundary edges") +
                      first_problem(r, "open-edge"));
  if (r.non_manifold_edges > 0)
    reasons.push_back(count_of(r.non_manifold_edges, "non-manifold edge", "non-manifold edges") +
                      first_problem(r, "non-manifold-edge"));
  if (r.non_manifold_vertices > 0)
    reasons.push_back(count_of(r.non_manifold_vertices, "non-manifold vertex", "non-manifold vertices") +
                      first_problem(r, "non-manifold-vertex"));
  if (r.degenerate_faces > 0)
    reasons.push_back(count_of(r.degenerate_faces, "degenerate face", "degenerate faces") +
                      first_problem(r, "degenerate-face"));
  if (r.self_intersections > 0)
    reasons.push_back("it is self-intersecting: " +
                      count_of(r.self_intersections, "pair of faces intersects", "pairs of faces intersect") +
                      first_problem(r, "self-intersection"));
  if (r.adjacent_overlaps > 0)
    reasons.push_back(
        "it folds onto itself: " +
        count_of(r.adjacent_overlaps, "pair of neighbouring faces overlaps", "pairs of neighbouring faces overlap") +
        first_problem(r, "adjacent-overlap"));
  if (!r.oriented)
    reasons.push_back("its orientation is inconsistent: " + count_of(r.inconsistent_edges, "edge is", "edges are") +
                      " traversed twice in the same direction, " +
                      count_of(r.flipped_faces, "face needs", "faces need") + " flipping" +
                      first_problem(r, "inconsistent-edge"));
  if (r.closed && r.oriented && r.signed_volume <= 0)
    reasons.push_back("its normals point inward (signed volume " + std::to_string(r.signed_volume) +
                      "); flip every face (structmesh tetmesh --repair)");
  if (r.isolated_vertices > 0)
    reasons.push_back(count_of(r.isolated_vertices, "point is", "points are") + " used by no triangle" +
                      first_problem(r, "isolated-vertex") +
                      "; remove them (the tet mesh keeps the surface's point numbering)");
  if (reasons.empty()) reasons.push_back("check_surface() rejects it");  // a new kind of problem
  std::string message = "the surface does not bound a solid: ";
  for (std::size_t i = 0; i < reasons.size(); ++i) message += (i ? "; " : "") + reasons[i];
  throw InputError(message);
}

// Without the full check, TetGen must at least not read out of bounds or take NaNs.
void check_indices_and_coordinates(const TriMesh& surface) {
  for (std::size_t p = 0; p < surface.points.size(); ++p)
    if (!surface.points[p].allFinite())
      throw InputError("the surface is not usable: point " + std::to_string(p) + " has a non-finite coordinate");
  for (std::size_t t = 0; t < surface.triangles.size(); ++t)
    for (Index v : surface.triangles[t])
      if (v >= surface.points.size())
        throw InputError("the surface is not usable: triangle " + std::to_string(t) + " refers to point " +
                         std::to_string(v) + " of " + std::to_string(surface.points.size()));
}

// What the codes of terminatetetgen() mean (tetgen.h, the non-library branch prints them).
[[noreturn]] void throw_tetgen_failure(int code) {
  const std::string prefix = "TetGen failed (code " + std::to_string(code) + "): ";
  switch (code) {
    case 1:
      throw Error(prefix + "out of memory");
    case 2:
      throw Error(prefix + "internal error");
    case 3:
      throw InputError(prefix + "it found a self-intersection of the surface");
    case 4:
      throw Error(prefix + "the surface has a feature too small for TetGen's tolerance");
    case 5:
      throw Error(prefix + "two surface triangles are too close to each other for TetGen's tolerance");
    case 10:
      throw InputError(prefix + "it rejected the input surface");
    default:
      throw Error(prefix + "unknown error");
  }
}

std::array<Index, 3> sorted(std::array<Index, 3> f) {
  std::sort(f.begin(), f.end());
  return f;
}

// Interior dihedral angles (radians) of a positive tet at its six edges.
// The angle at the edge shared by the faces opposite vertices i and j is pi minus the
// angle between those faces' outward normals.
void dihedral_range(const std::array<Vec3, 4>& p, double& lo, double& hi) {
  std::array<Vec3, 4> normal;
  for (int i = 0; i < 4; ++i) {
    const auto& f = kTetFaces[i];  // face opposite vertex i, outward
    normal[i] = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).normalized();
  }
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double angle = std::acos(std::clamp(-normal[i].dot(normal[j]), -1.0, 1.0));
      lo = std::min(lo, angle);
      hi = std::max(hi, angle);
    }
}

}  // namespace

double mean_edge_length(const TriMesh& surface) {
  double sum = 0;
  for (const auto& t : surface.triangles)
    for (int k = 0; k < 3; ++k) sum += (surface.points[t[(k + 1) % 3]] - surface.points[t[k]]).norm();
  return surface.triangles.empty() ? 0 : sum / (3.0 * static_cast<double>(surface.triangles.size()));
}

TetmeshResult tetrahedralize(const TriMesh& surface, const TetmeshOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (!(options.size >= 0) || !std::isfinite(options.size))
    throw InputError("tetmesh: the size must be a finite number >= 0 (0: the mean edge length of the surface)");
  if (!(options.radius_edge_ratio >= 1.0) || !std::isfinite(options.radius_edge_ratio))
    throw InputError("tetmesh: the radius-edge ratio bound must be at least 1 (TetGen may not terminate below)");
  if (surface.triangles.empty() || surface.points.empty())
    throw InputError("the surface is empty: it has no triangles");
  if (surface.points.size() > static_cast<std::size_t>(INT_MAX) ||
      surface.triangles.size() > static_cast<std::size_t>(INT_MAX))
    throw InputError("the surface has more points or triangles than TetGen's int indices can number");
  if (options.check_input)
    check_solid_boundary(surface);
  else
    check_indices_and_coordinates(surface);

  TetmeshResult result;
  result.surface_volume = enclosed_volume(surface);
  result.size = options.size > 0 ? options.size : mean_edge_length(surface);
  const double max_volume = std::pow(result.size, 3) / (6.0 * std::numbers::sqrt2);
  if (!(max_volume > 0) || !std::isfinite(max_volume))
    throw InputError("tetmesh: the target edge length " + std::to_string(result.size) +
                     " gives no usable tet volume bound");

  const std::size_t n = surface.points.size();
  tetgenio in, out;  // their destructors free the arrays with delete[]
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(n);
  in.pointlist = new REAL[3 * n];
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < 3; ++k) in.pointlist[3 * p + k] = surface.points[p][k];
  in.numberoffacets = static_cast<int>(surface.triangles.size());
  in.facetlist = new tetgenio::facet[surface.triangles.size()];
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    tetgenio::facet& facet = in.facetlist[t];
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    facet.numberofholes = 0;
    facet.holelist = nullptr;
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) facet.polygonlist[0].vertexlist[k] = static_cast<int>(surface.triangles[t][k]);
  }

  tetgenbehavior behavior;
  char switches[] = "pYqa1JzQ";
  if (!behavior.parse_commandline(switches)) throw Error("TetGen rejected the switches " + std::string(switches));
  behavior.minratio = options.radius_edge_ratio;
  behavior.maxvolume = max_volume;
  try {
    tetrahedralize(&behavior, &in, &out);
  } catch (int code) {
    // With TETLIBRARY, terminatetetgen() throws the exit code instead of calling exit().
    // Debian's TetGen 1.5.0 frees its mesh in terminatetetgen() and again in the
    // destructor of the tetgenmesh that tetrahedralize() keeps on its stack, so there
    // the error path crashes before the exception gets here (seen with two overlapping
    // cubes and check_input off). The input check above is what keeps TetGen off that path.
    throw_tetgen_failure(code);
  }

  // --- the contract, checked ---
  if (out.numberofcorners != 4 || out.numberofpoints < in.numberofpoints || out.pointlist == nullptr ||
      out.tetrahedronlist == nullptr || out.numberoftetrahedra <= 0)
    throw Error("TetGen returned no usable tetrahedral mesh (" + std::to_string(out.numberoftetrahedra) + " tets)");
  if (std::memcmp(out.pointlist, in.pointlist, 3 * n * sizeof(REAL)) != 0)
    throw Error("TetGen moved or renumbered surface points (the output does not start with the input points)");
  TetMesh& mesh = result.mesh;
  mesh.points.resize(static_cast<std::size_t>(out.numberofpoints));
  for (std::size_t p = 0; p < mesh.points.size(); ++p)
    mesh.points[p] = Vec3(out.pointlist[3 * p], out.pointlist[3 * p + 1], out.pointlist[3 * p + 2]);
  result.interior_points = mesh.points.size() - n;
  mesh.tets.resize(static_cast<std::size_t>(out.numberoftetrahedra));
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      const int v = out.tetrahedronlist[4 * t + k];
      if (v < 0 || v >= out.numberofpoints)
        throw Error("TetGen returned tet " + std::to_string(t) + " with point index " + std::to_string(v));
      mesh.tets[t][k] = static_cast<Index>(v);
    }

  // TetGen's corner order already gives (p1-p0).((p2-p0)x(p3-p0)) > 0, the VTK order
  // (0-1-2 counter-clockwise seen from 3); a tet that is not positive is reported.
  double min_dihedral = std::numbers::pi, max_dihedral = 0;
  result.min_tet_volume = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& c = mesh.tets[t];
    const std::array<Vec3, 4> p{mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]], mesh.points[c[3]]};
    const double volume = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])) / 6.0;
    if (!(volume > 0))
      throw Error("TetGen returned tet " + std::to_string(t) + " with non-positive volume " + std::to_string(volume));
    result.mesh_volume += volume;
    result.min_tet_volume = std::min(result.min_tet_volume, volume);
    dihedral_range(p, min_dihedral, max_dihedral);
  }
  result.min_dihedral_deg = min_dihedral * 180.0 / std::numbers::pi;
  result.max_dihedral_deg = max_dihedral * 180.0 / std::numbers::pi;

  // Boundary faces (one tet) against the input triangles, as vertex sets.
  const FaceAdjacency<3> faces = build_faces(mesh);
  if (!faces.extra_cells.empty()) throw Error("TetGen returned a face shared by more than two tets");
  std::vector<std::array<Index, 3>> boundary, input;
  for (std::size_t f = 0; f < faces.faces.size(); ++f)
    if (faces.face_cells[f][1] == kInvalidIndex) boundary.push_back(sorted(faces.faces[f]));
  input.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles) input.push_back(sorted(t));
  std::sort(boundary.begin(), boundary.end());
  std::sort(input.begin(), input.end());
  result.boundary_faces = boundary.size();
  if (boundary != input) {
    // TetGen removes only the tets it reaches from outside without crossing the surface,
    // so the inside of an inner shell (a cavity) gets filled and its triangles end up
    // interior. Anything else is TetGen breaking -Y.
    if (boundary.size() < input.size() && std::includes(input.begin(), input.end(), boundary.begin(), boundary.end()))
      throw InputError("the surface encloses a cavity (" + std::to_string(input.size() - boundary.size()) +
                       " triangles bound a void inside the solid, e.g. a shell nested in another); tetmesh "
                       "meshes solids without cavities");
    throw Error("the boundary of TetGen's mesh (" + std::to_string(boundary.size()) +
                " faces) is not the input surface (" + std::to_string(input.size()) + " triangles)");
  }

  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace structmesh
