// structmesh generate key|pipe|SOLID: the built-in procedural regions of §3.4 and the built-in
// solids of solids.hpp (closed surfaces for the 3D pipelines).
#include "cli.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/regions.hpp"
#include "structmesh/render.hpp"
#include "structmesh/solids.hpp"

#include <memory>

namespace structmesh::cli {

Action add_generate_command(CLI::App& command, const GlobalOptions& global) {
  struct Settings {
    std::string shape;
    std::size_t segments = 0;
    std::vector<std::string> outputs;
  };
  auto settings = std::make_shared<Settings>();
  std::vector<std::string> shapes{"key", "pipe"};
  std::string solids;
  for (const BuiltinSolid& solid : builtin_solids()) {
    shapes.emplace_back(solid.name);
    solids += "\n  " + std::string(solid.name) + ": " + std::string(solid.description);
  }
  command
      .add_option("SHAPE", settings->shape,
                  "Regions: key (1 hole) or pipe (9 holes). Solids (closed surfaces, written as .obj .off .ply "
                  ".stl .mesh .vtu):" +
                      solids)
      ->required()
      ->check(CLI::IsMember(shapes));
  command
      .add_option("--segments", settings->segments,
                  "Boundary segments over all rings (default 2000 for the key, 4000 for the pipe)")
      ->check(CLI::Range(std::size_t{16}, std::size_t{200'000'000}));
  command
      .add_option("-o,--output", settings->outputs,
                  "Output files: .geojson .poly .svg .png for a region, a surface mesh format for a solid (repeatable)")
      ->required();
  return [&global, settings]() {
    if (settings->shape != "key" && settings->shape != "pipe") {
      if (settings->segments > 0)
        throw InputError("--segments applies to the key and the pipe; the built-in solids have a fixed resolution");
      const TriMesh surface = make_builtin_solid(settings->shape);
      for (const std::string& output : settings->outputs) {
        write_mesh(output, to_bundle(surface));
        say(global, "wrote " + output);
      }
      write_json_report(global, {{"shape", settings->shape},
                                 {"vertices", surface.points.size()},
                                 {"triangles", surface.triangles.size()},
                                 {"outputs", settings->outputs}});
      return 0;
    }
    const bool key = settings->shape == "key";
    const std::size_t segments = settings->segments > 0 ? settings->segments : (key ? 2000 : 4000);
    const std::vector<Polygon2> region{key ? make_key_region(segments) : make_pipe_region(segments)};
    const RegionReport check = check_region(region);
    if (!check.valid)
      throw Error("generated " + settings->shape + " region is invalid: " + check.problems.front().message);
    for (const std::string& output : settings->outputs) {
      const FileFormat format = format_from_path(output);
      if (format == FileFormat::Png) {
        write_file_atomic(output, region_png(region));
      } else if (format == FileFormat::Svg) {
        SvgOptions svg;
        svg.title = settings->shape + ", " + std::to_string(check.vertices) + " boundary segments, " +
                    std::to_string(check.holes) + (check.holes == 1 ? " hole" : " holes");
        write_file_atomic(output, region_svg(region, svg));
      } else {
        write_region(output, region);
      }
      say(global, "wrote " + output);
    }
    write_json_report(global, {{"shape", settings->shape},
                               {"segments", check.vertices},
                               {"holes", check.holes},
                               {"area", check.area},
                               {"outputs", settings->outputs}});
    return 0;
  };
}

}  // namespace structmesh::cli
