// pillow(): one layer of padding under the boundary (the padding step of the chapter-5
// pipeline, see hex.hpp). A polycube hex mesh has hexes with two or three faces on the
// boundary at the polycube's edges and corners, and no smoothing can give them a good scaled
// Jacobian once the boundary is curved; one layer of new hexes between the old boundary and a
// copy of it leaves every hex with at most one boundary face.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <string>

namespace structmesh {

namespace {

// Normals closer than this (cosine) count as one plane: the quads of one polycube face.
constexpr double kSameNormal = 0.999;
// Singular values of the normal matrix below this share of the largest are dropped: the
// normals then span fewer directions (a point inside a face has one, on an edge two), and the
// minimum-norm solution is the offset of those planes alone. Normals a few degrees apart (a
// curved boundary) would otherwise ask for an offset of arbitrary length along their
// ill-determined direction.
constexpr double kSingularShare = 0.1;

// The offset direction m with m . n = 1 for each normal n, least squares (truncated SVD), so
// moving a point by -depth m moves each of its boundary planes inward by depth. Falls back to
// the normalised mean normal where that solution does not point inward through every plane.
Vec3 offset_direction(const std::vector<Vec3>& normals) {
  if (normals.empty()) return Vec3::Zero();
  Eigen::MatrixXd a(static_cast<Eigen::Index>(normals.size()), 3);
  for (std::size_t i = 0; i < normals.size(); ++i) a.row(static_cast<Eigen::Index>(i)) = normals[i].transpose();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  svd.setThreshold(kSingularShare);
  const Vec3 m = svd.solve(Eigen::VectorXd::Ones(a.rows()));
  bool inward = m.allFinite();
  for (const Vec3& n : normals) inward = inward && m.dot(n) > 0;
  if (inward) return m;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& n : normals) mean += n;
  const double length = mean.norm();
  // Normals that cancel out (a non-manifold point) leave no inward direction: the point stays.
  return length > 0 ? Vec3(mean / length) : Vec3::Zero();
}

}  // namespace

HexMesh pillow(const HexMesh& mesh, double depth, std::vector<Index>* copied_from,
               std::vector<std::uint8_t>* is_outer) {
  if (!(depth > 0) || !std::isfinite(depth))
    throw InputError("pillow: the depth must be a positive length, got " + std::to_string(depth));
  const std::vector<std::array<Index, 4>> quads = hex_boundary_quads(mesh);
  const std::size_t n = mesh.points.size();

  // The copy of each boundary point, numbered after the old points in ascending order.
  std::vector<Index> copy(n, kInvalidIndex);
  for (const auto& q : quads)
    for (const Index v : q) copy[v] = 0;
  Index next = static_cast<Index>(n);
  for (std::size_t v = 0; v < n; ++v)
    if (copy[v] == 0) copy[v] = next++;

  // Distinct unit normals per boundary point. A quad's normal is its vector area (the
  // cross product of its diagonals), which is defined for non-planar quads too.
  std::vector<std::vector<Vec3>> normals(n);
  for (const auto& q : quads) {
    const Vec3 area = (mesh.points[q[2]] - mesh.points[q[0]]).cross(mesh.points[q[3]] - mesh.points[q[1]]);
    const double length = area.norm();
    if (!(length > 0)) continue;
    const Vec3 normal = area / length;
    for (const Index v : q) {
      bool seen = false;
      for (const Vec3& other : normals[v]) seen = seen || other.dot(normal) > kSameNormal;
      if (!seen) normals[v].push_back(normal);
    }
  }

  HexMesh result;
  result.points.resize(next);
  result.hexes.reserve(mesh.hexes.size() + quads.size());
  result.hexes.insert(result.hexes.end(), mesh.hexes.begin(), mesh.hexes.end());
  for (std::size_t v = 0; v < n; ++v) {
    result.points[v] = mesh.points[v];
    if (copy[v] == kInvalidIndex) continue;
    result.points[copy[v]] = mesh.points[v];
    result.points[v] -= depth * offset_direction(normals[v]);
  }
  // The quad is outward, so seen from its copy it is counter-clockwise: it is the new hex's
  // bottom (VTK nodes 0-3) and the copy its top, which gives positive corner Jacobians.
  for (const auto& q : quads)
    result.hexes.push_back({q[0], q[1], q[2], q[3], copy[q[0]], copy[q[1]], copy[q[2]], copy[q[3]]});

  if (copied_from) {
    copied_from->resize(next);
    for (std::size_t v = 0; v < n; ++v) {
      (*copied_from)[v] = static_cast<Index>(v);
      if (copy[v] != kInvalidIndex) (*copied_from)[copy[v]] = static_cast<Index>(v);
    }
  }
  if (is_outer) {
    is_outer->assign(next, 0);
    std::fill(is_outer->begin() + static_cast<std::ptrdiff_t>(n), is_outer->end(), std::uint8_t{1});
  }
  return result;
}

}  // namespace structmesh
