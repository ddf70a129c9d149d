// structmesh convert IN -o OUT: between any two mesh formats, or region formats.
#include "cli.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/render.hpp"

#include <memory>

namespace structmesh::cli {

Action add_convert_command(CLI::App& command, const GlobalOptions& global) {
  struct Settings {
    std::string input, output;
  };
  auto settings = std::make_shared<Settings>();
  command.add_option("INPUT", settings->input, "Mesh (.obj .off .ply .stl .mesh .msh .vtu) or region (.geojson .poly)")
      ->required();
  command.add_option("-o,--output", settings->output, "Output file; the format follows the extension")->required();
  return [&global, settings]() {
    const FileFormat in = format_from_path(settings->input);
    const FileFormat out = format_from_path(settings->output);
    nlohmann::json report{{"input", settings->input}, {"output", settings->output}};
    if (in == FileFormat::GeoJson || in == FileFormat::Poly) {
      const std::vector<Polygon2> region = read_region(settings->input);
      if (out == FileFormat::Png) {
        write_file_atomic(settings->output, region_png(region));
      } else if (out == FileFormat::Svg) {
        write_file_atomic(settings->output, region_svg(region));
      } else {
        write_region(settings->output, region);
      }
      report["polygons"] = region.size();
    } else {
      const MeshBundle mesh = read_mesh(settings->input);
      write_mesh(settings->output, mesh);  // element labels travel with the bundle
      report.update({{"points", mesh.points.size()},
                     {"triangles", mesh.triangles.size()},
                     {"quads", mesh.quads.size()},
                     {"tets", mesh.tets.size()},
                     {"hexes", mesh.hexes.size()}});
    }
    say(global, "wrote " + settings->output);
    write_json_report(global, report);
    return 0;
  };
}

}  // namespace structmesh::cli
