// structmesh check FILE: is this file usable as a solid boundary, a volume mesh or a region?
#include "cli.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <cstdio>
#include <memory>

namespace structmesh::cli {

namespace {

nlohmann::json problems_json(const std::vector<Problem>& problems) {
  nlohmann::json list = nlohmann::json::array();
  for (const Problem& p : problems) {
    nlohmann::json item{{"kind", p.kind}, {"message", p.message}};
    if (p.line > 0) item["line"] = p.line;
    if (p.element >= 0) item["element"] = p.element;
    list.push_back(item);
  }
  return list;
}

void print_problems(const GlobalOptions& global, const std::string& file, const std::vector<Problem>& problems) {
  if (global.quiet) return;
  for (const Problem& p : problems)
    std::printf("  %s: %s\n", located_message(file, p.line, p.kind).c_str(), p.message.c_str());
}

void row(const GlobalOptions& global, const char* name, const std::string& value) {
  if (!global.quiet) std::printf("  %-26s %s\n", name, value.c_str());
}
std::string yes_no(bool b) { return b ? "yes" : "no"; }

int check_surface_file(const GlobalOptions& global, const MeshBundle& mesh, const CheckOptions& options) {
  const SurfaceReport r = check_surface(mesh, options);
  say(global, mesh.source_name + ": surface");
  row(global, "vertices / faces / edges",
      std::to_string(r.vertices) + " / " + std::to_string(r.faces) + " / " + std::to_string(r.edges));
  row(global, "closed", yes_no(r.closed) + " (" + std::to_string(r.boundary_edges) + " boundary edges)");
  row(global, "edge-manifold",
      yes_no(r.edge_manifold) + " (" + std::to_string(r.non_manifold_edges) + " non-manifold edges)");
  row(global, "non-manifold vertices", std::to_string(r.non_manifold_vertices));
  row(global, "consistently oriented",
      yes_no(r.oriented) + (r.oriented ? "" : " (" + std::to_string(r.flipped_faces) + " faces to flip)"));
  row(global, "signed volume",
      std::to_string(r.signed_volume) + (r.signed_volume > 0 ? " (outward)" : " (inward or open)"));
  row(global, "components", std::to_string(r.components));
  row(global, "Euler characteristic", std::to_string(r.euler_characteristic));
  row(global, "genus", r.genus >= 0 ? std::to_string(r.genus) : std::string("- (not a closed oriented manifold)"));
  row(global, "degenerate faces", std::to_string(r.degenerate_faces));
  row(global, "self-intersections", options.self_intersections ? std::to_string(r.self_intersections) : "not checked");
  row(global, "folds (adjacent overlaps)",
      options.self_intersections ? std::to_string(r.adjacent_overlaps) : "not checked");
  row(global, "valid solid boundary", yes_no(r.valid_solid_boundary));
  print_problems(global, mesh.source_name, r.problems);
  write_json_report(global, {{"file", mesh.source_name},
                             {"kind", "surface"},
                             {"vertices", r.vertices},
                             {"faces", r.faces},
                             {"edges", r.edges},
                             {"boundary_edges", r.boundary_edges},
                             {"non_manifold_edges", r.non_manifold_edges},
                             {"non_manifold_vertices", r.non_manifold_vertices},
                             {"degenerate_faces", r.degenerate_faces},
                             {"inconsistent_edges", r.inconsistent_edges},
                             {"flipped_faces", r.flipped_faces},
                             {"adjacent_overlaps", options.self_intersections ? nlohmann::json(r.adjacent_overlaps)
                                                                              : nlohmann::json(nullptr)},
                             {"self_intersections", options.self_intersections ? nlohmann::json(r.self_intersections)
                                                                               : nlohmann::json(nullptr)},
                             {"components", r.components},
                             {"isolated_vertices", r.isolated_vertices},
                             {"euler_characteristic", r.euler_characteristic},
                             {"closed", r.closed},
                             {"edge_manifold", r.edge_manifold},
                             {"oriented", r.oriented},
                             {"genus", r.genus >= 0 ? nlohmann::json(r.genus) : nlohmann::json(nullptr)},
                             {"signed_volume", r.signed_volume},
                             {"valid", r.valid_solid_boundary},
                             {"problems", problems_json(r.problems)}});
  return r.valid_solid_boundary ? 0 : 2;
}

int check_volume_file(const GlobalOptions& global, const MeshBundle& mesh, const CheckOptions& options) {
  const VolumeReport r = check_volume(mesh, options);
  say(global, mesh.source_name + ": volume mesh");
  row(global, "vertices", std::to_string(r.vertices));
  row(global, "tets / hexes", std::to_string(r.tets) + " / " + std::to_string(r.hexes));
  row(global, "boundary tris / quads", std::to_string(r.triangles) + " / " + std::to_string(r.quads));
  row(global, "inverted elements", std::to_string(r.inverted));
  row(global, "degenerate elements", std::to_string(r.degenerate));
  row(global, "non-manifold faces", std::to_string(r.non_manifold_faces));
  row(global, "unused vertices", std::to_string(r.unused_vertices));
  row(global, "valid", yes_no(r.valid));
  print_problems(global, mesh.source_name, r.problems);
  write_json_report(global, {{"file", mesh.source_name},
                             {"kind", "volume"},
                             {"vertices", r.vertices},
                             {"tets", r.tets},
                             {"hexes", r.hexes},
                             {"triangles", r.triangles},
                             {"quads", r.quads},
                             {"inverted", r.inverted},
                             {"degenerate", r.degenerate},
                             {"non_manifold_faces", r.non_manifold_faces},
                             {"unused_vertices", r.unused_vertices},
                             {"valid", r.valid},
                             {"problems", problems_json(r.problems)}});
  return r.valid ? 0 : 2;
}

int check_planar_file(const GlobalOptions& global, const MeshBundle& mesh, const CheckOptions& options) {
  const PlanarMeshReport r = check_planar_mesh(mesh, options);
  say(global, mesh.source_name + ": planar mesh");
  row(global, "vertices / edges", std::to_string(r.vertices) + " / " + std::to_string(r.edges));
  row(global, "triangles / quads", std::to_string(r.triangles) + " / " + std::to_string(r.quads));
  row(global, "area", std::to_string(r.area));
  row(global, "components / holes", std::to_string(r.components) + " / " + std::to_string(r.holes));
  row(global, "boundary edges", std::to_string(r.boundary_edges));
  row(global, "inverted elements", std::to_string(r.inverted));
  row(global, "min quad scaled Jacobian", std::to_string(r.min_quad_scaled_jacobian));
  row(global, "degenerate elements", std::to_string(r.degenerate));
  row(global, "non-manifold edges", std::to_string(r.non_manifold_edges));
  row(global, "inconsistent edges", std::to_string(r.inconsistent_edges));
  row(global, "unused vertices", std::to_string(r.unused_vertices));
  row(global, "valid", yes_no(r.valid));
  print_problems(global, mesh.source_name, r.problems);
  write_json_report(global, {{"file", mesh.source_name},
                             {"kind", "planar"},
                             {"vertices", r.vertices},
                             {"triangles", r.triangles},
                             {"quads", r.quads},
                             {"edges", r.edges},
                             {"area", r.area},
                             {"components", r.components},
                             {"holes", r.holes},
                             {"euler_characteristic", r.euler_characteristic},
                             {"boundary_edges", r.boundary_edges},
                             {"inverted", r.inverted},
                             {"min_quad_scaled_jacobian", r.min_quad_scaled_jacobian},
                             {"degenerate", r.degenerate},
                             {"non_manifold_edges", r.non_manifold_edges},
                             {"inconsistent_edges", r.inconsistent_edges},
                             {"unused_vertices", r.unused_vertices},
                             {"valid", r.valid},
                             {"problems", problems_json(r.problems)}});
  return r.valid ? 0 : 2;
}

int check_region_file(const GlobalOptions& global, const std::string& file, const CheckOptions& options) {
  const std::vector<Polygon2> polygons = read_region(file);
  const RegionReport r = check_region(polygons, options);
  const bool lonlat = !polygons.empty() && polygons.front().coordinates == Polygon2::Coordinates::LonLat;
  say(global, file + (options.shared_boundaries ? ": partition (polygons may share boundaries)" : ": region"));
  row(global, "polygons / rings / holes",
      std::to_string(r.polygons) + " / " + std::to_string(r.rings) + " / " + std::to_string(r.holes));
  row(global, "vertices", std::to_string(r.vertices));
  row(global, "coordinates", lonlat ? "lon/lat degrees" : "planar");
  row(global, "area", std::to_string(r.area) + (lonlat ? " deg^2" : ""));
  row(global, "self-intersections", std::to_string(r.self_intersections));
  row(global, "holes outside", std::to_string(r.holes_outside));
  row(global, "nested/overlapping holes", std::to_string(r.nested_holes));
  row(global, "short rings", std::to_string(r.short_rings));
  row(global, "duplicate points", std::to_string(r.duplicate_points));
  row(global, "overlapping polygons", std::to_string(r.overlapping_polygons));
  row(global, "valid", yes_no(r.valid));
  print_problems(global, file, r.problems);
  write_json_report(global, {{"file", file},
                             {"kind", options.shared_boundaries ? "partition" : "region"},
                             {"coordinates", lonlat ? "lonlat" : "planar"},
                             {"polygons", r.polygons},
                             {"rings", r.rings},
                             {"holes", r.holes},
                             {"vertices", r.vertices},
                             {"area", r.area},
                             {"self_intersections", r.self_intersections},
                             {"holes_outside", r.holes_outside},
                             {"nested_holes", r.nested_holes},
                             {"short_rings", r.short_rings},
                             {"duplicate_points", r.duplicate_points},
                             {"overlapping_polygons", r.overlapping_polygons},
                             {"valid", r.valid},
                             {"problems", problems_json(r.problems)}});
  return r.valid ? 0 : 2;
}

}  // namespace

Action add_check_command(CLI::App& command, const GlobalOptions& global) {
  struct Settings {
    std::string file;
    std::string as = "auto";
    bool skip_self_intersections = false;
    std::size_t max_problems = 20;
  };
  auto settings = std::make_shared<Settings>();
  command
      .add_option("FILE", settings->file,
                  "Surface (.obj .off .ply .stl), volume or planar mesh (.mesh .msh .vtu), or region (.geojson .poly)")
      ->required();
  command.add_option("--as", settings->as, "What to check the file as")
      ->check(CLI::IsMember({"auto", "surface", "volume", "planar", "region", "partition"}));
  command.add_flag("--no-self-intersections", settings->skip_self_intersections,
                   "Skip the (costly) self-intersection test of surfaces");
  command.add_option("--max-problems", settings->max_problems, "Problems listed per kind (counts stay complete)");
  return [&global, settings]() {
    CheckOptions options;
    options.self_intersections = !settings->skip_self_intersections;
    options.max_problems_per_kind = settings->max_problems;
    const FileFormat format = format_from_path(settings->file);
    std::string as = settings->as;
    if (as == "auto" && (format == FileFormat::GeoJson || format == FileFormat::Poly)) as = "region";
    if (as == "partition") options.shared_boundaries = true;  // parts of partition2d's output
    if (as == "region" || as == "partition") return check_region_file(global, settings->file, options);
    const MeshBundle mesh = read_mesh(settings->file);
    if (as == "auto") {
      // A mesh whose points all share one z is a 2D mesh, never a solid's boundary.
      bool flat = !mesh.points.empty();
      for (const Vec3& p : mesh.points) flat = flat && p.z() == mesh.points.front().z();
      as = !mesh.tets.empty() || !mesh.hexes.empty() ? "volume" : flat ? "planar" : "surface";
    }
    if (as == "planar") return check_planar_file(global, mesh, options);
    return as == "surface" ? check_surface_file(global, mesh, options) : check_volume_file(global, mesh, options);
  };
}

}  // namespace structmesh::cli
