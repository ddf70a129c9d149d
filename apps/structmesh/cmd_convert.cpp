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
      WriteOptions options;
      const auto add_labels = [&](const auto& labels, std::size_t count, std::size_t offset, std::vector<int>& all) {
        for (std::size_t i = 0; i < count; ++i) all[offset + i] = labels.empty() ? 0 : labels[i];
      };
      if (!mesh.triangle_labels.empty() || !mesh.quad_labels.empty() || !mesh.tet_labels.empty() ||
          !mesh.hex_labels.empty()) {
        std::vector<int> labels(mesh.cell_count(), 0);
        std::size_t offset = 0;
        add_labels(mesh.triangle_labels, mesh.triangles.size(), offset, labels);
        offset += mesh.triangles.size();
        add_labels(mesh.quad_labels, mesh.quads.size(), offset, labels);
        offset += mesh.quads.size();
        add_labels(mesh.tet_labels, mesh.tets.size(), offset, labels);
        offset += mesh.tets.size();
        add_labels(mesh.hex_labels, mesh.hexes.size(), offset, labels);
        options.cell_data.push_back({"label", {}, std::vector<std::int32_t>(labels.begin(), labels.end())});
      }
      write_mesh(settings->output, mesh, options);
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
