// repair_flipped_tets(): the last step of the volumetric map's untangling (§5.2.2): what the
// point-by-point untangling leaves flipped is cut out and re-triangulated as a star.
//
// Why. The untangling moves one point at a time (Knupp's function is convex in a point, so
// each move is that point's best), and a fold whose points hold each other in place stays:
// the remaining flipped tets are squeezed flat (volume -1e-9 beside 1e-7 in the source)
// around boundary edges the surface map stretched 5-20x. Joint untangling (Garanzha et
// al.'s foldover-free energy over rings of the fold) and edge refinement around it both
// left most of them (docs/design/hex.md).
//
// How. A cavity C of tets around a cluster of flipped tets is removed, and one new point s
// is joined to every face of its boundary, in the source (the solid M) and in the parameter
// domain alike. The cone tet on a boundary face is positive exactly where s lies on the inner
// side of the face's plane, so the cone is valid in both domains when s_source lies in the
// kernel of C's boundary in M and s_parameter in the kernel of its image: the boundary is then
// star-shaped from s, and (every face strictly in front of s, the surface closed) it bounds
// a ball that the cone fills once. Each kernel point is the Chebyshev centre of the faces'
// inner half-spaces, an LP of 4 unknowns solved by COIN-OR CLP. The map outside C and on C's
// boundary is unchanged, so the mesh stays conforming and the boundary points keep their
// images. C starts as the cluster's flipped tets and their first vertex ring; while a kernel
// is empty, C grows through the boundary faces in the way (those the point behind the
// fewest faces, found by an LP with a slack per face, is behind), or by a vertex ring when
// none of those can be crossed. A surface face cannot be crossed: an empty kernel that only
// surface faces block means the map's surface itself folds there, and the cluster stays.
//
// The points of C that are not on its boundary stay in the point list, unreferenced.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/quality.hpp"

#include "lp/small_lp.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

namespace structmesh {
namespace {

using Face = std::array<Index, 3>;  // outward from the cavity

// Growth limits. On the bench models every cavity that worked did at its first try (the
// cluster and one vertex ring, up to 82 tets); the clusters that failed failed at every size,
// and growing them 60 steps up to 20,000 tets cost 7-9 s on the bunny, kitten_40k and the dog.
constexpr int kGrowthSteps = 8;
constexpr std::size_t kLargestCavity = 2000;

std::array<Index, 3> sorted_face(const Face& f) {
  std::array<Index, 3> s = f;
  std::sort(s.begin(), s.end());
  return s;
}

struct FaceHash {
  std::size_t operator()(const std::array<Index, 3>& f) const {
    return (static_cast<std::size_t>(f[0]) * 73856093u) ^ (static_cast<std::size_t>(f[1]) * 19349663u) ^
           (static_cast<std::size_t>(f[2]) * 83492791u);
  }
};

/// The boundary faces of the tets `cavity` (each outward from its tet), or empty when that
/// boundary is not a closed 2-manifold (an edge in other than two faces).
std::vector<Face> cavity_boundary(const TetMesh& tets, const std::vector<Index>& cavity) {
  std::unordered_map<std::array<Index, 3>, std::pair<Face, int>, FaceHash> count;
  count.reserve(cavity.size() * 4);
  for (const Index t : cavity)
    for (const auto& f : kTetFaces) {
      const Face face{tets.tets[t][f[0]], tets.tets[t][f[1]], tets.tets[t][f[2]]};
      auto [it, inserted] = count.try_emplace(sorted_face(face), face, 0);
      ++it->second.second;
    }
  std::vector<Face> boundary;
  std::unordered_map<std::uint64_t, int> edge_uses;
  for (const auto& [key, entry] : count) {
    if (entry.second != 1) continue;
    boundary.push_back(entry.first);
    for (int k = 0; k < 3; ++k) {
      Index a = entry.first[k], b = entry.first[(k + 1) % 3];
      if (a > b) std::swap(a, b);
      ++edge_uses[(static_cast<std::uint64_t>(a) << 32) | b];
    }
  }
  for (const auto& [edge, uses] : edge_uses)
    if (uses != 2) return {};
  // A deterministic order (the map's iteration order depends on the hash table's history).
  std::sort(boundary.begin(), boundary.end());
  return boundary;
}

/// The faces' bounding box (the LPs are solved in its frame: centre at the origin, diagonal
/// 1) and, per face in that frame, its plane (outward unit normal n, offset n . first
/// corner); a degenerate face gets n = 0, offset 0 and valid = 0.
struct FacesInBoxFrame {
  Vec3 middle = Vec3::Zero(), box_lo = Vec3::Zero(), box_hi = Vec3::Zero();
  double diagonal = 0;
  std::vector<lp::Plane> planes;
  std::vector<std::uint8_t> valid;

  FacesInBoxFrame(const std::vector<Vec3>& points, const std::vector<Face>& faces) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (const Face& f : faces)
      for (const Index v : f) lo = lo.cwiseMin(points[v]), hi = hi.cwiseMax(points[v]);
    middle = (lo + hi) / 2;
    diagonal = (hi - lo).norm();
    if (!(diagonal > 0)) return;
    box_lo = (lo - middle) / diagonal, box_hi = (hi - middle) / diagonal;
    planes.assign(faces.size(), lp::Plane{Vec3::Zero(), 0.0, 1.0});
    valid.assign(faces.size(), 0);
    for (std::size_t i = 0; i < faces.size(); ++i) {
      const Face& f = faces[i];
      const Vec3 a = (points[f[0]] - middle) / diagonal, b = (points[f[1]] - middle) / diagonal,
                 c = (points[f[2]] - middle) / diagonal;
      const Vec3 n = (b - a).cross(c - a);  // outward
      const double length = n.norm();
      if (!(length > 1e-300)) continue;
      planes[i].normal = n / length, planes[i].offset = planes[i].normal.dot(a), valid[i] = 1;
    }
  }
};

/// The point deepest inside every face's inner half-space (the Chebyshev centre of the kernel
/// of a closed surface), within the faces' box, and its depth; depth <= 0 when the kernel is
/// empty or flat, or a face is degenerate (no point is strictly in front of it).
double kernel_centre(const std::vector<Vec3>& points, const std::vector<Face>& faces, Vec3& centre) {
  const FacesInBoxFrame frame(points, faces);
  if (!(frame.diagonal > 0) || std::find(frame.valid.begin(), frame.valid.end(), 0) != frame.valid.end()) return 0;
  Vec3 at;
  double depth = 0;
  if (!lp::chebyshev_centre(frame.planes, frame.box_lo, frame.box_hi, at, depth)) return 0;
  centre = frame.middle + frame.diagonal * at;
  return depth * frame.diagonal;
}

/// Marks in `violated` the faces that the point in front of the most faces (least total
/// shortfall behind their planes, crossing a face of `crossable` 0 costs 100 times more) is
/// not in front of by a thousandth of the box diagonal. A degenerate face (zero normal) is
/// always in the way: its row forces its shortfall to 1e-3.
void least_violated_faces(const std::vector<Vec3>& points, const std::vector<Face>& faces,
                          const std::vector<std::uint8_t>& crossable, std::vector<std::uint8_t>& violated) {
  FacesInBoxFrame frame(points, faces);
  if (!(frame.diagonal > 0)) return;
  for (std::size_t i = 0; i < faces.size(); ++i) frame.planes[i].weight = crossable[i] ? 1.0 : 100.0;
  Vec3 point;
  std::vector<double> excess;
  if (!lp::least_violating_point(frame.planes, 1e-3, frame.box_lo, frame.box_hi, point, &excess)) return;
  for (std::size_t i = 0; i < faces.size(); ++i)
    if (excess[i] > 1e-9) violated[i] = 1;
}

}  // namespace

FlippedTetRepair repair_flipped_tets(TetMesh& tets, std::vector<Vec3>& parameter, int max_rings) {
  if (parameter.size() != tets.points.size())
    throw InputError("repair_flipped_tets: " + std::to_string(parameter.size()) + " parameter points for " +
                     std::to_string(tets.points.size()) + " points");
  FlippedTetRepair result;
  auto flipped_tets = [&] {
    std::vector<Index> flipped;
    for (std::size_t t = 0; t < tets.tets.size(); ++t)
      if (!(tet_signed_volume(parameter, tets.tets[t]) > 0)) flipped.push_back(static_cast<Index>(t));
    return flipped;
  };
  std::vector<Index> flipped = flipped_tets();
  result.flipped_before = flipped.size();
  // Passes: every cluster's cavity is cut from the mesh as it was at the pass's start, and a
  // cavity that would reach a tet another cavity took this pass waits for the next one.
  for (int pass = 0; pass < 8 && !flipped.empty(); ++pass) {
    const CompressedRows tets_of_point = build_vertex_elements(tets.tets, tets.points.size());
    std::vector<std::uint8_t> taken(tets.tets.size(), 0);       // by a cavity of this pass
    std::vector<std::uint32_t> in_cavity(tets.tets.size(), 0);  // stamp of the cavity being grown
    std::vector<std::uint32_t> point_seen(tets.points.size(), 0);
    std::vector<std::uint8_t> settled(tets.tets.size(), 0);  // flipped tets of a cluster left this pass
    std::uint32_t stamp = 0;
    std::vector<std::array<Index, 4>> cones;
    std::size_t repaired_this_pass = 0;
    for (const Index seed : flipped) {
      if (taken[seed] || settled[seed]) continue;
      // The cluster: the flipped tets joined to the seed through shared points.
      std::vector<Index> cavity{seed};
      ++stamp;
      in_cavity[seed] = stamp;
      for (std::size_t i = 0; i < cavity.size(); ++i)
        for (const Index v : tets.tets[cavity[i]])
          for (const Index t : tets_of_point.row(v))
            if (in_cavity[t] != stamp && !(tet_signed_volume(parameter, tets.tets[t]) > 0))
              in_cavity[t] = stamp, cavity.push_back(t);
      const std::size_t cluster_size = cavity.size();
      bool done = false;
      int rings = 0;
      // Grows the cavity by one vertex ring; false at the ring limit.
      auto grow_ring = [&] {
        if (rings >= max_rings) return false;
        ++rings;
        const std::size_t before = cavity.size();
        ++stamp;
        for (std::size_t i = 0; i < before; ++i) in_cavity[cavity[i]] = stamp;
        for (std::size_t i = 0; i < before; ++i)
          for (const Index v : tets.tets[cavity[i]]) {
            if (point_seen[v] == stamp) continue;
            point_seen[v] = stamp;
            for (const Index t : tets_of_point.row(v))
              if (in_cavity[t] != stamp) in_cavity[t] = stamp, cavity.push_back(t);
          }
        return true;
      };
      // The tet across a boundary face of the cavity, or kInvalidIndex on the surface.
      auto tet_across = [&](const Face& f) {
        const auto r0 = tets_of_point.row(f[0]);
        for (const Index t : r0) {
          if (in_cavity[t] == stamp) continue;
          const auto& q = tets.tets[t];
          const auto holds = [&](Index v) { return std::find(q.begin(), q.end(), v) != q.end(); };
          if (holds(f[1]) && holds(f[2])) return t;
        }
        return kInvalidIndex;
      };
      grow_ring();  // the cluster and its first vertex ring
      for (int step = 0; step < kGrowthSteps && !done && cavity.size() <= kLargestCavity; ++step) {
        if (std::any_of(cavity.begin(), cavity.end(), [&](Index t) { return taken[t] != 0; })) {
          break;  // another cavity of this pass holds part of it: the next pass
        }
        ++stamp;
        for (const Index t : cavity) in_cavity[t] = stamp;
        const std::vector<Face> boundary = cavity_boundary(tets, cavity);
        if (boundary.empty()) {  // not a closed manifold: a ring more
          if (!grow_ring()) break;
          continue;
        }
        Vec3 source_centre, parameter_centre;
        const double source_depth = kernel_centre(tets.points, boundary, source_centre);
        const double parameter_depth = kernel_centre(parameter, boundary, parameter_centre);
        if (!(source_depth > 0) || !(parameter_depth > 0)) {
          // Grow through the faces that stand in the way: those the point violating the
          // fewest (least in sum) must stay in front of; surface faces cannot be crossed.
          std::vector<std::uint8_t> crossable(boundary.size());
          for (std::size_t i = 0; i < boundary.size(); ++i) crossable[i] = tet_across(boundary[i]) != kInvalidIndex;
          std::vector<std::uint8_t> violated(boundary.size(), 0);
          if (!(source_depth > 0)) least_violated_faces(tets.points, boundary, crossable, violated);
          if (!(parameter_depth > 0)) least_violated_faces(parameter, boundary, crossable, violated);
          std::size_t added = 0;
          for (std::size_t i = 0; i < boundary.size(); ++i)
            if (violated[i] && crossable[i])
              if (const Index t = tet_across(boundary[i]); t != kInvalidIndex && in_cavity[t] != stamp)
                in_cavity[t] = stamp, cavity.push_back(t), ++added;
          if (added == 0 && !grow_ring()) break;
          continue;
        }
        // The LP's tolerance: check every cone tet's volume in both domains.
        const auto steiner = static_cast<Index>(tets.points.size());
        tets.points.push_back(source_centre);
        parameter.push_back(parameter_centre);
        bool valid = true;
        const std::size_t first_cone = cones.size();
        for (const Face& f : boundary) {
          const std::array<Index, 4> cone{f[0], f[2], f[1], steiner};
          if (!(tet_signed_volume(tets.points, cone) > 0) || !(tet_signed_volume(parameter, cone) > 0)) {
            valid = false;
            break;
          }
          cones.push_back(cone);
        }
        if (!valid) {  // the same cavity would fail the same way at the next step
          cones.resize(first_cone);
          tets.points.pop_back();
          parameter.pop_back();
          break;
        }
        for (const Index t : cavity) taken[t] = 1;
        result.removed_tets += cavity.size();
        result.added_tets += boundary.size();
        result.largest_cavity = std::max(result.largest_cavity, cavity.size());
        result.largest_ring = std::max(result.largest_ring, rings);
        ++result.cavities;
        ++repaired_this_pass;
        done = true;
      }
      if (!done)  // no cavity within max_rings, or one another cavity holds part of
        for (std::size_t i = 0; i < cluster_size; ++i) settled[cavity[i]] = 1;
    }
    if (repaired_this_pass == 0) break;
    // Cut the cavities out and put the cones in (taken slots first, then appended).
    std::size_t next_cone = 0;
    for (std::size_t t = 0; t < tets.tets.size() && next_cone < cones.size(); ++t)
      if (taken[t]) tets.tets[t] = cones[next_cone++], taken[t] = 0;
    tets.tets.insert(tets.tets.end(), cones.begin() + static_cast<std::ptrdiff_t>(next_cone), cones.end());
    std::size_t kept = 0;
    for (std::size_t t = 0; t < tets.tets.size(); ++t)
      if (t >= taken.size() || !taken[t]) tets.tets[kept++] = tets.tets[t];
    tets.tets.resize(kept);
    flipped = flipped_tets();
  }
  result.flipped_after = flipped.size();
  return result;
}

}  // namespace structmesh
