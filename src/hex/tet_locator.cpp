#include "tet_locator.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

namespace structmesh::hex_detail {

TetLocator::TetLocator(const std::vector<Vec3>& points, const std::vector<std::array<Index, 4>>& tets)
    : points_(points), tets_(tets) {
  BoundingBox3 box = bounding_box(points);
  if (box.empty() || tets.empty()) {
    cell_tets_.offsets.assign(2, 0);
    return;
  }
  const Vec3 extent = (box.max - box.min).cwiseMax(1e-12);
  // About one cell per tet.
  cell_size_ = std::cbrt(extent.prod() / static_cast<double>(tets.size()));
  if (!(cell_size_ > 0)) cell_size_ = extent.maxCoeff();
  for (int a = 0; a < 3; ++a) dims_[a] = std::clamp(static_cast<int>(std::ceil(extent[a] / cell_size_)), 1, 1024);
  origin_ = box.min;
  const std::size_t cells = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
  std::vector<Index> count(cells + 1, 0);
  auto for_cells = [&](std::size_t t, auto&& visit) {
    Vec3 lo = points[tets[t][0]], hi = lo;
    for (int c = 1; c < 4; ++c) {
      lo = lo.cwiseMin(points[tets[t][c]]);
      hi = hi.cwiseMax(points[tets[t][c]]);
    }
    const auto a = cell_of(lo), b = cell_of(hi);
    for (int z = a[2]; z <= b[2]; ++z)
      for (int y = a[1]; y <= b[1]; ++y)
        for (int x = a[0]; x <= b[0]; ++x)
          visit(static_cast<std::size_t>(x) +
                static_cast<std::size_t>(dims_[0]) * (y + static_cast<std::size_t>(dims_[1]) * z));
  };
  for (std::size_t t = 0; t < tets.size(); ++t) for_cells(t, [&](std::size_t c) { ++count[c + 1]; });
  for (std::size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
  cell_tets_.offsets = count;
  cell_tets_.items.resize(count[cells]);
  for (std::size_t t = 0; t < tets.size(); ++t)
    for_cells(t, [&](std::size_t c) { cell_tets_.items[count[c]++] = static_cast<Index>(t); });
}

std::array<int, 3> TetLocator::cell_of(const Vec3& p) const {
  std::array<int, 3> cell{};
  for (int a = 0; a < 3; ++a)
    cell[a] = std::clamp(static_cast<int>(std::floor((p[a] - origin_[a]) / cell_size_)), 0, dims_[a] - 1);
  return cell;
}

TetLocation TetLocator::locate(const Vec3& p, double tolerance) const {
  TetLocation best;
  if (tets_.empty()) return best;
  const auto c = cell_of(p);
  const std::size_t cell = static_cast<std::size_t>(c[0]) +
                           static_cast<std::size_t>(dims_[0]) * (c[1] + static_cast<std::size_t>(dims_[1]) * c[2]);
  double best_min = -std::numeric_limits<double>::infinity();
  for (Index t : cell_tets_.row(cell)) {
    const auto& tet = tets_[t];
    Eigen::Matrix3d edges;
    edges.col(0) = points_[tet[1]] - points_[tet[0]];
    edges.col(1) = points_[tet[2]] - points_[tet[0]];
    edges.col(2) = points_[tet[3]] - points_[tet[0]];
    const Vec3 local = edges.partialPivLu().solve(p - points_[tet[0]]);
    if (!local.allFinite()) continue;
    const std::array<double, 4> b{1 - local.sum(), local[0], local[1], local[2]};
    const double smallest = *std::min_element(b.begin(), b.end());
    if (smallest > best_min) {
      best_min = smallest;
      best.tet = t;
      best.barycentric = b;
    }
  }
  best.inside = best.tet != kInvalidIndex && best_min >= -tolerance;
  return best;
}

}  // namespace structmesh::hex_detail
