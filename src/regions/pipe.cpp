// The Pipe of §3.4 (Fig. 3.6e-h, 3.7): shown but not published, so this is our
// own pipe-bend plate in about [0,10]x[0,5]: a U-shaped (hairpin) pipe band of
// width 1.5 with a 180-degree round bend on the right and a square flange on each
// leg's left end, pierced by exactly 9 holes: a bolt hole in each flange, two
// slots along each leg and three round holes spaced around the bend. Every hole
// keeps at least 0.15 from the outline and 0.5 from the other holes.
#include "regions/outline.hpp"
#include "structmesh/regions.hpp"

#include <cmath>
#include <numbers>

namespace structmesh {

namespace {

constexpr double kPi = std::numbers::pi;

detail::OutlineRing circle_hole(const Vec2& center, double radius) {
  // Clockwise, as holes are.
  return {{detail::arc_from(center + Vec2(radius, 0), center, radius, 0, -2 * kPi)}, true};
}

// A slot (stadium) along x: straight sides of length 2*half_length, round ends.
detail::OutlineRing slot_hole(const Vec2& center, double half_length, double radius) {
  using detail::arc_from;
  using detail::line_from;
  const Vec2 left = center - Vec2(half_length, 0), right = center + Vec2(half_length, 0);
  // Clockwise: upper side to the right, right end down, lower side back, left end up.
  return {{line_from(left + Vec2(0, radius)), arc_from(right + Vec2(0, radius), right, radius, kPi / 2, -kPi),
           line_from(right - Vec2(0, radius)), arc_from(left - Vec2(0, radius), left, radius, -kPi / 2, -kPi)},
          true};
}

}  // namespace

Polygon2 make_pipe_region(std::size_t boundary_segments) {
  using detail::arc_from;
  using detail::line_from;

  const Vec2 bend_center(7.5, 2.5);
  const double outer_radius = 2.1, inner_radius = 0.6;  // legs 1.5 wide: y in [0.4,1.9] and [3.1,4.6]
  const double flange_left = 0.2, flange_right = 0.9;

  // Counter-clockwise from the lower flange's lower left corner.
  detail::OutlineRing outer{{
      line_from({flange_left, 0.1}),
      line_from({flange_right, 0.1}),
      line_from({flange_right, 0.4}),
      arc_from({7.5, 0.4}, bend_center, outer_radius, -kPi / 2, kPi),  // outside of the bend
      line_from({7.5, 4.6}),
      line_from({flange_right, 4.6}),
      line_from({flange_right, 4.9}),
      line_from({flange_left, 4.9}),
      line_from({flange_left, 2.8}),
      line_from({flange_right, 2.8}),
      line_from({flange_right, 3.1}),
      arc_from({7.5, 3.1}, bend_center, inner_radius, kPi / 2, -kPi),  // inside of the bend
      line_from({7.5, 1.9}),
      line_from({flange_right, 1.9}),
      line_from({flange_right, 2.2}),
      line_from({flange_left, 2.2}),
  }};

  std::vector<detail::OutlineRing> rings{outer};
  for (const double y : {1.15, 3.85}) {
    rings.push_back(circle_hole({0.55, y}, 0.2));  // flange bolt hole
    rings.push_back(slot_hole({2.9, y}, 0.4, 0.35));
    rings.push_back(slot_hole({5.3, y}, 0.4, 0.35));
  }
  const double middle_radius = 0.5 * (outer_radius + inner_radius);
  for (const double degrees : {-60.0, 0.0, 60.0}) {
    const double angle = degrees * kPi / 180;
    rings.push_back(circle_hole(bend_center + middle_radius * Vec2(std::cos(angle), std::sin(angle)), 0.35));
  }
  return detail::sample_outline(rings, boundary_segments);
}

}  // namespace structmesh
