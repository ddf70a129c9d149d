// Small linear programs over a point in 3D and the half-spaces of planar faces, solved by
// COIN-OR CLP (the LP solver under CBC): the kernel of a set of faces (the points that see
// all of them from their inner side), its Chebyshev centre, and where the kernel is empty
// the point behind the fewest faces. Used by the guard's kernel rounds (guard/
// kernel_candidates.cpp) and by the hex map's star cavities (hex/repair_flipped_tets.cpp).
#pragma once

#include "structmesh/mesh.hpp"

#include <initializer_list>
#include <utility>
#include <vector>

namespace structmesh::lp {

/// A face's plane: inside is normal . x <= offset.
struct Plane {
  Vec3 normal;        ///< unit, outward (zero for a degenerate face)
  double offset = 0;  ///< normal . x on the face
  double weight = 1;  ///< cost of a unit of excess in least_violating_point()
};

/// One small LP: minimise objective . x subject to rows "a . x <= upper" and bounds on x,
/// whose first three entries are the point sought.
class SmallLp {
 public:
  void add_column(double lo, double hi, double cost);
  void add_row(std::initializer_list<int> index, std::initializer_list<double> value, double upper);
  /// normal . (x, y, z) [+ extra_value * column extra_column, if >= 0] <= upper.
  void add_plane_row(const Plane& plane, int extra_column, double extra_value, double upper);
  /// The optimal x, or empty when CLP finds none.
  std::vector<double> solve() const;

 private:
  std::vector<std::pair<std::vector<int>, std::vector<double>>> rows_;
  std::vector<double> row_hi_, column_lo_, column_hi_, objective_;
};

/// An LP whose columns x, y, z are bounded by the box [lo, hi], of no cost.
SmallLp point_in_box(const Vec3& lo, const Vec3& hi);

/// Maximise r subject to n_f . p + r <= offset_f and p in [lo, hi], r within +-|hi - lo|:
/// the Chebyshev centre of the planes' kernel. False when the LP fails; depth gets r
/// (<= 0: the kernel is empty or flat).
bool chebyshev_centre(const std::vector<Plane>& planes, const Vec3& lo, const Vec3& hi, Vec3& centre, double& depth);

/// The point p within [lo, hi] that minimises sum_f weight_f max(0, n_f . p - offset_f +
/// margin): where the kernel is empty, the point on the wrong side of the least (weighted)
/// faces. `excess`, if given, gets each plane's max(0, ...) at p. False when the LP fails.
bool least_violating_point(const std::vector<Plane>& planes, double margin, const Vec3& lo, const Vec3& hi, Vec3& point,
                           std::vector<double>* excess = nullptr);

}  // namespace structmesh::lp
