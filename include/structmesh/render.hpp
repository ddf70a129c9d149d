// Pictures of regions and meshes for people to look at.
#pragma once

#include "structmesh/mesh.hpp"

#include <string>
#include <vector>

namespace structmesh {

struct SvgOptions {
  double width_px = 1200;         // picture width; height follows the aspect ratio
  std::string fill = "#9ecae1";   // region fill
  std::string stroke = "#08306b"; // boundary stroke
  std::string title;              // optional caption
};

/// An SVG of planar regions: each polygon filled (holes cut out with the even-odd
/// rule), rings outlined. Suitable for 10^5+ vertices (one path per polygon).
std::string region_svg(const std::vector<Polygon2>& polygons, const SvgOptions& options = {});

}  // namespace structmesh
