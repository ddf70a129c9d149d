// structmesh: structured (all-quad / all-hex) meshing of large geometry by divide
// and conquer. This file only parses, dispatches and maps errors to exit codes:
// 0 ok, 1 runtime failure, 2 bad usage or bad input.
#include "cli.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/progress.hpp"

#include <tbb/global_control.h>

#include <cstdio>
#include <map>
#include <memory>

namespace structmesh::cli {

void add_common_options(CLI::App& command, GlobalOptions& global) {
  command.add_option("--json", global.json_path, "Write the report as JSON to this file");
  command.add_flag("-q,--quiet", global.quiet, "Print nothing but errors");
  command.add_flag("--progress", global.progress, "Show progress on stderr even when it is not a terminal");
  command.add_option("--threads", global.threads, "Worker threads (default: all cores)")->check(CLI::NonNegativeNumber);
}

void write_json_report(const GlobalOptions& global, const nlohmann::json& report) {
  if (global.json_path.empty()) return;
  write_file_atomic(global.json_path, report.dump(2) + "\n");
}

void say(const GlobalOptions& global, const std::string& text) {
  if (!global.quiet) std::printf("%s\n", text.c_str());
}

}  // namespace structmesh::cli

int main(int argc, char** argv) {
  using namespace structmesh;
  CLI::App app{"structmesh: structured quad/hex meshing of large regions and solids"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "structmesh 0.1.0");
  cli::GlobalOptions global;
  cli::add_common_options(app, global);

  std::map<CLI::App*, cli::Action> actions;
  const auto add = [&](const char* name, const char* description,
                       cli::Action (*registrar)(CLI::App&, const cli::GlobalOptions&)) {
    CLI::App* command = app.add_subcommand(name, description);
    cli::add_common_options(*command, global);
    actions[command] = registrar(*command, global);
  };
  add("check", "Validate a surface, volume mesh or region file (exit 0 valid, 2 invalid)", cli::add_check_command);
  add("quality", "Scaled Jacobian, dihedral angles, singular vertices, D_g, D_v of a mesh", cli::add_quality_command);
  add("generate",
      "Write a built-in input: the Key (1 hole) or the Pipe (9 holes) of §3.4, or a closed solid (trefoil, cylinder, "
      "...)",
      cli::add_generate_command);
  add("convert", "Convert a mesh or region between formats (format from the extension)", cli::add_convert_command);
  add("partition2d", "Split a planar region into k balanced, compact parts with near-90° corners (§3.2)",
      cli::add_partition2d_command);
  add("quad2d", "All-quad mesh of a planar region: partition, pave the parts in parallel, merge, relax (§3.3)",
      cli::add_quad2d_command);
  add("tetmesh", "Tetrahedral mesh of a closed surface, keeping its triangles as the boundary (TetGen)",
      cli::add_tetmesh_command);
  add("guard", "Fewest interior guards that see every face of a closed surface or solid (§2.2)",
      cli::add_guard_command);
  add("star", "Split a solid into star-shaped parts grown from its guards (§2.3)", cli::add_star_command);
  add("polycube", "Build the polycube domain of a closed surface (ch. 4): deform, voxelize, optimise",
      cli::add_polycube_command);
  add("hex", "All-hex mesh of a closed surface by polycube mapping (ch. 4-5): polycube, volumetric map, grid",
      cli::add_hex_command);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }

  progress_settings().quiet = global.quiet;
  progress_settings().force = global.progress;
  std::unique_ptr<tbb::global_control> threads;
  if (global.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, global.threads);

  try {
    for (CLI::App* command : app.get_subcommands()) return actions.at(command)();
  } catch (const InputError& e) {
    std::fprintf(stderr, "structmesh: error: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "structmesh: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "structmesh: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
