// volumetric_map(): the volumetric polycube parameterization of §5.2.2.
//
// 1. Boundary frames. Each boundary tet takes the rotation carrying its boundary face from
//    the source surface S to the target surface (the frame of the face: first edge, in-plane
//    perpendicular, normal, on both sides). The dissertation sets one frame vector along the
//    face normal and lets the in-plane pair be optimised; the rotation of the pre-deformation
//    fixes that pair the way the surface map already did.
// 2. Interior frames minimise the smoothness energy C_S over the dual graph (face-adjacent
//    tets). §5.2.2 interpolates Euler angles; here the unit quaternions are interpolated
//    (harmonically, then normalised), which is the same linear solve without the gimbal
//    singularities and wrap-around of Euler angles. Rotations of the pre-deformation stay well
//    below 180 degrees, so one hemisphere (w >= 0) holds them all.
// 3. Positions minimise (5.1): sum_t vol(t) |grad u^k - X^k_t|^2, with X^k_t the k-th row of
//    the tet's rotation (the map's Jacobian should be that rotation) and every boundary point
//    fixed at its target. The normal equations are the cotangent stiffness matrix K (one for
//    all three coordinates) with right-hand sides div X^k; CHOLMOD factors K once.
//    The dissertation lets boundary points slide within their polycube facets; here the
//    boundary is the pseudo-polycube Q of §4.3 with its exact correspondence to S, and the
//    polycube's grid is fitted to Q afterwards (see polycube_hex_mesh.cpp), so every
//    boundary point is pinned.
// 4. Untangling. A tet the linear map still inverts (it happens where the frames twist fast)
//    is repaired by moving its interior points to minimise Knupp's untangling function
//    sum_t (|V_t - beta_t| - (V_t - beta_t))^2 (Knupp 2001, the "Untangle" metric of [119]),
//    which is zero exactly when every tet around the point has volume >= beta_t.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/quality.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <Eigen/Cholesky>
#include <Eigen/CholmodSupport>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace structmesh {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The map untangling's wavefronts (below): a level of fewer points runs on the calling
// thread, a larger one in blocks of kLevelGrain points.
constexpr std::size_t kSerialLevel = 32, kLevelGrain = 8;

/// Orthonormal frame of a triangle: first edge, in-plane perpendicular, normal (columns).
bool triangle_frame(const Vec3& a, const Vec3& b, const Vec3& c, Eigen::Matrix3d& frame) {
  const Vec3 e = b - a;
  const Vec3 n = e.cross(c - a);
  if (!(e.norm() > 0) || !(n.norm() > 0)) return false;
  const Vec3 e1 = e.normalized(), e3 = n.normalized();
  frame.col(0) = e1;
  frame.col(1) = e3.cross(e1);
  frame.col(2) = e3;
  return true;
}

/// Gradients of the four barycentric functions of a tet (rows), and its signed volume.
bool barycentric_gradients(const std::array<Vec3, 4>& p, Eigen::Matrix<double, 4, 3>& gradient, double& volume) {
  Eigen::Matrix3d edges;
  edges.col(0) = p[1] - p[0];
  edges.col(1) = p[2] - p[0];
  edges.col(2) = p[3] - p[0];
  const double det = edges.determinant();
  volume = det / 6;
  if (!(std::abs(det) > 0)) return false;
  const Eigen::Matrix3d inverse = edges.inverse();
  gradient.block<3, 3>(1, 0) = inverse;
  gradient.row(0) = -inverse.colwise().sum();
  return true;
}

/// The same for tet t of the mesh, with its unsigned volume.
bool tet_barycentric_gradients(const TetMesh& tets, std::size_t t, Eigen::Matrix<double, 4, 3>& gradient,
                               double& volume) {
  const auto& tet = tets.tets[t];
  const std::array<Vec3, 4> p{tets.points[tet[0]], tets.points[tet[1]], tets.points[tet[2]], tets.points[tet[3]]};
  const bool ok = barycentric_gradients(p, gradient, volume);
  volume = std::abs(volume);
  return ok;
}

struct TriangleKey {
  std::array<Index, 3> v;
  bool operator==(const TriangleKey& o) const { return v == o.v; }
};
struct TriangleKeyHash {
  std::size_t operator()(const TriangleKey& k) const {
    return (static_cast<std::size_t>(k.v[0]) * 73856093u) ^ (static_cast<std::size_t>(k.v[1]) * 19349663u) ^
           (static_cast<std::size_t>(k.v[2]) * 83492791u);
  }
};
TriangleKey sorted_key(Index a, Index b, Index c) {
  std::array<Index, 3> v{a, b, c};
  std::sort(v.begin(), v.end());
  return {v};
}

}  // namespace

VolumetricMap volumetric_map(const TetMesh& tets, const TriMesh& boundary_source, const TriMesh& boundary_target,
                             const VolumetricMapOptions& options) {
  const std::size_t boundary_count = boundary_source.points.size();
  if (!options.boundary_positions.empty() && options.boundary_positions.size() != boundary_count)
    throw InputError("volumetric_map: " + std::to_string(options.boundary_positions.size()) +
                     " boundary positions for " + std::to_string(boundary_count) + " boundary points");
  if (boundary_target.points.size() != boundary_count || boundary_target.triangles != boundary_source.triangles)
    throw InputError("volumetric_map: the source and target surfaces must share their triangles (" +
                     std::to_string(boundary_count) + " and " + std::to_string(boundary_target.points.size()) +
                     " points)");
  if (tets.points.size() < boundary_count || tets.tets.empty())
    throw InputError("volumetric_map: the tet mesh must start with the surface's points and have tets");
  for (std::size_t i = 0; i < boundary_count; ++i)
    if (tets.points[i] != boundary_source.points[i])
      throw InputError("volumetric_map: tet-mesh point " + std::to_string(i) + " is not the surface's point " +
                       std::to_string(i));
  VolumetricMap result;
  auto start = Clock::now();
  const std::size_t tet_count = tets.tets.size(), point_count = tets.points.size();

  // --- 1. boundary frames: the rotation of each surface triangle from S to the target.
  std::unordered_map<TriangleKey, Index, TriangleKeyHash> triangle_of;
  triangle_of.reserve(boundary_source.triangles.size() * 2);
  std::vector<Eigen::Quaterniond> triangle_rotation(boundary_source.triangles.size(), Eigen::Quaterniond::Identity());
  for (std::size_t f = 0; f < boundary_source.triangles.size(); ++f) {
    const auto& t = boundary_source.triangles[f];
    triangle_of.emplace(sorted_key(t[0], t[1], t[2]), static_cast<Index>(f));
    Eigen::Matrix3d frame_source, frame_target;
    if (triangle_frame(boundary_source.points[t[0]], boundary_source.points[t[1]], boundary_source.points[t[2]],
                       frame_source) &&
        triangle_frame(boundary_target.points[t[0]], boundary_target.points[t[1]], boundary_target.points[t[2]],
                       frame_target)) {
      Eigen::Quaterniond q(Eigen::Matrix3d(frame_target * frame_source.transpose()));
      if (q.w() < 0) q.coeffs() = -q.coeffs();
      triangle_rotation[f] = q.normalized();
    }
  }
  const FaceAdjacency<3> faces = build_faces(tets);
  std::vector<Eigen::Vector4d> quaternion(tet_count, Eigen::Vector4d::Zero());
  std::vector<std::uint8_t> fixed_frame(tet_count, 0);
  for (std::size_t f = 0; f < faces.faces.size(); ++f) {
    if (faces.face_cells[f][1] != kInvalidIndex) continue;
    const auto& v = faces.faces[f];
    auto it = triangle_of.find(sorted_key(v[0], v[1], v[2]));
    if (it == triangle_of.end())
      throw InputError("volumetric_map: a boundary face of the tet mesh is not a triangle of the surface");
    const Index cell = faces.face_cells[f][0];
    quaternion[cell] += triangle_rotation[it->second].coeffs();
    fixed_frame[cell] = 1;
  }

  // The stiffness matrix K of the tets (cotangent weights) over the interior points, and its
  // couplings to the boundary points, which both solves below use. CHOLMOD factors it once.
  // Row i of K: sum over tets of vol grad_i . grad_j.
  std::vector<Index> unknown_of_point(point_count, kInvalidIndex);
  std::size_t unknowns = 0;
  for (std::size_t i = boundary_count; i < point_count; ++i) unknown_of_point[i] = static_cast<Index>(unknowns++);
  struct Coupling {
    Index row, boundary_point;
    double k;
  };
  std::vector<Coupling> couplings;  // K's entries between an interior row and a boundary point
  std::optional<Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>> factor;
  if (unknowns > 0) {
    // Only K's lower triangle: CholmodSupernodalLLT reads no other (Eigen's default UpLo =
    // Lower; CHOLMOD's stype -1), and half the entries halve the assembly (the bunny's 16M
    // triplets took 1.7 s).
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(tet_count * 10);
    for (std::size_t t = 0; t < tet_count; ++t) {
      const auto& tet = tets.tets[t];
      Eigen::Matrix<double, 4, 3> gradient;
      double volume = 0;
      if (!tet_barycentric_gradients(tets, t, gradient, volume)) continue;
      for (int i = 0; i < 4; ++i) {
        const Index row = unknown_of_point[tet[i]];
        if (row == kInvalidIndex) continue;
        for (int j = 0; j < 4; ++j) {
          const Index column = unknown_of_point[tet[j]];
          if (column != kInvalidIndex && column > row) continue;  // upper triangle
          const double k = volume * gradient.row(i).dot(gradient.row(j));
          if (column != kInvalidIndex)
            entries.emplace_back(row, static_cast<Eigen::Index>(column), k);
          else
            couplings.push_back({row, tet[j], k});
        }
      }
    }
    // Points no tet uses: a unit diagonal keeps the system definite (they stay at the origin).
    std::vector<std::uint8_t> used(point_count, 0);
    for (const auto& tet : tets.tets)
      for (Index v : tet) used[v] = 1;
    for (std::size_t i = boundary_count; i < point_count; ++i)
      if (!used[i]) {
        const auto row = static_cast<Eigen::Index>(unknown_of_point[i]);
        entries.emplace_back(row, row, 1.0);
      }
    Eigen::SparseMatrix<double> stiffness(static_cast<Eigen::Index>(unknowns), static_cast<Eigen::Index>(unknowns));
    stiffness.setFromTriplets(entries.begin(), entries.end());
    factor.emplace(stiffness);
    if (factor->info() != Eigen::Success)
      throw Error("volumetric_map: CHOLMOD could not factor the stiffness matrix (interior points without boundary?)");
  }

  // --- 2. interior frames: harmonic quaternions (C_S of §5.2.2), smoothed on the points
  // rather than on the dual graph (a tet mesh has about five tets per point), with the same
  // stiffness matrix as (5.1): the discrete Dirichlet energy of the quaternion field, and one
  // factorization for both solves (the graph Laplacian of the tet edges took a second
  // factorization: 7 of the bunny's 21 s of map at 80k hexes). An interior tet's frame is
  // the mean of its four points'. Boundary points carry the mean rotation of their triangles.
  std::vector<Eigen::Vector4d> point_quaternion(point_count, Eigen::Vector4d::Zero());
  for (std::size_t f = 0; f < boundary_source.triangles.size(); ++f)
    for (Index v : boundary_source.triangles[f]) point_quaternion[v] += triangle_rotation[f].coeffs();
  if (factor) {
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(unknowns), 4);
    for (const Coupling& c : couplings)
      rhs.row(c.row) -= c.k * point_quaternion[c.boundary_point].normalized().transpose();
    const Eigen::MatrixXd solution = factor->solve(rhs);
    for (std::size_t v = boundary_count; v < point_count; ++v)
      point_quaternion[v] = solution.row(static_cast<Eigen::Index>(unknown_of_point[v])).transpose();
  }
  for (std::size_t t = 0; t < tet_count; ++t)
    if (!fixed_frame[t])
      for (Index v : tets.tets[t]) quaternion[t] += point_quaternion[v].normalized();
  std::vector<Eigen::Matrix3d> rotation(tet_count);
  for (std::size_t t = 0; t < tet_count; ++t) {
    Eigen::Vector4d q = quaternion[t];
    rotation[t] = q.norm() > 1e-12 ? Eigen::Quaterniond(q / q.norm()).toRotationMatrix() : Eigen::Matrix3d::Identity();
  }
  result.seconds_frames = seconds_since(start);

  // --- 3. positions: the least squares (5.1) with the boundary pinned to the target.
  start = Clock::now();
  result.parameter.assign(point_count, Vec3::Zero());
  const std::vector<Vec3>& positions =
      options.boundary_positions.empty() ? boundary_target.points : options.boundary_positions;
  for (std::size_t i = 0; i < boundary_count; ++i) result.parameter[i] = positions[i];
  if (factor) {
    // Right-hand side: vol grad_i . X^k (X^k = row k of R), minus the boundary couplings.
    // The gradients are computed again rather than kept from the stiffness pass: 96 bytes a
    // tet (100 MB for the bunny's 1M tets) against one small inverse each.
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(unknowns), 3);
    for (std::size_t t = 0; t < tet_count; ++t) {
      const auto& tet = tets.tets[t];
      Eigen::Matrix<double, 4, 3> gradient;
      double volume = 0;
      if (!tet_barycentric_gradients(tets, t, gradient, volume)) continue;
      const Eigen::Matrix<double, 4, 3> divergence = volume * gradient * rotation[t].transpose();
      for (int i = 0; i < 4; ++i)
        if (const Index row = unknown_of_point[tet[i]]; row != kInvalidIndex) rhs.row(row) += divergence.row(i);
    }
    for (const Coupling& c : couplings) rhs.row(c.row) -= c.k * result.parameter[c.boundary_point].transpose();
    const Eigen::MatrixXd solution = factor->solve(rhs);
    for (std::size_t i = boundary_count; i < point_count; ++i)
      result.parameter[i] = solution.row(static_cast<Eigen::Index>(unknown_of_point[i])).transpose();
  }
  result.seconds_solve = seconds_since(start);

  // --- 4. untangling of inverted tets (interior points; boundary points only as a last resort).
  start = Clock::now();
  // The tets' parameter volumes: all measured here (in parallel; the count is a sum of
  // integers, the same on any thread count), then after each sweep those of the tets it
  // changed; read by everything but the energy, which measures the tets it moves.
  std::vector<double> volume(tet_count);
  auto measure = [&] {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, tet_count, 4096), std::size_t{0},
        [&](const tbb::blocked_range<std::size_t>& range, std::size_t flipped) {
          for (std::size_t t = range.begin(); t != range.end(); ++t) {
            volume[t] = tet_signed_volume(result.parameter, tets.tets[t]);
            if (!(volume[t] > 0)) ++flipped;
          }
          return flipped;
        },
        std::plus<>());
  };
  result.flipped_before_untangling = measure();
  result.flipped = result.flipped_before_untangling;
  // beta_t, the least volume an untangled tet must have: 1% of its source volume scaled by
  // the ratio of the two solids' volumes (the map may shrink a region a hundredfold).
  std::vector<double> beta(tet_count);
  double source_total = 0, target_total = 0;
  for (std::size_t t = 0; t < tet_count; ++t) {
    beta[t] = std::abs(tet_signed_volume(tets.points, tets.tets[t]));
    source_total += beta[t];
    target_total += volume[t];
  }
  const double volume_ratio = source_total > 0 && target_total > 0 ? target_total / source_total : 1.0;
  for (double& b : beta) b *= 0.01 * volume_ratio;
  if (result.flipped > 0 && options.untangle_sweeps > 0) {
    const CompressedRows tets_of_point = build_vertex_elements(tets.tets, point_count);
    // The energy at x for `point`, and (if asked) the Gauss-Newton normal equations of the
    // active tets (V < beta): rows dV/dx, residuals beta - V.
    auto untangle_energy = [&](Index point, const Vec3& x, Eigen::Matrix3d* normal, Vec3* rhs) {
      double energy = 0;
      if (normal) normal->setZero(), rhs->setZero();
      for (Index t : tets_of_point.row(point)) {
        std::array<Vec3, 4> p;
        int local = 0;
        for (int c = 0; c < 4; ++c) {
          p[c] = tets.tets[t][c] == point ? x : result.parameter[tets.tets[t][c]];
          if (tets.tets[t][c] == point) local = c;
        }
        const double volume = tet_signed_volume(p[0], p[1], p[2], p[3]);
        if (volume >= beta[t]) continue;
        const double gap = beta[t] - volume;  // (|V - b| - (V - b)) = 2 (b - V) when V < b
        energy += 4 * gap * gap;
        if (normal) {
          // dV/dx for the moving corner: minus the outward area vector of the opposite face / 3.
          const auto& face = kTetFaces[static_cast<std::size_t>(local)];
          const Vec3 dv = -(p[face[1]] - p[face[0]]).cross(p[face[2]] - p[face[0]]) / 6.0;
          *normal += dv * dv.transpose();
          *rhs += gap * dv;
        }
      }
      return energy;
    };
    // A point is active while one of its tets is below its least volume (`low`). After the
    // first full measure only the tets of the points a sweep moved are measured again, and
    // the active points are kept as a sorted list: on the bunny at 80k hexes (300 sweeps,
    // 4,000 active points each of 280k) measuring every tet and point per sweep was 5 of
    // the 9 s of the untangling.
    std::vector<std::uint8_t> low(tet_count, 0);
    std::vector<std::uint32_t> low_tets_of(point_count, 0);  // per point: how many of its tets are low
    std::vector<Index> active;                               // points with a low tet, ascending
    for (std::size_t t = 0; t < tet_count; ++t)
      if (!(volume[t] > beta[t])) {
        low[t] = 1;
        for (const Index v : tets.tets[t]) ++low_tets_of[v];
      }
    for (std::size_t v = 0; v < point_count; ++v)
      if (low_tets_of[v] > 0) active.push_back(static_cast<Index>(v));
    std::vector<Index> moved, touched_tets, next_active;
    std::vector<double> new_volume;
    std::vector<std::uint32_t> touched_at(tet_count, 0);
    std::uint32_t sweep_stamp = 0;
    // Measures the tets of the moved points again; returns the change in the flipped count.
    auto remeasure_moved = [&] {
      ++sweep_stamp;
      touched_tets.clear();
      for (const Index v : moved)
        for (const Index t : tets_of_point.row(v))
          if (touched_at[t] != sweep_stamp) touched_at[t] = sweep_stamp, touched_tets.push_back(t);
      std::ptrdiff_t change = 0;
      next_active = active;
      // The new volumes in parallel, then their bookkeeping in order.
      new_volume.resize(touched_tets.size());
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, touched_tets.size(), 4096), [&](const auto& range) {
        for (std::size_t k = range.begin(); k != range.end(); ++k)
          new_volume[k] = tet_signed_volume(result.parameter, tets.tets[touched_tets[k]]);
      });
      for (std::size_t k = 0; k < touched_tets.size(); ++k) {
        const Index t = touched_tets[k];
        const bool was_flipped = !(volume[t] > 0);
        volume[t] = new_volume[k];
        change += static_cast<std::ptrdiff_t>(!(volume[t] > 0)) - static_cast<std::ptrdiff_t>(was_flipped);
        const std::uint8_t now_low = !(volume[t] > beta[t]) ? 1 : 0;
        if (now_low == low[t]) continue;
        low[t] = now_low;
        for (const Index v : tets.tets[t]) {
          if (now_low && low_tets_of[v]++ == 0) next_active.push_back(v);
          if (!now_low) --low_tets_of[v];
        }
      }
      std::sort(next_active.begin(), next_active.end());
      next_active.erase(std::unique(next_active.begin(), next_active.end()), next_active.end());
      std::erase_if(next_active, [&](Index v) { return low_tets_of[v] == 0; });
      active.swap(next_active);
      return change;
    };
    std::optional<Progress> progress;
    if (options.progress) progress.emplace("untangling the map", static_cast<std::uint64_t>(options.untangle_sweeps));
    int stuck_sweeps = 0;
    std::vector<std::uint8_t> released(boundary_count, 0);
    std::size_t fewest_flipped = result.flipped;
    int since_fewest = 0;
    // One point's move; true if it moved.
    auto untangle_point = [&](Index point) {
      const std::size_t v = point;
      Eigen::Matrix3d normal;
      Vec3 rhs;
      const double energy = untangle_energy(point, result.parameter[v], &normal, &rhs);
      if (!(energy > 0)) return false;
      // Gauss-Newton (the energy is a sum of squares of functions linear in the point),
      // damped, with backtracking; the volumes are linear in x, so a full step solves the
      // active set's least squares exactly.
      const double damping = 1e-6 * normal.trace() + 1e-300;
      Vec3 step = (normal + damping * Eigen::Matrix3d::Identity()).ldlt().solve(rhs);
      if (!step.allFinite()) return false;
      for (int attempt = 0; attempt < 30; ++attempt, step *= 0.5) {
        const Vec3 candidate = result.parameter[v] + step;
        if (untangle_energy(point, candidate, nullptr, nullptr) < energy) {
          result.parameter[v] = candidate;
          return true;
        }
      }
      return false;
    };
    // A sweep is Gauss-Seidel over the active points in ascending order, run in wavefronts
    // with the same result: a point's level is one more than the highest level of the points
    // before it in that order that share a tet with it (its edge neighbours), so each point
    // reads its neighbours as the serial sweep would (those before it moved, those after it
    // not yet), and the points of a level, sharing no tet, move in parallel. The closed dog's
    // map: 300 sweeps of about 5,000 points in about 30 levels each.
    const CompressedRows neighbours = build_vertex_neighbors(build_edges(tets), point_count);
    std::vector<std::uint32_t> level_of(point_count, 0), level_stamp(point_count, 0);
    std::vector<Index> schedule, by_level, level_start, level_next;
    std::vector<std::uint8_t> moved_flag(point_count, 0);  // per point: moved in this sweep
    for (int sweep = 0; sweep < options.untangle_sweeps && result.flipped > 0; ++sweep) {
      moved.clear();
      schedule.clear();
      std::uint32_t levels = 0;
      const auto stamp = static_cast<std::uint32_t>(sweep + 1);
      for (const Index point : active) {
        if (point < boundary_count && !released[point]) continue;
        std::uint32_t level = 0;
        for (const Index u : neighbours.row(point))
          if (level_stamp[u] == stamp) level = std::max(level, level_of[u] + 1);
        level_of[point] = level;
        level_stamp[point] = stamp;
        levels = std::max(levels, level + 1);
        schedule.push_back(point);
      }
      // The points by level (a counting sort, ascending within a level).
      level_start.assign(levels + 1, 0);
      for (const Index point : schedule) ++level_start[level_of[point] + 1];
      for (std::uint32_t l = 0; l < levels; ++l) level_start[l + 1] += level_start[l];
      level_next.assign(level_start.begin(), level_start.end() - 1);
      by_level.resize(schedule.size());
      for (const Index point : schedule) by_level[level_next[level_of[point]]++] = point;
      for (std::uint32_t l = 0; l < levels; ++l) {
        const std::size_t begin = level_start[l], end = level_start[l + 1];
        if (end - begin < kSerialLevel) {
          for (std::size_t k = begin; k < end; ++k) moved_flag[by_level[k]] = untangle_point(by_level[k]);
        } else {
          tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, kLevelGrain), [&](const auto& range) {
            for (std::size_t k = range.begin(); k != range.end(); ++k)
              moved_flag[by_level[k]] = untangle_point(by_level[k]);
          });
        }
      }
      for (const Index point : schedule)
        if (moved_flag[point]) moved.push_back(point);
      const std::size_t flipped_before = result.flipped;
      result.flipped = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(result.flipped) + remeasure_moved());
      if (progress) progress->advance();
      // Stuck: no interior point alone can unfold what is left (the boundary faces around
      // it pin it where the target folds tightly). As a last resort the boundary points of
      // the flipped tets are released and move like interior ones: the map's boundary then
      // leaves the target by a little there (the caller reads the boundary back from
      // `parameter`).
      if (result.flipped >= flipped_before && ++stuck_sweeps >= 3) {
        for (std::size_t t = 0; t < tet_count; ++t)
          if (!(volume[t] > 0))
            for (Index v : tets.tets[t])
              if (v < boundary_count && !released[v]) released[v] = 1, ++result.released_boundary_points;
        stuck_sweeps = 0;
      }
      // Gauss-Seidel unfolds a large folded region slowly (fertility: 3,311 flipped, 258
      // after 100 sweeps, 37 after 700), so the sweeps go on while they gain: until 50 in a
      // row have not lowered the fewest flipped tets seen.
      if (result.flipped < fewest_flipped)
        fewest_flipped = result.flipped, since_fewest = 0;
      else if (++since_fewest >= 50)
        break;
    }
  }
  result.seconds_untangle = seconds_since(start);

  if (result.flipped == 0) {
    TetMesh image{result.parameter, tets.tets};
    result.volume_distortion = volume_distortion(tets, image);
  }
  return result;
}

}  // namespace structmesh
