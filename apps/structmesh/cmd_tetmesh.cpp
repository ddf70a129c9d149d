// structmesh tetmesh SURFACE -o solid.mesh: tets filling a closed surface, keeping its triangles.
#include "cli.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/tetmesh.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>

namespace structmesh::cli {

Action add_tetmesh_command(CLI::App& command, const GlobalOptions& global) {
  struct Settings {
    std::string input;
    std::vector<std::string> outputs;
    TetmeshOptions options;
    bool repair = false;
  };
  auto settings = std::make_shared<Settings>();
  command.add_option("SURFACE", settings->input, "Closed, outward-oriented triangle surface (.obj .off .ply .stl)")
      ->required();
  command.add_option("-o,--output", settings->outputs, "Outputs: .mesh, .vtu, .msh (repeatable)");
  command.add_option("--size", settings->options.size, "Target tet edge length (0: mean edge length of the surface)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command
      .add_option("--radius-edge", settings->options.radius_edge_ratio,
                  "Quality bound: circumradius / shortest edge of every tet (TetGen -q, at least 1)")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 1e6));
  command.add_flag("--repair", settings->repair, "Flip every face when the surface's signed volume is negative");

  return [&global, settings]() {
    for (const std::string& output : settings->outputs) {
      const FileFormat format = format_from_path(output);
      if (format != FileFormat::Medit && format != FileFormat::Vtu && format != FileFormat::Msh)
        throw InputError(output + ": tetmesh writes .mesh, .vtu or .msh");
    }
    const MeshBundle bundle = read_mesh(settings->input);
    if (!bundle.quads.empty() || !bundle.tets.empty() || !bundle.hexes.empty())
      throw InputError(settings->input + ": tetmesh needs a triangle surface; the file holds other elements");
    TriMesh surface{bundle.points, bundle.triangles};
    bool flipped = false;
    if (settings->repair && enclosed_volume(surface) < 0) {
      for (auto& t : surface.triangles) std::swap(t[1], t[2]);
      flipped = true;
    }
    TetmeshResult result;
    try {
      result = tetrahedralize(surface, settings->options);
    } catch (const InputError& e) {
      throw InputError(settings->input + ": " + e.what());
    }

    MeshBundle out;
    out.points = std::move(result.mesh.points);
    out.tets = std::move(result.mesh.tets);
    for (const std::string& output : settings->outputs) write_mesh(output, out);

    if (flipped) say(global, "--repair: the signed volume was negative, every face flipped");
    char line[320];
    std::snprintf(line, sizeof line,
                  "%zu tets, %zu points (%zu inside), %zu boundary faces, volume %.10g (surface %.10g), "
                  "dihedral %.2f-%.2f deg, size %.6g, %.2f s",
                  out.tets.size(), out.points.size(), result.interior_points, result.boundary_faces, result.mesh_volume,
                  result.surface_volume, result.min_dihedral_deg, result.max_dihedral_deg, result.size, result.seconds);
    say(global, line);
    for (const std::string& output : settings->outputs) say(global, "wrote " + output);
    write_json_report(global, {{"input", settings->input},
                               {"outputs", settings->outputs},
                               {"repaired", flipped},
                               {"size", result.size},
                               {"radius_edge_ratio", settings->options.radius_edge_ratio},
                               {"points", out.points.size()},
                               {"interior_points", result.interior_points},
                               {"tets", out.tets.size()},
                               {"boundary_faces", result.boundary_faces},
                               {"surface_volume", result.surface_volume},
                               {"mesh_volume", result.mesh_volume},
                               {"min_tet_volume", result.min_tet_volume},
                               {"min_dihedral_deg", result.min_dihedral_deg},
                               {"max_dihedral_deg", result.max_dihedral_deg},
                               {"seconds", result.seconds}});
    return 0;
  };
}

}  // namespace structmesh::cli
