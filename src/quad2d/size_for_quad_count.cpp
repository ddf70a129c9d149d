#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"

#include <cmath>

namespace structmesh {

double size_for_quad_count(double area, std::size_t quads) {
  if (!(area > 0) || quads == 0) throw InputError("a quad count needs a region of positive area and quads >= 1");
  // A mesh of unit-aspect quads of edge h covers the area with area / h^2 quads.
  return std::sqrt(area / static_cast<double>(quads));
}

}  // namespace structmesh
