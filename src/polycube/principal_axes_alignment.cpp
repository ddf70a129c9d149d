// principal_axes_alignment(): the pre-alignment of §4.3 ("we heuristically compute
// three principal axes [105] of the given model and pre-align principal axes with the
// global X, Y, Z axes"), so that the rotation-driven deformation does not depend on how
// the model happens to be posed (Fig. 4.2).
//
// Written here rather than taken from a library: the moments are a dozen lines over
// signed tetrahedra and the eigen-decomposition is Eigen's; what no Debian package
// provides is the part that matters for a polycube, a deterministic choice of signs and
// of the frame inside a repeated eigenvalue (a cube or a sphere must not be turned by
// whatever basis the solver happens to return).
#include "polycube/solid_moments.hpp"
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace structmesh {

RigidAlignment principal_axes_alignment(const TriMesh& surface) {
  if (surface.triangles.empty()) throw InputError("principal axes: the surface has no triangles");
  const polycube_detail::SolidMoments moments = polycube_detail::solid_moments(surface.points, surface.triangles);
  const double diagonal = surface.bounding_box().diagonal();
  if (!(std::abs(moments.volume) > 1e-12 * diagonal * diagonal * diagonal))
    throw InputError("principal axes: the surface bounds no volume (signed volume " + std::to_string(moments.volume) +
                     "); is it closed?");

  // The variance along a unit direction u is u^T C u, so the eigenvectors of the
  // covariance C ordered by decreasing eigenvalue are the axes of largest extent first.
  // (The inertia tensor has the same eigenvectors in the reverse order.)
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(moments.covariance);
  if (solver.info() != Eigen::Success) throw Error("principal axes: the eigen-decomposition failed");
  const Eigen::Vector3d ascending = solver.eigenvalues();
  Eigen::Matrix3d axes;  // column k goes to coordinate axis k
  Eigen::Vector3d variances;
  for (int k = 0; k < 3; ++k) {
    axes.col(k) = solver.eigenvectors().col(2 - k);
    variances[k] = ascending[2 - k];
  }

  // Sign and frame rule: of the rotations R with R C R^T diagonal and decreasing, take
  // the one nearest the identity (largest trace, i.e. smallest rotation angle), so a
  // model already posed along its principal axes is left alone. Eigenvalues equal up to
  // rounding (1e-9 of the largest) form one eigenspace, inside which any orthonormal
  // frame is principal; the nearest one to the target axes is the orthogonal Procrustes
  // solution W = A B^T of P^T E = A S B^T (P the eigenspace's basis, E its target axes).
  // A single eigenvector is the one-dimensional case: its sign. If the result is a
  // reflection, the direction of smallest singular value over all eigenspaces (the
  // cheapest in trace) is negated.
  const double equal = 1e-9 * std::max(std::abs(variances[0]), 1e-300);
  std::vector<std::array<int, 2>> groups;  // [first axis, end) of each eigenspace
  for (int k = 0; k < 3;) {
    int end = k + 1;
    while (end < 3 && variances[end - 1] - variances[end] <= equal) ++end;
    groups.push_back({k, end});
    k = end;
  }
  Eigen::Matrix3d frame = Eigen::Matrix3d::Zero();
  double cheapest = 0;
  std::array<int, 2> cheapest_group{-1, -1};
  Eigen::Vector3d cheapest_direction = Eigen::Vector3d::Zero();
  for (const auto& group : groups) {
    const auto [begin, end] = group;
    const int d = end - begin;
    const Eigen::MatrixXd basis = axes.middleCols(begin, d);
    const Eigen::MatrixXd overlap = basis.middleRows(begin, d).transpose();  // P^T E
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(overlap, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::MatrixXd best = basis * (svd.matrixU() * svd.matrixV().transpose());
    frame.middleCols(begin, d) = best;
    const double smallest = svd.singularValues()[d - 1];
    if (cheapest_group[0] < 0 || smallest < cheapest) {
      cheapest = smallest;
      cheapest_group = group;
      cheapest_direction = basis * svd.matrixU().col(d - 1);
    }
  }
  if (frame.determinant() < 0) {
    // Negating the component of the group's frame along its weakest direction u:
    // (I - 2 u u^T) maps the frame to the best reflection-free one of that group.
    const Eigen::Matrix3d flip =
        Eigen::Matrix3d::Identity() - 2.0 * cheapest_direction * cheapest_direction.transpose();
    const auto [begin, end] = cheapest_group;
    frame.middleCols(begin, end - begin) = flip * frame.middleCols(begin, end - begin);
  }

  RigidAlignment alignment;
  alignment.rotation = frame.transpose();  // maps frame column k to axis k
  alignment.centre = moments.centroid;
  return alignment;
}

}  // namespace structmesh
