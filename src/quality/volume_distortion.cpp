// Volume distortion D_v of §5.3 (Table 5.2): how unevenly a volumetric map (the
// polycube parameterization) scales the tets of the source mesh.
#include "structmesh/error.hpp"
#include "structmesh/quality.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <string>

namespace structmesh {

namespace {

std::string format_volume(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

}  // namespace

double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

double volume_distortion(const TetMesh& source, const TetMesh& target) {
  if (source.tets.size() != target.tets.size())
    throw InputError("volume distortion: the source has " + std::to_string(source.tets.size()) +
                     " tets but the image has " + std::to_string(target.tets.size()) +
                     "; D_v compares the same tets at two positions");
  if (source.tets.empty()) throw InputError("volume distortion: the meshes have no tets");
  const auto volume = [](const TetMesh& mesh, std::size_t t) {
    const auto& c = mesh.tets[t];
    return tet_signed_volume(mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]], mesh.points[c[3]]);
  };
  // Sequential sums in tet order: the result is reproducible bit for bit.
  double total_source = 0, total_target = 0, ratio_sum = 0;
  for (std::size_t t = 0; t < source.tets.size(); ++t) {
    const double vs = volume(source, t), vt = volume(target, t);
    if (vs == 0 || vt == 0 || (vs > 0) != (vt > 0))
      throw InputError("volume distortion: tet " + std::to_string(t) + " has volume " + format_volume(vs) +
                       " in the source and " + format_volume(vt) +
                       " in the image; D_v needs a map that neither flattens nor inverts a tet");
    total_source += std::abs(vs);
    total_target += std::abs(vt);
    ratio_sum += vs / vt;
  }
  // (1/|T|) (V_t / V_s) sum_i v_s^i / v_t^i: the mean ratio of each tet's share of
  // the source volume to its share of the image volume.
  return total_target / total_source * ratio_sum / static_cast<double>(source.tets.size());
}

}  // namespace structmesh
