// The Key of §3.4 (Fig. 3.3, 3.6a-d): the dissertation shows it but publishes
// no coordinates, so this is our own key silhouette in about [0,10]x[0,5]:
// a round bow with a round hole, a straight shaft, a bit with four teeth and
// three notches of different depths along the lower edge, and a pointed tip.
#include "regions/outline.hpp"
#include "structmesh/regions.hpp"

#include <cmath>
#include <numbers>

namespace structmesh {

Polygon2 make_key_region(std::size_t boundary_segments) {
  using detail::arc_from;
  using detail::line_from;
  constexpr double kPi = std::numbers::pi;

  const Vec2 bow_center(2.0, 2.5);
  const double bow_radius = 1.8;
  const double shaft_bottom = 2.1, shaft_top = 2.9;  // the shaft is 0.8 wide, centred on the bow
  // Where the shaft edges meet the bow circle: exact corners, and the arc's end angles.
  const double junction_x = bow_center.x() + std::sqrt(bow_radius * bow_radius - 0.4 * 0.4);
  const double junction_angle = std::asin(0.4 / bow_radius);

  // Counter-clockwise: along the shaft's lower edge, around the bit's teeth, the
  // tip, back along the upper edge, and around the bow.
  const std::vector<Vec2> corners{
      {junction_x, shaft_bottom},
      {5.4, shaft_bottom},  // the bit starts
      {5.4, 0.9},           // tooth 1
      {5.9, 0.9},
      {6.1, 1.45},  // notch 1 (deepest)
      {6.4, 1.45},
      {6.6, 0.8},  // tooth 2 (longest)
      {7.0, 0.8},
      {7.2, 1.2},  // notch 2 (shallow)
      {7.5, 1.2},
      {7.7, 1.0},  // tooth 3
      {8.1, 1.0},
      {8.3, 1.6},  // notch 3 (deepest)
      {8.55, 1.6},
      {8.75, 0.95},  // tooth 4
      {9.0, 0.95},
      {9.2, 1.3},  // the bit ends with a bevel back up to the shaft
      {9.2, shaft_bottom},
      {9.45, shaft_bottom},
      {9.8, 2.5},  // the tip
      {9.45, shaft_top},
  };
  detail::OutlineRing outer;
  for (const Vec2& corner : corners) outer.pieces.push_back(line_from(corner));
  outer.pieces.push_back(
      arc_from({junction_x, shaft_top}, bow_center, bow_radius, junction_angle, 2 * kPi - 2 * junction_angle));

  // The hole sits a little towards the bow's far end, as on a real key.
  const Vec2 hole_center(1.7, 2.5);
  const double hole_radius = 0.65;
  detail::OutlineRing hole{{arc_from(hole_center + Vec2(hole_radius, 0), hole_center, hole_radius, 0, -2 * kPi)}, true};
  return detail::sample_outline({outer, hole}, boundary_segments);
}

}  // namespace structmesh
