// The six axis labels of §4.3 (+X, -X, +Y, -Y, +Z, -Z): faces are classified by the
// minimal rotation of their normal to an axis, i.e. by the axis nearest the normal.
// Written by hand: it is a comparison of three coordinates, and the tie rule (to the
// lower label) must be the project's own so labels are reproducible.
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"

#include <string>

namespace structmesh {

int nearest_axis_label(const Vec3& normal) {
  // The nearest axis maximises n . axis, which is +-n[k] for the labels 2k and 2k + 1;
  // scanning the labels in order with a strict comparison gives ties to the lower one.
  int best = 0;
  double best_dot = normal.x();
  for (int label = 1; label < kAxisLabels; ++label) {
    const double dot = (label % 2 == 0 ? 1.0 : -1.0) * normal[label / 2];
    if (dot > best_dot) {
      best = label;
      best_dot = dot;
    }
  }
  return best;
}

Vec3 axis_of_label(int label) {
  if (label < 0 || label >= kAxisLabels)
    throw InputError("axis label " + std::to_string(label) + " is not one of 0..5 (+X, -X, +Y, -Y, +Z, -Z)");
  Vec3 axis = Vec3::Zero();
  axis[label / 2] = label % 2 == 0 ? 1.0 : -1.0;
  return axis;
}

}  // namespace structmesh
