// pseudo_polycube(): the rotation-driven pre-deformation of §4.3 (after Gregson,
// Sheffer and Zhang 2011, "All-hex mesh generation via volumetric polycube deformation",
// here on the surface alone), which turns the model into the pseudo-polycube Q that
// §4.4 voxelizes.
//
// Written by hand: no Debian package provides a polycube deformation (libigl, which has
// the building blocks, is not in Debian; CGAL has none). Eigen supplies the quaternions
// and the sparse Cholesky factorization, check_surface()'s exact predicates the
// intersection guard.
//
// Each iteration, on the current surface:
//  1. every triangle gets the minimal rotation taking its normal to its nearest axis
//     (Eigen::Quaterniond::FromTwoVectors), capped at kMaxStepDegrees;
//  2. the rotation field is smoothed once (each triangle's quaternion averaged with its
//     three edge neighbours', as Gregson et al. smooth theirs) so that single noisy
//     triangles do not pull against their chart;
//  3. the Poisson system of §4.3 is solved in the least-squares sense over the edges,
//     x_a - x_b ~ (R_f + R_g)/2 (x~_a - x~_b), where f and g are the edge's two triangles
//     and x~ the positions at the start of the iteration;
//  4. the intersection guard: triangles that now cross another (or overlap a
//     neighbour) have their vertices and their one-ring frozen at the previous
//     positions, and the check is repeated until the surface is clean, so Q is as valid a
//     solid boundary as the input;
//  5. a similarity about the centroid restores the input's volume and centroid.
// It stops after max_iterations or when the mean normal deviation changes by less than
// the tolerance.
//
// Choices, each measured with everything else as it is here (mean normal deviation in
// degrees on an icosphere of 2,562 vertices / a torus / the kitten / the rocker arm,
// from 31.9 / 28.1 / 30.9 / 21.2; these: 0.8 / 0.6 / 2.4 / 2.2):
//  - Rotations on triangles, not vertices. §4.3 writes R_i for the rotation of vertex
//    i's normal and (R_i + R_j)/2 on the edge. A vertex on a crease between two flat
//    charts has a normal halfway between two axes, so its "rotation to the nearest axis"
//    stays near 45 degrees however flat both sides already are, and the edges around it
//    are dragged forever: with vertex rotations (vertex normals area-weighted, smoothed
//    over the one-ring) it ends at 8.4 / 9.3 / 7.4 / 14.4. With the rotation of each
//    triangle and the mean of the edge's two, a polycube is an exact fixed point (every
//    R = I). It is the same Poisson equation with the rotations carried by the elements,
//    as in Gregson et al.'s volumetric version, where they live on the tetrahedra.
//  - Rotations accumulate through the positions: each iteration rotates the current
//    differential coordinates (x~ = the positions at its start), so the only fixed point
//    is "every normal on its axis". The alternative, the input's coordinates under an
//    accumulated rotation (each triangle's fitted rotation from the input to now, times
//    the new step), holds on to the input's edge lengths, which a polycube cannot keep:
//    3.0 / 4.4 / 11.5 / 8.7, and the torus gets 14 charts (4 wedges) instead of 10.
//  - Uniform weights (the 1/|N_i| of §4.3 multiplied through to a symmetric matrix):
//    with R = I the least squares reproduces the surface exactly whatever the weights,
//    so they only decide how the incompatible part is spread; uniform weights are
//    positive on any mesh (cotangent weights go negative on obtuse triangles, of which
//    the rocker arm has many) and depend on the connectivity alone, so the matrix is
//    factored once (SimplicialLDLT) and again only when frozen vertices accumulate.
//  - The translation null space is removed by fixing one vertex per connected component
//    (its lowest index); the similarity of step 5 then puts the centroid back.
//  - Steps of at most 15 degrees: the first iteration would otherwise turn a sphere's
//    triangles by up to 55 degrees at once; smaller steps fold fewer triangles (fewer
//    frozen vertices: the kitten ends at 2.4 rather than 3.0) and keep the torus at its
//    10 charts (26 with unbounded steps).
#include "polycube/crossing_triangles.hpp"
#include "polycube/solid_moments.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/polycube.hpp"
#include "structmesh/progress.hpp"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace structmesh {

namespace {

constexpr double kDegrees = 180.0 / std::numbers::pi;
/// The largest rotation a triangle is given in one iteration.
constexpr double kMaxStepDegrees = 15;
/// Frozen vertices are moved back after each solve; the matrix is refactored (so the
/// solve itself respects them) once this share of the vertices has been frozen since.
constexpr double kRefactorShare = 0.01;
/// Rounds of freezing within one iteration before it is given up (each round freezes at
/// least one more vertex, so this only bounds pathological cases).
constexpr int kMaxGuardRounds = 50;

Index find_root(std::vector<Index>& parent, Index v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

void unite(std::vector<Index>& parent, Index a, Index b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a == b) return;
  if (b < a) std::swap(a, b);
  parent[b] = a;  // the lowest index is the root
}

void check_deformable(const TriMesh& surface) {
  if (surface.triangles.empty()) throw InputError("pseudo-polycube: the surface has no triangles");
  const SurfaceReport report = check_surface(to_bundle(surface));
  if (report.valid_solid_boundary) return;
  throw InputError("pseudo-polycube: the surface does not bound a solid:" + solid_boundary_problems(report));
}

// Twice the area times the unit normal of each triangle.
void triangle_normals(const std::vector<Vec3>& points, const std::vector<std::array<Index, 3>>& triangles,
                      std::vector<Vec3>& normals) {
  normals.resize(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& [a, b, c] = triangles[t];
    normals[t] = (points[b] - points[a]).cross(points[c] - points[a]);
  }
}

double mean_deviation_degrees(const std::vector<Vec3>& normals) {
  double sum = 0, area = 0;
  for (const Vec3& n : normals) {
    const double length = n.norm();
    if (length == 0) continue;
    const Vec3 axis = axis_of_label(nearest_axis_label(n));
    sum += length * std::acos(std::clamp(n.dot(axis) / length, -1.0, 1.0));
    area += length;
  }
  return area > 0 ? sum / area * kDegrees : 0.0;
}

// The Poisson system of §4.3 in least-squares form over the edges, with uniform
// weights: sum_ij |x_i - x_j - t_ij|^2 for edge targets t_ij, whose normal equations are
// the graph Laplacian (the 1/|N_i| of §4.3 multiplied through). Fixed vertices (one per
// component, which removes the translation from the null space, and the vertices frozen
// by the intersection guard) keep their positions and move to the right-hand side. The
// matrix depends on the connectivity and the fixed set only, so it is factored once and
// again only when the fixed set grows.
class PoissonSolver {
 public:
  void factor(const std::vector<std::array<Index, 2>>& edges, const std::vector<std::uint8_t>& fixed) {
    unknown_.assign(fixed.size(), -1);
    int unknowns = 0;
    for (std::size_t v = 0; v < fixed.size(); ++v)
      if (!fixed[v]) unknown_[v] = unknowns++;
    std::vector<Eigen::Triplet<double>> entries;
    for (const auto& [a, b] : edges) {
      const int ia = unknown_[a], ib = unknown_[b];
      if (ia >= 0) entries.emplace_back(ia, ia, 1.0);
      if (ib >= 0) entries.emplace_back(ib, ib, 1.0);
      if (ia >= 0 && ib >= 0) {
        entries.emplace_back(ia, ib, -1.0);
        entries.emplace_back(ib, ia, -1.0);
      }
    }
    Eigen::SparseMatrix<double> laplacian(unknowns, unknowns);
    laplacian.setFromTriplets(entries.begin(), entries.end());
    solver_.compute(laplacian);
    if (solver_.info() != Eigen::Success) throw Error("pseudo-polycube: the Laplacian could not be factored");
  }

  /// Positions minimising the edge least squares for targets[e] ~ x_a - x_b of edge
  /// e = (a, b); fixed vertices are taken from `points`.
  void solve(const std::vector<std::array<Index, 2>>& edges, const std::vector<Vec3>& targets,
             const std::vector<Vec3>& points, std::vector<Vec3>& result) {
    rhs_.setZero(solver_.rows(), 3);
    for (std::size_t e = 0; e < edges.size(); ++e) {
      const auto [a, b] = edges[e];
      const int ia = unknown_[a], ib = unknown_[b];
      if (ia >= 0) rhs_.row(ia) += (ib >= 0 ? targets[e] : Vec3(targets[e] + points[b])).transpose();
      if (ib >= 0) rhs_.row(ib) -= (ia >= 0 ? targets[e] : Vec3(targets[e] - points[a])).transpose();
    }
    const Eigen::MatrixXd solution = solver_.solve(rhs_);
    result = points;
    for (std::size_t v = 0; v < points.size(); ++v)
      if (unknown_[v] >= 0) result[v] = solution.row(unknown_[v]).transpose();
  }

 private:
  std::vector<int> unknown_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
  Eigen::MatrixXd rhs_;
};

// The similarity p -> centroid + scale (p - from) that gives a surface the input's
// volume and centroid (§4.3's deformation is to change the shape, not the size).
struct Similarity {
  double scale = 1;
  Vec3 from = Vec3::Zero(), centroid = Vec3::Zero();
  Vec3 operator()(const Vec3& p) const { return centroid + scale * (p - from); }
};
Similarity restoring_volume(const polycube_detail::SolidMoments& input, const std::vector<Vec3>& points,
                            const std::vector<std::array<Index, 3>>& triangles) {
  const polycube_detail::SolidMoments now = polycube_detail::solid_moments(points, triangles);
  return {now.volume > 0 ? std::cbrt(input.volume / now.volume) : 1.0, now.centroid, input.centroid};
}

// Labels, charts and wedges (§4.3) of the triangles with these normals.
void label_charts(const std::vector<Vec3>& normals, const std::vector<std::array<Index, 2>>& edge_triangles,
                  PseudoPolycube& result) {
  const std::size_t triangle_count = normals.size();
  result.labels.resize(triangle_count);
  for (std::size_t t = 0; t < triangle_count; ++t) result.labels[t] = nearest_axis_label(normals[t]);
  std::vector<Index> chart_parent(triangle_count);
  std::iota(chart_parent.begin(), chart_parent.end(), Index{0});
  for (const auto& [f, g] : edge_triangles)
    if (result.labels[f] == result.labels[g]) unite(chart_parent, f, g);
  std::vector<Index> chart_of(triangle_count);
  for (Index t = 0; t < triangle_count; ++t) chart_of[t] = find_root(chart_parent, t);
  std::set<std::pair<Index, Index>> adjacent;  // ordered pairs of adjacent charts (by root)
  for (const auto& [f, g] : edge_triangles) {
    if (chart_of[f] == chart_of[g]) continue;
    adjacent.emplace(chart_of[f], chart_of[g]);
    adjacent.emplace(chart_of[g], chart_of[f]);
  }
  std::vector<int> neighbour_charts(triangle_count, 0);
  std::vector<std::uint8_t> opposite(triangle_count, 0);
  for (const auto& [a, b] : adjacent) {
    ++neighbour_charts[a];
    if ((result.labels[a] ^ 1) == result.labels[b]) opposite[a] = 1;  // +X/-X etc. differ in the last bit
  }
  result.charts = result.wedges = 0;
  for (Index t = 0; t < triangle_count; ++t) {
    if (chart_of[t] != t) continue;
    ++result.charts;
    if (opposite[t] || neighbour_charts[t] < 4) ++result.wedges;
  }
}

}  // namespace

PseudoPolycube pseudo_polycube(const TriMesh& surface, const PseudoPolycubeOptions& options) {
  check_deformable(surface);
  const std::size_t n = surface.points.size();
  const std::size_t triangle_count = surface.triangles.size();
  const auto& triangles = surface.triangles;
  const EdgeAdjacency edges = build_edges(surface);
  const CompressedRows vertex_triangles = build_vertex_elements(triangles, n);
  const std::size_t edge_count = edges.edges.size();
  std::vector<std::array<Index, 2>> edge_triangles(edge_count);  // closed and manifold: two each
  for (std::size_t e = 0; e < edge_count; ++e) {
    const auto faces = edges.edge_elements.row(e);
    edge_triangles[e] = {faces[0], faces[1]};
  }

  // One fixed vertex per connected component (its lowest index) removes the
  // translation from the Laplacian's null space; vertices no triangle uses stay too.
  std::vector<Index> parent(n);
  std::iota(parent.begin(), parent.end(), Index{0});
  for (const auto& [a, b] : edges.edges) unite(parent, a, b);
  std::vector<std::uint8_t> fixed(n, 0);
  for (Index v = 0; v < n; ++v)
    if (find_root(parent, v) == v) fixed[v] = 1;
  const polycube_detail::SolidMoments input_moments = polycube_detail::solid_moments(surface.points, triangles);

  PoissonSolver solver;
  solver.factor(edges.edges, fixed);

  PseudoPolycube result;
  result.surface = surface;
  std::vector<Vec3>& points = result.surface.points;
  std::vector<Vec3> normals;
  triangle_normals(points, triangles, normals);
  result.input_deviation_degrees = mean_deviation_degrees(normals);
  double deviation = result.input_deviation_degrees;
  if (options.progress)
    status("pseudo-polycube: " + std::to_string(n) + " vertices, mean normal deviation " + std::to_string(deviation) +
           " degrees");

  const double max_step = kMaxStepDegrees / kDegrees;
  const auto refactor_after = static_cast<std::size_t>(kRefactorShare * static_cast<double>(n));
  std::size_t frozen_when_factored = 0;
  bool moved_back = false;  // in the last accepted iteration
  std::vector<Eigen::Quaterniond> rotation(triangle_count);
  std::vector<Eigen::Vector4d> rotation_sum(triangle_count);
  std::vector<Eigen::Matrix3d> matrix(triangle_count);
  std::vector<Vec3> targets(edge_count), candidate;
  std::vector<std::uint8_t> marked(triangle_count), next(triangle_count);
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    for (std::size_t t = 0; t < triangle_count; ++t) {
      rotation[t] = Eigen::Quaterniond::Identity();
      if (!(normals[t].norm() > 0)) continue;
      const Eigen::Quaterniond full =
          Eigen::Quaterniond::FromTwoVectors(normals[t], axis_of_label(nearest_axis_label(normals[t])));
      const double angle = 2 * std::acos(std::clamp(full.w(), -1.0, 1.0));
      rotation[t] = angle > max_step ? Eigen::Quaterniond::Identity().slerp(max_step / angle, full) : full;
    }
    // Every rotation is less than 90 degrees, so all quaternions have w > 0 and their
    // normalised sum is a fair average.
    for (std::size_t t = 0; t < triangle_count; ++t) rotation_sum[t] = rotation[t].coeffs();
    for (const auto& [f, g] : edge_triangles) {
      rotation_sum[f] += rotation[g].coeffs();
      rotation_sum[g] += rotation[f].coeffs();
    }
    for (std::size_t t = 0; t < triangle_count; ++t)
      matrix[t] = Eigen::Quaterniond(rotation_sum[t].normalized()).toRotationMatrix();
    for (std::size_t e = 0; e < edge_count; ++e) {
      const auto [a, b] = edges.edges[e];
      const auto [f, g] = edge_triangles[e];
      targets[e] = 0.5 * (matrix[f] + matrix[g]) * (points[a] - points[b]);
    }

    solver.solve(edges.edges, targets, points, candidate);
    for (Index v = 0; v < n; ++v)
      if (fixed[v]) candidate[v] = points[v];  // frozen since the last factorization
    const Similarity similarity = restoring_volume(input_moments, candidate, triangles);
    for (Vec3& p : candidate) p = similarity(p);
    // The guard, on the positions that will be kept, with frozen vertices moved back to
    // their previous positions under the same similarity. Each crossing pair has a
    // triangle with a vertex that moved (the previous surface was clean, and so is its
    // similar image), so every round freezes at least one more vertex.
    std::vector<Index> crossing = polycube_detail::crossing_triangles(candidate, triangles, vertex_triangles);
    const bool reverting = !crossing.empty();
    for (int round = 0; !crossing.empty() && round < kMaxGuardRounds; ++round) {
      std::fill(marked.begin(), marked.end(), 0);
      for (const Index t : crossing) marked[t] = 1;
      next = marked;  // and the triangles around them
      for (std::size_t t = 0; t < triangle_count; ++t)
        if (marked[t])
          for (const Index v : triangles[t])
            for (const Index u : vertex_triangles.row(v)) next[u] = 1;
      for (std::size_t t = 0; t < triangle_count; ++t)
        if (next[t])
          for (const Index v : triangles[t])
            if (!fixed[v]) {
              fixed[v] = 1;
              ++result.frozen_vertices;
              candidate[v] = similarity(points[v]);
            }
      crossing = polycube_detail::crossing_triangles(candidate, triangles, vertex_triangles);
    }
    if (result.frozen_vertices - frozen_when_factored > refactor_after) {
      solver.factor(edges.edges, fixed);
      frozen_when_factored = result.frozen_vertices;
    }
    if (!crossing.empty()) break;  // keep the last clean surface
    points.swap(candidate);
    moved_back = reverting;

    triangle_normals(points, triangles, normals);
    const double previous = deviation;
    deviation = mean_deviation_degrees(normals);
    result.iterations = iteration;
    if (options.progress)
      status("pseudo-polycube: iteration " + std::to_string(iteration) + ", mean normal deviation " +
             std::to_string(deviation) + " degrees, " + std::to_string(result.frozen_vertices) + " vertices frozen");
    if (std::abs(previous - deviation) < options.tolerance_degrees) break;
  }
  // Vertices moved back in the last iteration left the volume slightly off; one more
  // similarity puts it right, unless its rounding makes the surface cross itself (a
  // similar image of a clean surface is clean in exact arithmetic only).
  if (moved_back) {
    const Similarity similarity = restoring_volume(input_moments, points, triangles);
    for (std::size_t v = 0; v < n; ++v) candidate[v] = similarity(points[v]);
    if (polycube_detail::crossing_triangles(candidate, triangles, vertex_triangles).empty()) {
      points.swap(candidate);
      triangle_normals(points, triangles, normals);
      deviation = mean_deviation_degrees(normals);
    }
  }
  result.deviation_degrees = deviation;
  label_charts(normals, edge_triangles, result);
  return result;
}

}  // namespace structmesh
