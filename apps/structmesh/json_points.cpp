// read_json_points(): points stored in a JSON file by an earlier run (guards of
// structmesh guard for star, candidates for a repeatable guard run).
#include "cli.hpp"
#include "structmesh/error.hpp"

#include <fstream>

namespace structmesh::cli {

std::vector<Vec3> read_json_points(const std::string& path, const std::string& key, const std::string& field) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the file");
  nlohmann::json json;
  try {
    in >> json;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": not valid JSON (" + e.what() + ")");
  }
  if (!json.is_object() || !json.contains(key) || !json[key].is_array())
    throw InputError(path + ": expected an object with a \"" + key + "\" array (the output of structmesh guard)");
  std::vector<Vec3> points;
  for (std::size_t k = 0; k < json[key].size(); ++k) {
    const auto& item = json[key][k];
    const auto* point = field.empty() ? &item : item.is_object() && item.contains(field) ? &item[field] : nullptr;
    const std::string where = path + ": " + key + "[" + std::to_string(k) + "]";
    if (point == nullptr || !point->is_array() || point->size() != 3 || !(*point)[0].is_number() ||
        !(*point)[1].is_number() || !(*point)[2].is_number())
      throw InputError(where + (field.empty() ? " is not [x, y, z]" : " has no \"" + field + "\": [x, y, z]"));
    points.emplace_back((*point)[0].get<double>(), (*point)[1].get<double>(), (*point)[2].get<double>());
    if (!points.back().allFinite()) throw InputError(where + " has a non-finite coordinate");
  }
  return points;
}

}  // namespace structmesh::cli
