// Shared pieces of the command-line front end: global options, JSON reports,
// and the registration functions of the subcommands (one file each).
#pragma once

#include "structmesh/mesh.hpp"
#include "structmesh/partition2d.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace structmesh::cli {

struct GlobalOptions {
  bool quiet = false;
  bool progress = false;
  int threads = 0;  // 0: all cores
  std::string json_path;
};

/// Each subcommand adds its options to `command` and returns the action to run after parsing;
/// the action returns the process exit code (0 ok, 2 invalid input).
using Action = std::function<int()>;

Action add_check_command(CLI::App& command, const GlobalOptions& global);
Action add_quality_command(CLI::App& command, const GlobalOptions& global);
Action add_generate_command(CLI::App& command, const GlobalOptions& global);
Action add_convert_command(CLI::App& command, const GlobalOptions& global);
Action add_partition2d_command(CLI::App& command, const GlobalOptions& global);
Action add_quad2d_command(CLI::App& command, const GlobalOptions& global);
Action add_guard_command(CLI::App& command, const GlobalOptions& global);
Action add_tetmesh_command(CLI::App& command, const GlobalOptions& global);
Action add_star_command(CLI::App& command, const GlobalOptions& global);
Action add_polycube_command(CLI::App& command, const GlobalOptions& global);
Action add_hex_command(CLI::App& command, const GlobalOptions& global);

/// A region from a file (.geojson, .poly) or the built-in "key" / "pipe" with about
/// `segments` boundary segments (0: the default); `polygon_choice` ("", an index or
/// "largest") picks one polygon of a multi-polygon file.
Polygon2 load_region(const std::string& source, std::size_t segments, const std::string& polygon_choice);
/// The partition metrics as a JSON object.
nlohmann::json metrics_json(const Partition& partition);
/// What the coastline filter of quad2d (remove_narrow_water()) changed.
nlohmann::json coastline_filter_json(const NarrowWaterReport& report);
/// One line for the user, empty when nothing changed.
std::string coastline_filter_summary(const NarrowWaterReport& report);

/// Points from a JSON file: the array `key` of its top-level object, each item [x, y, z]
/// or, with a `field`, an object whose `field` is [x, y, z] (a guards.json's "guards"
/// with "position"). InputError naming the file and the item when it is unreadable,
/// malformed or not finite.
std::vector<Vec3> read_json_points(const std::string& path, const std::string& key, const std::string& field = "");

/// Adds --json, --quiet, --progress and --threads to a subcommand (they are also
/// accepted before the subcommand name).
void add_common_options(CLI::App& command, GlobalOptions& global);

/// Writes the report atomically when --json was given.
void write_json_report(const GlobalOptions& global, const nlohmann::json& report);

/// stdout line unless --quiet.
void say(const GlobalOptions& global, const std::string& text);

/// --repair of a closed surface (guard, hex): every hole closed (fill_holes()), then every
/// face turned if the signed volume is negative; says what changed and returns the report's
/// "repaired" object. InputError naming `input` when a hole cannot be closed.
nlohmann::json repair_surface(TriMesh& surface, const std::string& input, const GlobalOptions& global);

}  // namespace structmesh::cli
