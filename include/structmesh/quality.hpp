// Mesh quality measures of §3.4.3 and §5.3 of the dissertation, with Verdict's
// definitions (the library inside VTK's vtkMeshQuality, which ParaView, HexaLab
// and the published comparisons use), so our numbers compare with other tools.
#pragma once

#include "structmesh/mesh.hpp"

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

namespace structmesh {

/// Verdict's quad scaled Jacobian (quad_scaled_jacobian, VTK 9.1's vtkMeshQuality
/// QuadScaledJacobian): the minimum over the 4 corners of the corner Jacobian (cross
/// product of the two corner edges, projected on the unit reference normal) divided
/// by the two edge lengths. Verdict's special cases are kept:
///  - a quad whose node 3 coincides with node 2 (exactly) is a triangle: the result
///    is the triangle scaled Jacobian of nodes 0, 1, 2 (|cross| * 2/sqrt(3) divided by
///    the largest product of two edge lengths), which is never negative in Verdict;
///  - any other zero-length edge (shorter than 1e-30, an absolute threshold) gives 0.
/// Without `reference_normal` the normal is Verdict's: the cross product of the
/// quad's two principal axes, i.e. the direction of the diagonals' cross product
/// (the vector area), so a quad's own orientation never makes it negative; only a
/// non-convex or twisted corner does. For a planar mesh pass +z: a clockwise
/// (flipped) quad is then negative, which is what "inverted" means in 2D. In the
/// z = 0 plane this differs from Verdict only for quads whose vector area points to
/// -z (clockwise quads, and bow-ties that are mostly clockwise) or vanishes (a
/// symmetric bow-tie, 0 in Verdict, negative with +z); a collapsed quad then takes
/// the sign of its triangle's normal along the reference. A zero reference normal is
/// ignored (Verdict's normal is used).
double quad_scaled_jacobian(const std::array<Vec3, 4>& corners, const Vec3* reference_normal = nullptr);

/// Verdict's hex_scaled_jacobian: minimum over the 8 corner samples and the
/// centre sample built from the three principal axes (VTK node order).
/// Returns std::nullopt for an invalid hex (an edge or principal axis with squared
/// length <= 1e-30, Verdict's absolute threshold, where Verdict returns
/// VERDICT_DBL_MAX = 1e30): such a hex is not "perfect".
std::optional<double> hex_scaled_jacobian(const std::array<Vec3, 8>& corners);
/// The minimum over the 8 corner samples only (the dissertation's zeta of §5.3).
/// Invalid exactly when hex_scaled_jacobian is, so both variants mark the same hexes.
std::optional<double> hex_corner_scaled_jacobian(const std::array<Vec3, 8>& corners);

/// The samples of hex_scaled_jacobian one at a time, for a smoother that moves one point of a
/// hex and evaluates again only the samples that depend on it (the centre and 4 of the 8
/// corners; hex_smoothing's inner loop). Inline because that loop is the hot spot of the hex
/// pipeline; hex_scaled_jacobian() is built from them, so both give the same bits.
namespace hex_jacobian_sample {

/// Verdict's VERDICT_DBL_MIN: its zero-length tests are absolute, not relative to the
/// element size; we keep them so that "invalid" means what it means in Verdict.
inline constexpr double kDegenerateSquaredLength = 1.0e-30;

/// Corner sample c is det(p[i]-p[c], p[j]-p[c], p[k]-p[c]) for {c, i, j, k} = kCorners[c],
/// ordered so that it is positive for a VTK-ordered hex (Verdict's J(0,0,0) ... J(0,1,1)).
inline constexpr std::array<std::array<int, 4>, 8> kCorners{
    {{0, 1, 3, 4}, {1, 2, 0, 5}, {2, 3, 1, 6}, {3, 0, 2, 7}, {4, 7, 5, 0}, {5, 4, 6, 1}, {6, 5, 7, 2}, {7, 6, 4, 3}}};

/// The sign of each node in the principal axes of the centre sample: X = (1+2+5+6) -
/// (0+3+4+7), Y = (2+3+6+7) - (0+1+4+5), Z = (4+5+6+7) - (0+1+2+3).
inline constexpr std::array<std::array<double, 3>, 8> kAxisSigns{
    {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}}};

/// The 4 corner samples that use point l (its own and its 3 neighbours'); the other 4 do not
/// change when l moves.
inline constexpr std::array<std::array<int, 4>, 8> kCornersUsing{
    {{0, 1, 3, 4}, {1, 0, 2, 5}, {2, 1, 3, 6}, {3, 0, 2, 7}, {4, 0, 5, 7}, {5, 1, 4, 6}, {6, 2, 5, 7}, {7, 3, 4, 6}}};

/// det(a, b, c) / (|a| |b| |c|), or nullopt where Verdict returns VERDICT_DBL_MAX.
inline std::optional<double> normalized_determinant(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.squaredNorm(), lb = b.squaredNorm(), lc = c.squaredNorm();
  if (la <= kDegenerateSquaredLength || lb <= kDegenerateSquaredLength || lc <= kDegenerateSquaredLength)
    return std::nullopt;
  return a.dot(b.cross(c)) / std::sqrt(la * lb * lc);
}

/// Corner sample c (0..7).
inline std::optional<double> corner(const std::array<Vec3, 8>& p, int c) {
  const auto& [o, i, j, k] = kCorners[static_cast<std::size_t>(c)];
  return normalized_determinant(p[static_cast<std::size_t>(i)] - p[static_cast<std::size_t>(o)],
                                p[static_cast<std::size_t>(j)] - p[static_cast<std::size_t>(o)],
                                p[static_cast<std::size_t>(k)] - p[static_cast<std::size_t>(o)]);
}

/// The centre sample: the principal axes, each the sum of the 4 parallel edges.
inline std::optional<double> centre(const std::array<Vec3, 8>& p) {
  const Vec3 axis_x = (p[1] + p[2] + p[5] + p[6]) - (p[0] + p[3] + p[4] + p[7]);
  const Vec3 axis_y = (p[2] + p[3] + p[6] + p[7]) - (p[0] + p[1] + p[4] + p[5]);
  const Vec3 axis_z = (p[4] + p[5] + p[6] + p[7]) - (p[0] + p[1] + p[2] + p[3]);
  return normalized_determinant(axis_x, axis_y, axis_z);
}

}  // namespace hex_jacobian_sample

/// The 12 dihedral angles (radians) of a hex, one per edge: pi minus the angle
/// between the outward normals of the two faces sharing the edge. Face normals are
/// the cross product of the face's diagonals, so non-planar faces are handled.
/// Angle k belongs to edge kHexEdges[k]; it is NaN when one of the two faces has a
/// zero normal (parallel diagonals).
std::array<double, 12> hex_dihedral_angles(const std::array<Vec3, 8>& corners);

/// Summary statistics of a set of values; NaN values are skipped (not counted).
struct Statistics {
  std::size_t count = 0;
  double min = 0, max = 0, mean = 0, stddev = 0;  // population standard deviation
};
Statistics statistics(const std::vector<double>& values);

/// Histogram over [lo, hi] with `bins` equal bins (values outside are clamped, the
/// value hi falls in the last bin, NaN values are skipped). InputError unless
/// bins >= 1 and lo < hi.
std::vector<std::uint64_t> histogram(const std::vector<double>& values, double lo, double hi, int bins);

struct QuadQuality {
  std::vector<double> scaled_jacobian;  // per quad
  Statistics scaled_jacobian_stats;
  std::vector<std::uint64_t> scaled_jacobian_histogram;  // 20 bins over [-1, 1]
  std::size_t inverted = 0;                              // scaled Jacobian <= 0
  std::size_t singular_vertices = 0;                     // interior vertices of valence != 4
  std::size_t boundary_vertices = 0, interior_vertices = 0;
  bool planar = false;  // all z equal: +z used as reference normal
};
/// Quality of a quad mesh. Planar meshes (all z equal) use +z as reference normal.
QuadQuality quad_quality(const QuadMesh& mesh);

/// Singular vertices per part (parts given per quad); index = part id, size = largest
/// id + 1. A singular vertex of the whole mesh (as counted by quad_quality) belongs to
/// the smallest part id among its quads, so the counts add up to the mesh's total.
/// InputError if part_of_quad does not have one non-negative id per quad.
std::vector<std::size_t> singular_vertices_per_part(const QuadMesh& mesh,
                                                    const std::vector<std::int32_t>& part_of_quad);

struct HexQuality {
  std::vector<double> scaled_jacobian;         // per hex, Verdict 9-sample; NaN if invalid
  std::vector<double> corner_scaled_jacobian;  // per hex, 8 corners only; NaN if invalid
  Statistics scaled_jacobian_stats;            // over valid hexes
  Statistics corner_scaled_jacobian_stats;
  std::vector<std::uint64_t> scaled_jacobian_histogram;  // 20 bins over [-1, 1]
  Statistics dihedral_degrees;                           // all 12 angles of every valid hex
  std::size_t inverted = 0;                              // scaled Jacobian <= 0
  std::size_t invalid = 0;                               // zero-length edge or axis
  std::size_t singular_vertices = 0;                     // N_h of Table 5.2
  std::size_t singular_interior = 0, singular_boundary = 0;
};
HexQuality hex_quality(const HexMesh& mesh);

/// Two-sided Hausdorff distance between two triangle surfaces,
/// max(sup_{a in A} d(a, B), sup_{b in B} d(b, A)), estimated from samples: every
/// triangle of each surface is sampled on rows parallel to its longest edge with
/// spacing h = sampling_ratio * (bbox diagonal of `reference`), including its
/// vertices, and each sample's exact distance to the other surface (closest point on
/// its triangles, CGAL AABB tree) is taken. Every point of a surface lies within
/// sqrt(5)/2 * h of a sample and d(., B) is 1-Lipschitz, so the true distance lies in
/// [distance, distance + tolerance] with tolerance = sqrt(5)/2 * h. About area / h^2
/// samples per surface. InputError if a surface has no triangles or
/// sampling_ratio <= 0.
struct HausdorffResult {
  double distance = 0;
  double relative = 0;   // distance / bbox diagonal of reference (D_g, §5.3)
  double tolerance = 0;  // upper bound of the sampling error (see above)
  std::size_t samples = 0;
  /// samples whose closest point was looked up; the others lie too near one that was, by
  /// the distance's 1-Lipschitz bound, to raise the maximum
  std::size_t queried_samples = 0;
};
HausdorffResult hausdorff_distance(const TriMesh& reference, const TriMesh& other, double sampling_ratio = 1e-3);

/// Volume distortion D_v of §5.3 between a tet mesh and its image (same tets,
/// other point positions): (1/|T|) (V_t / V_s) sum_i v_s^i / v_t^i, with v the absolute
/// tet volumes and V their sums. Identical and uniformly scaled images give 1.
/// InputError if the tet counts differ, if there are no tets, or if a tet has zero
/// volume in either mesh or opposite signs in the two (the map flattens or inverts
/// it and D_v is undefined). Meshes in the other orientation convention (all volumes
/// negative in both) are accepted.
double volume_distortion(const TetMesh& source, const TetMesh& target);

/// Signed volume of a tet (positive for VTK order).
double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// The same for the tet `tet` with its corners in `points` (a mesh's, or a map's image).
inline double tet_signed_volume(const std::vector<Vec3>& points, const std::array<Index, 4>& tet) {
  return tet_signed_volume(points[tet[0]], points[tet[1]], points[tet[2]], points[tet[3]]);
}

}  // namespace structmesh
