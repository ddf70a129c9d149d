// Planar inputs of the quad meshing benchmark that are not built-in regions: the
// issue's Gmsh anchor cases. Deterministic (no random numbers).
#pragma once

#include "structmesh/mesh.hpp"

#include <cmath>
#include <numbers>
#include <vector>

namespace structmesh::bench {

inline std::vector<Vec2> circle(const Vec2& centre, double radius, int n, bool clockwise) {
  std::vector<Vec2> ring;
  for (int i = 0; i < n; ++i) {
    const double t = (clockwise ? -2 : 2) * std::numbers::pi * i / n;
    ring.emplace_back(centre + radius * Vec2(std::cos(t), std::sin(t)));
  }
  return ring;
}

/// The unit square with a round hole of radius 0.25 (a 256-gon) in the middle.
inline Polygon2 square_with_hole() {
  Polygon2 region;
  const std::vector<Vec2> outer{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  region.add_ring(outer);
  region.add_ring(circle({0.5, 0.5}, 0.25, 256, true));
  return region;
}

/// A disk of radius about 1 with a noisy coast (a fixed sum of sines) and a noisy
/// island off centre.
inline Polygon2 noisy_disk_with_island() {
  const auto noisy = [](const Vec2& centre, double radius, int n, bool clockwise, double phase) {
    std::vector<Vec2> ring;
    for (int i = 0; i < n; ++i) {
      const double t = (clockwise ? -2 : 2) * std::numbers::pi * i / n;
      const double r = radius * (1 + 0.04 * std::sin(7 * t + phase) + 0.025 * std::sin(13 * t + 1.1 + phase) +
                                 0.015 * std::sin(29 * t + 2.0) + 0.008 * std::sin(61 * t + 0.7));
      ring.emplace_back(centre + r * Vec2(std::cos(t), std::sin(t)));
    }
    return ring;
  };
  Polygon2 region;
  region.add_ring(noisy({0, 0}, 1.0, 720, false, 0.0));
  region.add_ring(noisy({0.35, 0.1}, 0.22, 180, true, 0.9));
  return region;
}

inline double perimeter(const Polygon2& region) {
  double length = 0;
  for (std::size_t r = 0; r < region.ring_count(); ++r) {
    const auto ring = region.ring(r);
    for (std::size_t i = 0; i < ring.size(); ++i) length += (ring[(i + 1) % ring.size()] - ring[i]).norm();
  }
  return length;
}

}  // namespace structmesh::bench
