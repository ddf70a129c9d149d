// The surface models a 3D benchmark runs on: every file of DATA/surfaces, or only the ones
// named on the command line, in name order.
#pragma once

#include "structmesh/tetmesh.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace structmesh::bench {

/// Exits with status 2 and a message when DATA/surfaces is not a folder (a wrong first argument).
inline void require_surfaces_folder(const std::filesystem::path& data) {
  std::error_code error;
  if (std::filesystem::is_directory(data / "surfaces", error)) return;
  std::fprintf(stderr, "bench: %s is not a folder; the first argument is the data folder (default ../shared/data)\n",
               (data / "surfaces").string().c_str());
  std::exit(2);
}

/// argv[1] is the data folder (default ../shared/data), argv[2...] optional model names.
inline std::vector<std::filesystem::path> surface_models(int argc, char** argv) {
  const std::filesystem::path data = argc > 1 ? argv[1] : "../shared/data";
  require_surfaces_folder(data);
  const std::vector<std::string> only(argv + std::min(argc, 2), argv + argc);
  std::vector<std::filesystem::path> models;
  for (const auto& entry : std::filesystem::directory_iterator(data / "surfaces"))
    if (only.empty() || std::find(only.begin(), only.end(), entry.path().filename().string()) != only.end())
      models.push_back(entry.path());
  std::sort(models.begin(), models.end());
  return models;
}

/// What `--repair` did to a surface, for a table's row: "2 holes closed", ", turned outward".
inline std::string repair_label(const SurfaceRepair& repair) {
  return std::to_string(repair.holes) + " holes closed" + (repair.turned ? ", turned outward" : "");
}

}  // namespace structmesh::bench
