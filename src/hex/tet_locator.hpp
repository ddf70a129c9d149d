// TetLocator: which tet of a tet mesh contains a point, and where (barycentric coordinates).
// A uniform bucket grid over the tets' bounding boxes, about one cell per tet; queries are
// const and thread-safe. Written by hand: CGAL's AABB tree has no tetrahedron primitive
// with barycentric output, and a bucket grid is a few lines and fast for well-shaped tets.
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <vector>

namespace structmesh::hex_detail {

struct TetLocation {
  Index tet = kInvalidIndex;            ///< kInvalidIndex when no tet is near
  std::array<double, 4> barycentric{};  ///< of the point in that tet
  bool inside = false;                  ///< all barycentric coordinates >= -tolerance
};

class TetLocator {
 public:
  /// `points` and `tets` must outlive the locator.
  TetLocator(const std::vector<Vec3>& points, const std::vector<std::array<Index, 4>>& tets);
  /// The tet containing p (the one with the largest smallest barycentric coordinate among the
  /// tets of p's cell); when none contains it, that best tet with inside = false.
  TetLocation locate(const Vec3& p, double tolerance = 1e-9) const;

 private:
  std::array<int, 3> cell_of(const Vec3& p) const;
  const std::vector<Vec3>& points_;
  const std::vector<std::array<Index, 4>>& tets_;
  Vec3 origin_ = Vec3::Zero();
  double cell_size_ = 1;
  std::array<int, 3> dims_{1, 1, 1};
  CompressedRows cell_tets_;
};

}  // namespace structmesh::hex_detail
