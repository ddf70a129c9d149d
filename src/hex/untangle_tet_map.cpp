// untangle_tet_map(): the last step of the volumetric map's untangling (§5.2.2): the tets that
// the point-by-point untangling and the star cavities leave flipped are untangled jointly,
// with the map's surface free to leave P where it folds.
//
// Why. What stays flipped lies where the map's surface on P folds or is squeezed flat (Q's
// charts do not match P's facets, thin parts of Q are squashed): with the surface pinned there,
// no placement of the interior points is valid, and neither moving one point at a time
// (Knupp's function) nor a star cavity can help (docs/design/hex.md). So the surface points
// of a region around what stays flipped are freed too, held near their places on P by a
// spring only, and the region is untangled jointly by the continuation method of Garanzha et
// al. 2021 ("Foldover-free maps in 50 lines of code", mesh/foldover_free.hpp) on the tets'
// Jacobians J = E_parameter E_source^-1 (scaled so that det J is 1 on average). With the
// region's surface free a valid placement always exists (the rim of the region, where it
// meets tets that stay as they are, is valid), and the barrier keeps every tet positive once
// it is. Only the region's points move; the map outside it does not change.
//
// In practice the continuation does not always find that placement: inside layers that the
// map squashes to a thousandth of their volume (the dogs' thin parts) the flipped tets stay,
// and rounds over 12 rings cost minutes on the large models. So polycube_hex_mesh() runs it
// over 3 rings by default (1-10 s; the bunny's, fertility's and the screwdriver's maps come
// out flip-free) and over 3, 6 and 12 only when asked (--untangle-map); the measurements are
// in docs/design/hex.md.
//
// Hand-written on LBFGS++ for the same reason as untangle_hexes.cpp: no Debian library
// untangles a tet map.
//
// The energy is evaluated per tet in fixed parallel blocks (mesh/free_point_elements.hpp), so
// the result does not depend on the thread count.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/quality.hpp"

#include "mesh/foldover_free.hpp"
#include "mesh/free_point_elements.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>

namespace structmesh {
namespace {

// The joint energy of the tets that use a free point: per tet its reference matrix M_t (so
// that J = E_x M_t, E_x the edge matrix in the unknowns' units) and weight (source volume over
// the mean), plus the springs of the free surface points.
class TetMapEnergy {
 public:
  TetMapEnergy(const TetMesh& source, const std::vector<Vec3>& parameter, std::span<const Index> free,
               std::span<const Vec3> anchor, double spring, double unit, double jacobian_scale)
      : layout_(parameter, free, unit), anchor_(anchor.size()), spring_(spring) {
    // The springs' rest positions in the unknowns' units (NaN for interior points).
    for (std::size_t k = 0; k < anchor.size(); ++k)
      anchor_[k] = std::isnan(anchor[k][0]) ? anchor[k] : layout_.to_unknowns(anchor[k]);
    double total_volume = 0;
    for (const auto& tet : source.tets) {
      if (!layout_.uses_free_point(tet)) continue;
      Eigen::Matrix3d edges;
      for (int c = 0; c < 3; ++c) edges.col(c) = source.points[tet[c + 1]] - source.points[tet[0]];
      const double det = edges.determinant();
      if (!(std::abs(det) > 0)) continue;  // a flat source tet has no Jacobian; it cannot invert either
      layout_.add(tet);
      // J = E_parameter E_source^-1 c, with E_parameter = unit E_x.
      reference_.push_back(unit * jacobian_scale * edges.inverse());
      weight_.push_back(std::abs(det));
      total_volume += std::abs(det);
    }
    layout_.finish();
    const double mean = weight_.empty() ? 1.0 : total_volume / static_cast<double>(weight_.size());
    for (double& w : weight_) w /= mean;
  }

  std::size_t tet_count() const { return layout_.size(); }
  Eigen::VectorXd initial() const { return layout_.initial(); }
  void write(const Eigen::VectorXd& x, std::vector<Vec3>& parameter) const { layout_.write(x, parameter); }

  double eps = 0;

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    double total = layout_.sum_with_gradient(
        [&](std::size_t t) {
          const Eigen::Matrix3d jacobian = edge_matrix(x, t) * reference_[t];
          Vec3 ga, gb, gd;
          const double energy = weight_[t] * detail::foldover_energy_3d(eps, jacobian.col(0), jacobian.col(1),
                                                                        jacobian.col(2), ga, gb, gd);
          // dE/dE_x = dE/dJ M^T, column c the gradient of node c + 1; node 0 takes minus their sum.
          Eigen::Matrix3d d_jacobian;
          d_jacobian << ga, gb, gd;
          const Eigen::Matrix3d d_edges = weight_[t] * d_jacobian * reference_[t].transpose();
          Vec3* g = layout_.node_gradient(t);
          g[0] = -d_edges.rowwise().sum();
          for (int c = 0; c < 3; ++c) g[1 + c] = d_edges.col(c);
          return energy;
        },
        grad);
    for (std::size_t k = 0; k < anchor_.size(); ++k) {
      if (std::isnan(anchor_[k][0])) continue;
      const Vec3 offset = Vec3(x.segment<3>(3 * static_cast<Eigen::Index>(k))) - anchor_[k];
      total += spring_ * offset.squaredNorm();
      grad.segment<3>(3 * static_cast<Eigen::Index>(k)) += 2 * spring_ * offset;
    }
    return total;
  }

  /// The smallest det J, and (if given) how many tets have det J <= 0.
  double min_det(const Eigen::VectorXd& x, std::size_t* nonpositive = nullptr) {
    std::atomic<std::size_t> count{0};
    const double smallest = layout_.minimum([&](std::size_t t) {
      const double det = (edge_matrix(x, t) * reference_[t]).determinant();
      if (!(det > 0)) count.fetch_add(1, std::memory_order_relaxed);
      return det;
    });
    if (nonpositive) *nonpositive = count.load();
    return smallest;
  }

 private:
  Eigen::Matrix3d edge_matrix(const Eigen::VectorXd& x, std::size_t t) const {
    const std::array<Vec3, 4> p = layout_.nodes(x, t);
    Eigen::Matrix3d edges;
    for (int c = 0; c < 3; ++c) edges.col(c) = p[c + 1] - p[0];
    return edges;
  }

  detail::FreePointElements<4> layout_;
  std::vector<Vec3> anchor_;
  double spring_;
  std::vector<Eigen::Matrix3d> reference_;
  std::vector<double> weight_;
};

// The tets whose image is inverted or flat: det J, normalised so that it averages 1 over the
// mesh, at most `flat` (0: inverted or zero volume only).
std::size_t count_flipped(const TetMesh& source, std::span<const Vec3> parameter, double flat,
                          std::vector<std::uint8_t>* flags = nullptr) {
  double source_volume = 0, image_volume = 0;
  for (const auto& tet : source.tets) {
    source_volume += std::abs(tet_signed_volume(source.points, tet));
    image_volume +=
        std::abs(tet_signed_volume(parameter[tet[0]], parameter[tet[1]], parameter[tet[2]], parameter[tet[3]]));
  }
  const double scale = image_volume > 0 ? source_volume / image_volume : 1.0;
  std::size_t flipped = 0;
  if (flags) flags->assign(source.tets.size(), 0);
  for (std::size_t t = 0; t < source.tets.size(); ++t) {
    const auto& tet = source.tets[t];
    const double image = tet_signed_volume(parameter[tet[0]], parameter[tet[1]], parameter[tet[2]], parameter[tet[3]]);
    const double own = std::abs(tet_signed_volume(source.points, tet));
    if (!(image > 0) || !(image * scale > flat * own)) {
      ++flipped;
      if (flags) (*flags)[t] = 1;
    }
  }
  return flipped;
}

}  // namespace

std::size_t flipped_or_flat_tets(const TetMesh& source, std::span<const Vec3> parameter, double flat) {
  if (parameter.size() != source.points.size())
    throw InputError("flipped_or_flat_tets: " + std::to_string(parameter.size()) + " parameter positions for " +
                     std::to_string(source.points.size()) + " points");
  return count_flipped(source, parameter, flat);
}

TetMapUntangling untangle_tet_map(const TetMesh& source, std::vector<Vec3>& parameter, std::size_t boundary_count,
                                  std::span<const Vec3> boundary_targets, const TetMapUntanglingOptions& options) {
  if (parameter.size() != source.points.size())
    throw InputError("untangle_tet_map: " + std::to_string(parameter.size()) + " parameter positions for " +
                     std::to_string(source.points.size()) + " points");
  if (boundary_targets.size() != boundary_count || boundary_count > source.points.size())
    throw InputError("untangle_tet_map: " + std::to_string(boundary_targets.size()) + " boundary targets for " +
                     std::to_string(boundary_count) + " boundary points");
  TetMapUntangling result;
  const std::size_t point_count = source.points.size();
  std::vector<std::uint8_t> flipped;
  result.flipped_before = count_flipped(source, parameter, options.flat, &flipped);
  result.flipped_after = result.flipped_before;
  if (result.flipped_before == 0) return result;

  // det J averages 1: J scaled by the cube root of the source's volume over the image's.
  double source_volume = 0, image_volume = 0, edge_sum = 0;
  for (const auto& tet : source.tets) {
    source_volume += std::abs(tet_signed_volume(source.points, tet));
    image_volume += std::abs(tet_signed_volume(parameter, tet));
    edge_sum += (parameter[tet[1]] - parameter[tet[0]]).norm();
  }
  const double jacobian_scale = image_volume > 0 ? std::cbrt(source_volume / image_volume) : 1.0;
  // The unknowns in units of the mean image edge, so that L-BFGS's first step is about an edge.
  const double unit = edge_sum > 0 ? edge_sum / static_cast<double>(source.tets.size()) : 1.0;

  const CompressedRows tets_of_point = build_vertex_elements(source.tets, point_count);
  std::vector<std::uint8_t> in_region(point_count, 0);
  std::vector<Index> region;
  for (std::size_t t = 0; t < source.tets.size(); ++t)
    if (flipped[t])
      for (const Index v : source.tets[t])
        if (!in_region[v]) in_region[v] = 1, region.push_back(v);
  int rings = 0;
  auto grow_to = [&](int target_rings) {
    for (; rings < target_rings; ++rings) {
      const std::size_t end = region.size();
      for (std::size_t i = 0; i < end; ++i)
        for (const Index t : tets_of_point.row(region[i]))
          for (const Index v : source.tets[t])
            if (!in_region[v]) in_region[v] = 1, region.push_back(v);
    }
  };
  // The rounds: (rings, surface free), the first one pinned if asked.
  std::vector<std::pair<int, bool>> rounds;
  for (const int r : options.rings) {
    if (rounds.empty() && options.pinned_first) rounds.emplace_back(r, false);
    rounds.emplace_back(r, true);
  }
  for (const auto& [target_rings, surface_free] : rounds) {
    grow_to(target_rings);
    // Free: the region's points whose tets all lie in the region's closure (so the rim, the
    // points with a tet reaching outside, holds the rest of the map in place).
    std::vector<Index> free;
    for (const Index v : region) {
      bool inner = true;
      for (const Index t : tets_of_point.row(v))
        for (const Index u : source.tets[t]) inner = inner && in_region[u];
      if (inner && (v >= boundary_count || surface_free)) free.push_back(v);
    }
    if (free.empty()) continue;
    // Sorted, so the unknowns' order (and the result) does not depend on the growth's order.
    std::sort(free.begin(), free.end());
    // The springs' targets: a surface point's place on P, NaN for an interior point.
    std::vector<Vec3> anchor(free.size(), Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0));
    for (std::size_t k = 0; k < free.size(); ++k)
      if (free[k] < boundary_count) anchor[k] = boundary_targets[free[k]];
    TetMapEnergy energy(source, parameter, free, anchor, options.spring, unit, jacobian_scale);
    Eigen::VectorXd x = energy.initial();
    detail::FoldoverFreeSettings loop;
    loop.wolfe = false;
    loop.restore_on_failure = true;
    loop.max_steps = options.max_steps;
    loop.max_iterations = options.max_iterations;
    loop.max_steps_once_valid = options.max_steps_once_valid;
    std::vector<Vec3> trial = parameter;
    // The loop keeps the placement with the largest smallest det J; the one with the fewest
    // flipped tets is kept here too, and wins while some stay flipped.
    std::size_t fewest = 0;
    energy.min_det(x, &fewest);
    const std::size_t start_count = fewest;
    Eigen::VectorXd fewest_x = x;
    bool given_up = false;
    loop.give_up = [&](int steps) {
      given_up = steps >= options.give_up_after_steps && fewest >= start_count;
      return given_up;
    };
    const detail::FoldoverFreeResult minimised = detail::minimize_foldover_free(
        x, energy.eps, [&](const Eigen::VectorXd& v, Eigen::VectorXd& g) { return energy(v, g); },
        [&](const Eigen::VectorXd& v) {
          std::size_t count = 0;
          const double smallest = energy.min_det(v, &count);
          if (count < fewest) fewest = count, fewest_x = v;
          return smallest;
        },
        loop);
    if (!(minimised.min_det_after > 0)) x = fewest_x;
    energy.write(x, trial);
    ++result.rounds;
    if (given_up) ++result.rounds_given_up;
    result.rings = rings;
    result.region_tets = energy.tet_count();
    const std::size_t left = count_flipped(source, trial, options.flat);
    if (left >= result.flipped_after) continue;  // kept only when it gains
    parameter.swap(trial);
    result.flipped_after = left;
    result.min_det_after = minimised.min_det_after;
    result.steps = minimised.outer_iterations;
    result.free_points = free.size();
    result.moved_boundary_points = 0;
    result.boundary_drift = 0;
    for (std::size_t v = 0; v < boundary_count; ++v) {
      const double drift = (parameter[v] - boundary_targets[v]).norm();
      if (drift > 0) ++result.moved_boundary_points;
      result.boundary_drift = std::max(result.boundary_drift, drift / unit);
    }
    if (left == 0) break;
  }
  return result;
}

}  // namespace structmesh
