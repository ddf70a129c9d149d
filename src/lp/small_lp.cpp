// The small LPs of small_lp.hpp. Written here rather than through CBC's modelling layer:
// these are a few rows each, built and solved thousands of times, and CLP's
// loadProblem on a packed matrix is all they need.
#include "lp/small_lp.hpp"

#include <CoinPackedMatrix.hpp>
#include <OsiClpSolverInterface.hpp>

namespace structmesh::lp {

void SmallLp::add_column(double lo, double hi, double cost) {
  column_lo_.push_back(lo), column_hi_.push_back(hi), objective_.push_back(cost);
}

void SmallLp::add_row(std::initializer_list<int> index, std::initializer_list<double> value, double upper) {
  rows_.emplace_back(std::vector<int>(index), std::vector<double>(value));
  row_hi_.push_back(upper);
}

void SmallLp::add_plane_row(const Plane& plane, int extra_column, double extra_value, double upper) {
  if (extra_column < 0)
    add_row({0, 1, 2}, {plane.normal.x(), plane.normal.y(), plane.normal.z()}, upper);
  else
    add_row({0, 1, 2, extra_column}, {plane.normal.x(), plane.normal.y(), plane.normal.z(), extra_value}, upper);
}

std::vector<double> SmallLp::solve() const {
  CoinPackedMatrix matrix(false, 0, 0);
  matrix.setDimensions(0, static_cast<int>(column_lo_.size()));
  for (const auto& [index, value] : rows_) matrix.appendRow(static_cast<int>(index.size()), index.data(), value.data());
  const std::vector<double> row_lo(row_hi_.size(), -COIN_DBL_MAX);
  OsiClpSolverInterface lp;
  lp.messageHandler()->setLogLevel(0);
  lp.loadProblem(matrix, column_lo_.data(), column_hi_.data(), objective_.data(), row_lo.data(), row_hi_.data());
  lp.initialSolve();
  if (!lp.isProvenOptimal()) return {};
  const double* x = lp.getColSolution();
  return {x, x + column_lo_.size()};
}

SmallLp point_in_box(const Vec3& lo, const Vec3& hi) {
  SmallLp lp;
  for (int k = 0; k < 3; ++k) lp.add_column(lo[k], hi[k], 0);
  return lp;
}

bool chebyshev_centre(const std::vector<Plane>& planes, const Vec3& lo, const Vec3& hi, Vec3& centre, double& depth) {
  SmallLp lp = point_in_box(lo, hi);
  const double size = (hi - lo).norm();
  lp.add_column(-size, size, -1);
  for (const Plane& plane : planes) lp.add_plane_row(plane, 3, 1.0, plane.offset);
  const std::vector<double> x = lp.solve();
  if (x.empty()) return false;
  centre = Vec3(x[0], x[1], x[2]);
  depth = x[3];
  return true;
}

bool least_violating_point(const std::vector<Plane>& planes, double margin, const Vec3& lo, const Vec3& hi, Vec3& point,
                           std::vector<double>* excess) {
  SmallLp lp = point_in_box(lo, hi);
  for (std::size_t f = 0; f < planes.size(); ++f) {
    lp.add_column(0, COIN_DBL_MAX, planes[f].weight);  // the plane's excess
    lp.add_plane_row(planes[f], static_cast<int>(3 + f), -1.0, planes[f].offset - margin);
  }
  const std::vector<double> x = lp.solve();
  if (x.empty()) return false;
  point = Vec3(x[0], x[1], x[2]);
  if (excess) excess->assign(x.begin() + 3, x.end());
  return true;
}

}  // namespace structmesh::lp
