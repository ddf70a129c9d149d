// The test data folder (../shared/data: surfaces/, regions/): STRUCTMESH_DATA when set and
// not empty, else the folder the build was configured with (STRUCTMESH_DATA_DEFAULT).
#pragma once

#include <cstdlib>
#include <filesystem>

namespace structmesh::test {

inline std::filesystem::path data_dir() {
  const char* env = std::getenv("STRUCTMESH_DATA");
  return std::filesystem::path(env != nullptr && *env != '\0' ? env : STRUCTMESH_DATA_DEFAULT);
}

}  // namespace structmesh::test
