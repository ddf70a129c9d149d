// Internal: the bookkeeping of a joint optimisation over some points of a mesh, shared by
// hex/untangle_hexes.cpp (hex corners) and hex/untangle_tet_map.cpp (a tet map's Jacobians).
// The unknowns are the free points' coordinates in units of `unit` from the first free point
// (so that L-BFGS's first step, of unit length, is about one edge); the elements that use a
// free point are evaluated in fixed blocks (TBB) into a buffer of per-node gradients, which
// are then summed per free point in element order: the result does not depend on the thread
// count.
#pragma once

#include "structmesh/mesh.hpp"

#include <Eigen/Core>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace structmesh::detail {

template <std::size_t N>
class FreePointElements {
 public:
  static constexpr std::size_t kBlock = 512;  ///< elements per parallel block (fixed)

  FreePointElements(const std::vector<Vec3>& points, std::span<const Index> free, double unit)
      : points_(points),
        free_(free),
        inv_unit_(1.0 / unit),
        origin_(points[free[0]]),
        slot_(points.size(), kInvalidIndex) {
    for (std::size_t k = 0; k < free.size(); ++k) slot_[free[k]] = static_cast<Index>(k);
  }

  /// Whether the element has a free node (only those are worth adding).
  bool uses_free_point(const std::array<Index, N>& element) const {
    return std::any_of(element.begin(), element.end(), [&](Index v) { return slot_[v] != kInvalidIndex; });
  }
  void add(const std::array<Index, N>& element) {
    elements_.push_back(element);
    std::array<Index, N> s;
    for (std::size_t i = 0; i < N; ++i) s[i] = slot_[element[i]];
    slots_.push_back(s);
  }
  /// After the last add(): per free point, the (element, node) entries of the gradient
  /// buffer, in element order.
  void finish() {
    incidence_offsets_.assign(free_.size() + 1, 0);
    for (const auto& s : slots_)
      for (const Index k : s)
        if (k != kInvalidIndex) ++incidence_offsets_[k + 1];
    for (std::size_t k = 0; k < free_.size(); ++k) incidence_offsets_[k + 1] += incidence_offsets_[k];
    incidence_.resize(incidence_offsets_.back());
    std::vector<std::size_t> fill(incidence_offsets_.begin(), incidence_offsets_.end() - 1);
    for (std::size_t e = 0; e < slots_.size(); ++e)
      for (std::size_t i = 0; i < N; ++i)
        if (slots_[e][i] != kInvalidIndex) incidence_[fill[slots_[e][i]]++] = static_cast<Index>(N * e + i);
    node_gradient_.resize(N * elements_.size());
    block_values_.resize((elements_.size() + kBlock - 1) / kBlock);
  }

  std::size_t size() const { return elements_.size(); }
  const std::array<Index, N>& element(std::size_t e) const { return elements_[e]; }

  Eigen::VectorXd initial() const {
    Eigen::VectorXd x(3 * static_cast<Eigen::Index>(free_.size()));
    for (std::size_t k = 0; k < free_.size(); ++k)
      x.segment<3>(3 * static_cast<Eigen::Index>(k)) = (points_[free_[k]] - origin_) * inv_unit_;
    return x;
  }
  void write(const Eigen::VectorXd& x, std::vector<Vec3>& points) const {
    for (std::size_t k = 0; k < free_.size(); ++k)
      points[free_[k]] = origin_ + Vec3(x.segment<3>(3 * static_cast<Eigen::Index>(k))) / inv_unit_;
  }
  /// Element e's nodes in the unknowns' units (free ones from x).
  std::array<Vec3, N> nodes(const Eigen::VectorXd& x, std::size_t e) const {
    std::array<Vec3, N> p;
    for (std::size_t i = 0; i < N; ++i) {
      const Index s = slots_[e][i];
      p[i] = s == kInvalidIndex ? Vec3((points_[elements_[e][i]] - origin_) * inv_unit_)
                                : Vec3(x.segment<3>(3 * static_cast<Eigen::Index>(s)));
    }
    return p;
  }
  /// Where element e's node gradients go (N of them).
  Vec3* node_gradient(std::size_t e) { return node_gradient_.data() + N * e; }
  /// Free point k's position, in the unknowns' units, of `target` (a position of the mesh).
  Vec3 to_unknowns(const Vec3& target) const { return (target - origin_) * inv_unit_; }

  /// The sum over elements of value(e), which also fills node_gradient(e); then grad, the
  /// node gradients summed per free point.
  template <class Value>
  double sum_with_gradient(Value&& value, Eigen::VectorXd& grad) {
    tbb::parallel_for(std::size_t{0}, block_values_.size(), [&](std::size_t b) {
      double total = 0;
      for (std::size_t e = b * kBlock; e < std::min(elements_.size(), (b + 1) * kBlock); ++e) total += value(e);
      block_values_[b] = total;
    });
    grad.resize(3 * static_cast<Eigen::Index>(free_.size()));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, free_.size(), kBlock), [&](const auto& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        Vec3 sum = Vec3::Zero();
        for (std::size_t i = incidence_offsets_[k]; i < incidence_offsets_[k + 1]; ++i)
          sum += node_gradient_[incidence_[i]];
        grad.segment<3>(3 * static_cast<Eigen::Index>(k)) = sum;
      }
    });
    double total = 0;
    for (const double v : block_values_) total += v;
    return total;
  }
  /// The smallest value(e) over the elements (0 with none).
  template <class Value>
  double minimum(Value&& value) {
    tbb::parallel_for(std::size_t{0}, block_values_.size(), [&](std::size_t b) {
      double smallest = std::numeric_limits<double>::infinity();
      for (std::size_t e = b * kBlock; e < std::min(elements_.size(), (b + 1) * kBlock); ++e)
        smallest = std::min(smallest, value(e));
      block_values_[b] = smallest;
    });
    return block_values_.empty() ? 0.0 : *std::min_element(block_values_.begin(), block_values_.end());
  }

 private:
  const std::vector<Vec3>& points_;
  std::span<const Index> free_;
  double inv_unit_;
  Vec3 origin_;
  std::vector<Index> slot_;
  std::vector<std::array<Index, N>> elements_, slots_;
  std::vector<std::size_t> incidence_offsets_;
  std::vector<Index> incidence_;  // N * element + node
  std::vector<Vec3> node_gradient_;
  std::vector<double> block_values_;
};

}  // namespace structmesh::detail
