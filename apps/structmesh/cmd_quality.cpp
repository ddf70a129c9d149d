// structmesh quality MESH: the measures of §3.4.3 (quads) and §5.3 (hexes).
#include "cli.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/quality.hpp"

#include <cmath>
#include <cstdio>
#include <memory>

namespace structmesh::cli {

namespace {

nlohmann::json stats_json(const Statistics& s) {
  return {{"count", s.count}, {"min", s.min}, {"max", s.max}, {"mean", s.mean}, {"stddev", s.stddev}};
}

void print_row(const GlobalOptions& global, const char* name, const std::string& value) {
  if (!global.quiet) std::printf("  %-30s %s\n", name, value.c_str());
}

std::string format_stats(const Statistics& s, int digits = 4) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "avg %.*f  std %.*f  min %.*f  max %.*f", digits, s.mean, digits, s.stddev,
                digits, s.min, digits, s.max);
  return buffer;
}

void print_histogram(const GlobalOptions& global, const std::vector<std::uint64_t>& bins) {
  if (global.quiet || bins.empty()) return;
  std::uint64_t largest = 1;
  for (std::uint64_t b : bins) largest = std::max(largest, b);
  const double width = 2.0 / static_cast<double>(bins.size());
  for (std::size_t i = 0; i < bins.size(); ++i) {
    if (bins[i] == 0) continue;
    const int bar = static_cast<int>(std::ceil(40.0 * static_cast<double>(bins[i]) / static_cast<double>(largest)));
    std::printf("    [%5.2f,%5.2f) %10llu %s\n", -1.0 + i * width, -1.0 + (i + 1) * width,
                static_cast<unsigned long long>(bins[i]), std::string(bar, '#').c_str());
  }
}

// The boundary surface of whatever the bundle holds, as triangles (quads split),
// for the geometric deviation D_g.
TriMesh boundary_surface(const MeshBundle& mesh) {
  TriMesh surface;
  surface.points = mesh.points;
  const auto add_quad = [&](const std::array<Index, 4>& q) {
    surface.triangles.push_back({q[0], q[1], q[2]});
    surface.triangles.push_back({q[0], q[2], q[3]});
  };
  if (!mesh.hexes.empty()) {
    const FaceAdjacency<4> faces = build_faces(HexMesh{mesh.points, mesh.hexes});
    for (std::size_t f = 0; f < faces.faces.size(); ++f)
      if (faces.face_cells[f][1] == kInvalidIndex) add_quad(faces.faces[f]);
  } else if (!mesh.tets.empty()) {
    const FaceAdjacency<3> faces = build_faces(TetMesh{mesh.points, mesh.tets});
    for (std::size_t f = 0; f < faces.faces.size(); ++f)
      if (faces.face_cells[f][1] == kInvalidIndex) surface.triangles.push_back(faces.faces[f]);
  } else {
    surface.triangles = mesh.triangles;
    for (const auto& q : mesh.quads) add_quad(q);
  }
  return surface;
}

}  // namespace

Action add_quality_command(CLI::App& command, const GlobalOptions& global) {
  struct Settings {
    std::string file, output, compare, image;
    double sampling = 2e-3;
  };
  auto settings = std::make_shared<Settings>();
  command.add_option("MESH", settings->file, "Quad or hex mesh (.vtu .msh .mesh; quads also .obj .off .ply)")
      ->required();
  command.add_option("-o,--output", settings->output,
                     "Write the measured elements with per-cell scaled_jacobian (hexes also corner_scaled_jacobian)");
  command.add_option(
      "--compare", settings->compare,
      "Reference surface S: report the Hausdorff distance D_g = d_H / diag(S) of the mesh boundary to S");
  command
      .add_option("--sampling", settings->sampling,
                  "Hausdorff sample spacing as a fraction of the reference's bounding-box diagonal "
                  "(error bound about 1.1x this)")
      ->check(CLI::Range(1e-5, 0.1));
  command.add_option("--image", settings->image,
                     "Image of a tet MESH (same tets, moved points): report the volume distortion D_v of §5.3");
  return [&global, settings]() {
    const MeshBundle mesh = read_mesh(settings->file);
    nlohmann::json report{{"file", settings->file}};
    MeshBundle measured;
    measured.points = mesh.points;
    WriteOptions cell_output;
    say(global, settings->file + ":");
    if (!mesh.hexes.empty()) {
      const HexMesh hexes{mesh.points, mesh.hexes};
      const HexQuality q = hex_quality(hexes);
      print_row(global, "hexahedra", std::to_string(mesh.hexes.size()));
      print_row(global, "scaled Jacobian (Verdict)", format_stats(q.scaled_jacobian_stats));
      print_row(global, "scaled Jacobian (8 corners)", format_stats(q.corner_scaled_jacobian_stats));
      print_row(global, "dihedral angle (degrees)", format_stats(q.dihedral_degrees, 2));
      print_row(global, "inverted (SJ <= 0)", std::to_string(q.inverted));
      print_row(global, "invalid (zero-length edge)", std::to_string(q.invalid));
      print_row(global, "singular vertices N_h",
                std::to_string(q.singular_vertices) + " (" + std::to_string(q.singular_interior) + " interior, " +
                    std::to_string(q.singular_boundary) + " boundary)");
      print_histogram(global, q.scaled_jacobian_histogram);
      report.update({{"kind", "hex"},
                     {"elements", mesh.hexes.size()},
                     {"scaled_jacobian", stats_json(q.scaled_jacobian_stats)},
                     {"corner_scaled_jacobian", stats_json(q.corner_scaled_jacobian_stats)},
                     {"scaled_jacobian_histogram", q.scaled_jacobian_histogram},
                     {"dihedral_degrees", stats_json(q.dihedral_degrees)},
                     {"inverted", q.inverted},
                     {"invalid", q.invalid},
                     {"singular_vertices", q.singular_vertices},
                     {"singular_interior", q.singular_interior},
                     {"singular_boundary", q.singular_boundary}});
      measured.hexes = mesh.hexes;
      measured.hex_labels = mesh.hex_labels;
      cell_output.cell_data.push_back({"scaled_jacobian", q.scaled_jacobian, {}});
      cell_output.cell_data.push_back({"corner_scaled_jacobian", q.corner_scaled_jacobian, {}});
    } else if (!mesh.quads.empty()) {
      const QuadMesh quads{mesh.points, mesh.quads};
      const QuadQuality q = quad_quality(quads);
      print_row(global, "quadrilaterals", std::to_string(mesh.quads.size()));
      print_row(global, "scaled Jacobian (Verdict)", format_stats(q.scaled_jacobian_stats));
      print_row(global, "inverted (SJ <= 0)", std::to_string(q.inverted));
      print_row(global, "singular vertices",
                std::to_string(q.singular_vertices) + " of " + std::to_string(q.interior_vertices) + " interior");
      print_row(global, "reference normal", q.planar ? "+z (planar mesh)" : "per quad (Verdict)");
      print_histogram(global, q.scaled_jacobian_histogram);
      report.update({{"kind", "quad"},
                     {"elements", mesh.quads.size()},
                     {"scaled_jacobian", stats_json(q.scaled_jacobian_stats)},
                     {"scaled_jacobian_histogram", q.scaled_jacobian_histogram},
                     {"inverted", q.inverted},
                     {"invalid", 0},
                     {"singular_vertices", q.singular_vertices},
                     {"interior_vertices", q.interior_vertices},
                     {"boundary_vertices", q.boundary_vertices},
                     {"planar", q.planar}});
      if (!mesh.quad_labels.empty()) {
        const std::vector<std::size_t> per_part = singular_vertices_per_part(quads, mesh.quad_labels);
        report["singular_vertices_per_part"] = per_part;
        print_row(global, "parts", std::to_string(per_part.size()));
      }
      measured.quads = mesh.quads;
      measured.quad_labels = mesh.quad_labels;
      cell_output.cell_data.push_back({"scaled_jacobian", q.scaled_jacobian, {}});
    } else if (!mesh.tets.empty()) {
      std::vector<double> volumes(mesh.tets.size());
      std::size_t inverted = 0;
      for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
        const auto& c = mesh.tets[t];
        volumes[t] = tet_signed_volume(mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]], mesh.points[c[3]]);
        inverted += volumes[t] <= 0 ? 1 : 0;
      }
      print_row(global, "tetrahedra", std::to_string(mesh.tets.size()));
      print_row(global, "volume", format_stats(statistics(volumes), 6));
      print_row(global, "inverted (volume <= 0)", std::to_string(inverted));
      report.update({{"kind", "tet"},
                     {"elements", mesh.tets.size()},
                     {"volume", stats_json(statistics(volumes))},
                     {"inverted", inverted}});
      measured.tets = mesh.tets;
      cell_output.cell_data.push_back({"volume", volumes, {}});
    } else if (settings->compare.empty()) {
      throw InputError(located_message(settings->file, 0,
                                       "holds only triangles: quality measures quads, hexes or tets; "
                                       "use --compare SURFACE for the geometric deviation"));
    } else {
      report["kind"] = "surface";
    }

    if (!settings->compare.empty()) {
      const MeshBundle reference = read_mesh(settings->compare);
      const HausdorffResult h =
          hausdorff_distance(boundary_surface(reference), boundary_surface(mesh), settings->sampling);
      print_row(global, "Hausdorff distance d_H",
                std::to_string(h.distance) + " (+" + std::to_string(h.tolerance) + " sampling bound, " +
                    std::to_string(h.samples) + " samples, " + std::to_string(h.queried_samples) + " looked up)");
      print_row(global, "D_g = d_H / diag(S)", std::to_string(h.relative));
      report["hausdorff_distance"] = h.distance;
      report["hausdorff_tolerance"] = h.tolerance;
      report["hausdorff_samples"] = h.samples;
      report["hausdorff_samples_looked_up"] = h.queried_samples;
      report["geometric_deviation"] = h.relative;
    }
    if (!settings->image.empty()) {
      const MeshBundle image = read_mesh(settings->image);
      const double dv = volume_distortion(to_tet_mesh(mesh), to_tet_mesh(image));
      print_row(global, "volume distortion D_v", std::to_string(dv));
      report["volume_distortion"] = dv;
    }
    if (!settings->output.empty()) {
      if (measured.cell_count() == 0)
        throw InputError(located_message(settings->output, 0, "nothing measured per element to write"));
      write_mesh(settings->output, measured, cell_output);
    }
    write_json_report(global, report);
    return 0;
  };
}

}  // namespace structmesh::cli
