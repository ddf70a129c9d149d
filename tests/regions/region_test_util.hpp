// Shared helpers for the region tests.
#pragma once

#include "structmesh/mesh.hpp"
#include "test_data.hpp"

#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

namespace structmesh::test {

/// A polygon from rings given as point lists (ring 0 is the outer ring), stored as given.
inline Polygon2 make_polygon(std::initializer_list<std::vector<Vec2>> rings) {
  Polygon2 polygon;
  for (const auto& ring : rings) polygon.add_ring(ring);
  return polygon;
}

/// An axis-aligned rectangle ring, counter-clockwise unless `clockwise`.
inline std::vector<Vec2> rectangle(double x0, double y0, double x1, double y1, bool clockwise = false) {
  std::vector<Vec2> ring{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  if (clockwise) ring = {{x0, y0}, {x0, y1}, {x1, y1}, {x1, y0}};
  return ring;
}

}  // namespace structmesh::test
