// Dihedral angles of a hex (§5.3, Table 5.2: average and standard deviation of the
// dihedral angles, ideally all 90 degrees).
#include "structmesh/quality.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <numbers>

namespace structmesh {

namespace {

constexpr bool face_has(const std::array<int, 4>& face, int v) {
  return face[0] == v || face[1] == v || face[2] == v || face[3] == v;
}

// For each of the 12 edges of kHexEdges, the two faces of kHexFaces that share it.
constexpr std::array<std::array<int, 2>, 12> make_edge_faces() {
  std::array<std::array<int, 2>, 12> table{};
  for (std::size_t e = 0; e < kHexEdges.size(); ++e) {
    int found = 0;
    for (std::size_t f = 0; f < kHexFaces.size(); ++f)
      if (face_has(kHexFaces[f], kHexEdges[e][0]) && face_has(kHexFaces[f], kHexEdges[e][1]))
        table[e][found++] = static_cast<int>(f);
  }
  return table;
}
constexpr std::array<std::array<int, 2>, 12> kEdgeFaces = make_edge_faces();

}  // namespace

std::array<double, 12> hex_dihedral_angles(const std::array<Vec3, 8>& p) {
  // The diagonals' cross product is the face's vector area (exact for planar faces,
  // the average normal of a non-planar bilinear face); kHexFaces lists each face
  // counter-clockwise seen from outside, so it points outward.
  std::array<Vec3, 6> normals;
  for (std::size_t f = 0; f < kHexFaces.size(); ++f) {
    const auto& [a, b, c, d] = kHexFaces[f];
    normals[f] = (p[c] - p[a]).cross(p[d] - p[b]);
  }
  std::array<double, 12> angles{};
  for (std::size_t e = 0; e < angles.size(); ++e) {
    const Vec3& n1 = normals[kEdgeFaces[e][0]];
    const Vec3& n2 = normals[kEdgeFaces[e][1]];
    if (n1.squaredNorm() == 0 || n2.squaredNorm() == 0) {
      angles[e] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    // atan2 keeps full precision near 0 and pi, where acos of a dot product does not.
    angles[e] = std::numbers::pi - std::atan2(n1.cross(n2).norm(), n1.dot(n2));
  }
  return angles;
}

}  // namespace structmesh
