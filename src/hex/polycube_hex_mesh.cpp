// polycube_hex_mesh(): chapters 4 and 5 end to end.
//
//   surface S --build_polycube--> Q (pseudo-polycube), P (voxel polycube), alignment
//   S --tetrahedralize--> M (tet mesh, S's points first)
//   Q --projection onto P, relax_surface_map--> the map's boundary on P (§5.2.1)
//   M --volumetric_map--> parameter positions of M's points, boundary pinned there
//   P --polycube_hex_grid--> Omega_H in parameter space
//   Omega_H --phi^-1 (barycentric in M's parameter image)--> hexes in the aligned frame
//   --pillow--> one padding layer --unalign, smooth_hex_mesh--> the hex mesh
//
// How the grid meets the map. §5.2.1 maps S onto P and pins the map's boundary to P. Here Q
// (whose correspondence with S is exact: same connectivity) is projected onto P along its
// charts' axes, and the folds the projection makes where Q's charts do not match P's facets
// are relaxed on P. Each boundary point of the grid then goes to that image of Q along its
// polycube normal (the closest point where that line misses nearby), so it lands exactly on
// S, and each interior point is located in M's parameter image. Without plane merging P
// stays within about a voxel of Q and the map ends on Q itself, which does not fold: Q is a
// deformation of S checked free of self-intersections.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/quality.hpp"
#include "structmesh/tetmesh.hpp"
#include "tet_locator.hpp"

#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace structmesh {
namespace {

// A number with 4 significant digits (std::to_string prints small sizes as 0.000000).
std::string significant(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

using Clock = std::chrono::steady_clock;

// D_g (over the bounding-box diagonal) beyond which a hex mesh has lost a part of the model:
// on the benchmark models a sound mesh stays under 0.07.
constexpr double kLostPartDeviation = 0.1;
// The extraction is also made again from P when the first one's worst hex is below this
// (the target for the worst scaled Jacobian).
constexpr double kRetryBelowQuality = 0.3;
// A released boundary point of the map this many voxels off P makes the mesh from the map's
// boundary unlikely to win: the mesh from P is made first, and if it is sound the other is
// not made. On the benchmark models (AVX2 kernels) the map's boundary gave the kept mesh up to
// 34 voxels off P (the kitten; the rocker arm 20, the screwdriver 17, the hand 8), and lost
// from 91 on (fertility 91, the bunny and kitten_40k 216 and 217): making it first cost the
// bunny 5.6 s (it stayed tangled).
constexpr double kHopelessDriftVoxels = 50;

// The merged-plane attempt stops after the surface map when more than this share of Q's
// triangles stays folded on P after the relaxation: a folded boundary triangle pins inverted
// tets, and the hexes on them stay inverted. Where the merged attempt gave a valid mesh on
// the benchmark models, at most 0.5% stayed folded (kitten_40k: 373 of 80,000); on the
// closed dog, whose ears, legs and tail are a voxel or two thick, 7.7% (3,896 of 50,580) and
// the mesh kept 121 inverted hexes after 45 s of work that the unmerged retry threw away.
constexpr double kHopelessFoldedShare = 0.02;
// ... and where the projection alone folds more than this share, it is not even relaxed.
constexpr double kHopelessProjectedShare = 0.25;

/// Hexes that are inverted or invalid: what a retry must lower first.
std::size_t bad_hexes(const HexQuality& quality) { return quality.inverted + quality.invalid; }

// Which of two meshes of the same input to keep: fewer bad hexes first, then not having lost
// a part (D_g over kLostPartDeviation), then the better worst hex.
bool better_mesh(const HexQuality& quality, double deviation, const HexQuality& other_quality, double other_deviation) {
  const auto rank = [](const HexQuality& q, double d) {
    return std::make_tuple(bad_hexes(q), d > kLostPartDeviation, -q.scaled_jacobian_stats.min);
  };
  return rank(quality, deviation) < rank(other_quality, other_deviation);
}

// What one extraction leaves in a HexResult, set aside while another is made.
struct Extraction {
  HexMesh mesh;
  HexSmoothingResult smoothing;
  HexQuality quality;
  double deviation = 0;

  static Extraction take(HexResult& result) {
    return {std::move(result.mesh), result.smoothing, result.quality, result.geometric_deviation};
  }
  // Whether this one beats the one now in `result`.
  bool better_than(const HexResult& result) const {
    return better_mesh(quality, deviation, result.quality, result.geometric_deviation);
  }
  void put_back(HexResult& result) && {
    result.mesh = std::move(mesh);
    result.smoothing = smoothing;
    result.quality = quality;
    result.geometric_deviation = deviation;
  }
};

class StageTimer {
 public:
  explicit StageTimer(std::vector<std::pair<std::string, double>>& stages) : stages_(stages) {}
  void stop(const std::string& name, double earlier_seconds = 0) {
    const auto now = Clock::now();
    stages_.emplace_back(name, earlier_seconds + std::chrono::duration<double>(now - start_).count());
    start_ = now;
  }

 private:
  std::vector<std::pair<std::string, double>>& stages_;
  Clock::time_point start_ = Clock::now();
};

/// The grid's hex count (padding included) for a hex size.
std::size_t hex_count(const VoxelGrid& voxels, double hex_size, bool padding) {
  const PolycubeGridCount count = polycube_hex_count(voxels, hex_size);
  return count.hexes + (padding ? count.boundary_quads : 0);
}

/// The hex size whose grid has about `target` hexes: bisection on log(size) (the count falls
/// as the size grows, in steps). 0 when even one layer per slab gives more than the target.
double hex_size_for_count(const VoxelGrid& voxels, std::size_t target, bool padding) {
  if (hex_count(voxels, 0, padding) >= target) return 0;
  double lo = voxels.size / 8, hi = voxels.size * std::max({voxels.dims[0], voxels.dims[1], voxels.dims[2]});
  for (int i = 0; i < 20; ++i) {
    const double mid = std::sqrt(lo * hi);
    if (hex_count(voxels, mid, padding) > target)
      lo = mid;
    else
      hi = mid;
    if (hi / lo < 1.01) break;
  }
  return std::sqrt(lo * hi);
}

TriMesh triangulated_boundary(const HexMesh& mesh) {
  TriMesh surface;
  surface.points = mesh.points;
  for (const auto& q : hex_boundary_quads(mesh)) {
    surface.triangles.push_back({q[0], q[1], q[2]});
    surface.triangles.push_back({q[0], q[2], q[3]});
  }
  return surface;
}

}  // namespace

namespace {

// The post-smoothing's settings for every extraction.
HexSmoothingOptions extraction_smoothing(const HexOptions& options) {
  HexSmoothingOptions smoothing = options.smoothing;
  smoothing.progress = options.progress || smoothing.progress;
  if (options.features && smoothing.feature_angle_degrees == 0) smoothing.feature_angle_degrees = 30;
  return smoothing;
}

// The smoothing's projection onto the input: a walk from the triangle of the point's last one.
HintedProjection walking_onto_input(const SurfaceProjection& onto_input) {
  return [&onto_input](const Vec3& p, Index* triangle) {
    return triangle ? onto_input.closest_point_walking(p, *triangle) : onto_input.closest_point(p);
  };
}

// Smoothing sweeps of an extraction that may be made twice (below), before the two are
// compared: the comparison needs the hexes untangled and the worst ones lifted a little,
// and the full sweeps (100 at 0.25 s each on the bunny at 80k hexes) are for the mesh that
// is kept. The bunny, whose first mesh loses: 87 s end to end when both got every sweep.
constexpr int kSweepsBeforeComparison = 10;

// The smoothing of the extraction that is kept, in full: its mesh as it was before the
// comparison's sweeps, smoothed as an extraction that is not compared would be (untangling,
// sweeps until they stall, then the polish of the worst hexes). From the start rather than
// on from the comparison's sweeps: a second call would put the points the first released
// back on the surface (the bunny's worst hex: 0.59 so, 0.67 from the start).
void finish_smoothing(const TriMesh& surface, const SurfaceProjection& onto_input, const HexOptions& options,
                      HexMesh unsmoothed, HexResult& result) {
  const HexSmoothingOptions smoothing = extraction_smoothing(options);
  if (smoothing.iterations <= 0) return;
  const auto start = Clock::now();
  result.smoothing = smooth_hex_mesh(unsmoothed, walking_onto_input(onto_input), smoothing);
  result.mesh = std::move(unsmoothed);
  result.quality = hex_quality(result.mesh);
  result.geometric_deviation = hausdorff_distance(surface, triangulated_boundary(result.mesh)).relative;
  result.stage_seconds.emplace_back("smoothing (kept mesh)",
                                    std::chrono::duration<double>(Clock::now() - start).count());
}

// Chapter 4's polycube, with the caller's progress setting.
PolycubeResult build_polycube_for(const TriMesh& surface, const HexOptions& options) {
  PolycubeOptions polycube_options = options.polycube;
  polycube_options.progress = options.progress || polycube_options.progress;
  return build_polycube(surface, polycube_options);
}

// Chapter 5 on a polycube built by chapter 4. With `stop_if_folded`, an attempt on a
// merged-plane polycube whose surface map stays folded beyond kHopelessFoldedShare stops
// there (HexResult::merged_map_folded) and returns no mesh.
HexResult polycube_hex_mesh_once(const TriMesh& surface, const HexOptions& options, PolycubeResult built,
                                 bool stop_if_folded) {
  HexResult result;
  StageTimer timer(result.stage_seconds);
  result.polycube = std::move(built);
  const PolycubeResult& polycube = result.polycube;
  double polycube_seconds = 0;  // built by the caller
  for (const auto& stage : polycube.stage_seconds) {
    result.stage_seconds.push_back(stage);
    polycube_seconds += stage.second;
  }
  timer.stop("polycube (total)", polycube_seconds);

  // The integer grid on P (§5.3): hex size from the requested count or length.
  if (options.target_hexes > 0)
    result.hex_size = hex_size_for_count(polycube.voxels, options.target_hexes, options.padding);
  else
    result.hex_size = options.size;
  // The input solid's tet mesh, in the aligned frame (the frame of Q and P).
  TriMesh aligned = surface;
  for (Vec3& p : aligned.points) p = polycube.alignment.apply(p);
  if (options.progress) status("hex: tetrahedralizing the solid");
  TetmeshOptions tet_options;
  // The map need not be finer than the hexes: tets as large as a hex inside (TetGen keeps
  // the surface's own resolution at the boundary). A finer default cost the bunny 3.4M tets
  // and two minutes of solving for 80k hexes.
  const PolycubeGridCount grid_count = polycube_hex_count(polycube.voxels, result.hex_size);
  if (const std::size_t planned = grid_count.hexes + (options.padding ? grid_count.boundary_quads : 0);
      planned > options.max_hexes)
    throw Error("hex: the grid would have " + std::to_string(planned) + " hexes, more than the limit of " +
                std::to_string(options.max_hexes) + " (--max-hexes): the polycube has " +
                std::to_string(polycube.optimization.after.corners) +
                " corners and every slab between its facet planes takes at least one layer; a smaller "
                "--max-resolution gives a coarser polycube");
  const double mean_hex =
      std::cbrt(enclosed_volume(aligned) / static_cast<double>(std::max<std::size_t>(grid_count.hexes, 1)));
  tet_options.size = options.tet_size > 0 ? options.tet_size : std::max(mean_edge_length(aligned), mean_hex);
  tet_options.check_input = false;  // build_polycube() has checked the surface
  // TetGen runs on one core, and the surface map below does not need the tets: the tet mesh
  // is made on a thread of its own alongside it (the bunny: 6.4 s of TetGen, 1.2 s of surface
  // map; kitten_40k 4.0 and 3.1 s). Its stage time is what is left of it after the surface map.
  struct SplitTets {
    TetMesh mesh;
    std::size_t split_edges = 0;
  };
  // Started once the merged attempt is known not to stop at its projection (below).
  std::future<SplitTets> tet_job;
  auto start_tets = [&] {
    tet_job = std::async(std::launch::async, [&aligned, tet_options] {
      SplitTets tets{tetrahedralize(aligned, tet_options).mesh};
      tets.split_edges = split_boundary_tets(tets.mesh, aligned.points.size());
      return tets;
    });
  };
  // Waits for the tet mesh (also on the way out of an exception: a future of std::async
  // waits in its destructor).
  auto take_tets = [&] {
    if (!tet_job.valid()) start_tets();
    SplitTets tets = tet_job.get();
    result.tets = std::move(tets.mesh);
    result.split_edges = tets.split_edges;
    timer.stop("tet mesh (beyond the surface map)");
  };

  // §5.2.2: the volumetric map onto the pseudo-polycube's solid.
  VolumetricMapOptions map_options;
  map_options.progress = options.progress;
  // The boundary goes onto P itself (§5.2.1's projection of Q onto P, then the relaxation
  // of the folds it makes): P differs from Q by the optimisation's and the plane merging's
  // moves, up to a few voxels, and with Q as the domain the grid points of P outside Q
  // were all put on the surface, folding whole layers.
  // Without plane merging P stays within about a voxel of Q and the map ends on Q.
  const bool map_onto_p = options.polycube.merge_planes_within > 0;
  TriMesh on_p;         // Q's triangles on P's points nearest to Q's
  TriMesh p_triangles;  // P's quads split in two (empty when the map ends on Q)
  std::optional<SurfaceProjection> onto_p;
  const TriMesh& q = polycube.pseudo.surface;
  // smooth_surface_map() on the map's boundary, alternating with relax_surface_map() while
  // folds or branch points stay and get fewer.
  auto smooth_surface_on_p = [&] {
    // Then the distortion smoothing (the strips the projection stretched over P's facets,
    // measured against the input's triangles, which the tets see). Folds the relaxation
    // left often come out once the smoothing has spread the points around them (the
    // bunny: 15 folded, 0 after three more rounds), so the two alternate while the folds
    // get fewer.
    result.surface_map_smoothing = smooth_surface_map(aligned, on_p.points, p_triangles, *onto_p);
    auto defects = [](const SurfaceMapRelaxation& r) { return r.folded_after + r.branched_after; };
    for (int round = 0; round < options.surface_map_rounds && defects(result.surface_map) > 0; ++round) {
      const SurfaceMapRelaxation again = relax_surface_map(q, on_p.points, p_triangles, *onto_p, 30);
      const bool fewer = defects(again) < defects(result.surface_map);
      result.surface_map.folded_after = again.folded_after;
      result.surface_map.branched_after = again.branched_after;
      result.surface_map.unwound_regions += again.unwound_regions;
      result.surface_map.sweeps += again.sweeps;
      result.surface_map.moved_points = std::max(result.surface_map.moved_points, again.moved_points);
      ++result.surface_map.rounds;
      const SurfaceMapSmoothing smoothed = smooth_surface_map(aligned, on_p.points, p_triangles, *onto_p);
      result.surface_map_smoothing.energy_after = smoothed.energy_after;
      result.surface_map_smoothing.worst_area_ratio_after = smoothed.worst_area_ratio_after;
      result.surface_map_smoothing.sweeps += smoothed.sweeps;
      result.surface_map_smoothing.moved_points =
          std::max(result.surface_map_smoothing.moved_points, smoothed.moved_points);
      if (!fewer) break;
    }
  };
  if (map_onto_p) {
    if (options.progress) status("hex: surface map of Q onto P (projection, relaxation of folds)");
    p_triangles.points = polycube.surface.points;
    for (const auto& q : polycube.surface.quads) {
      p_triangles.triangles.push_back({q[0], q[1], q[2]});
      p_triangles.triangles.push_back({q[0], q[2], q[3]});
    }
    onto_p.emplace(p_triangles);
    on_p.triangles = q.triangles;
    on_p.points.resize(q.points.size());
    // Each point of Q moves along the axes of its triangles' labels (a point inside a +X
    // chart along x only, one on a chart border along the sum of both axes), as §5.2.1
    // projects along normals: the closest point alone sent points across P's edges onto
    // the wrong facet and folded the map (fertility: 4,497 flipped tets before untangling).
    std::vector<std::uint8_t> labels_of(q.points.size(), 0);
    for (std::size_t t = 0; t < q.triangles.size(); ++t)
      for (const Index v : q.triangles[t]) labels_of[v] |= static_cast<std::uint8_t>(1u << polycube.pseudo.labels[t]);
    const double reach = 4 * polycube.voxels.size;
    tbb::parallel_for(std::size_t{0}, on_p.points.size(), [&](std::size_t v) {
      const Vec3& point = q.points[v];
      Vec3 direction = Vec3::Zero();
      for (int label = 0; label < kAxisLabels; ++label)
        if (labels_of[v] & (1u << label)) direction += axis_of_label(label);
      Vec3 hit, barycentric;
      Index triangle = 0;
      if (direction.squaredNorm() > 0 && onto_p->nearest_on_line(point, direction, reach, hit, triangle, barycentric))
        on_p.points[v] = hit;
      else
        on_p.points[v] = onto_p->closest_point(point);
    });
    // A projection that folds over a quarter of Q's triangles is not relaxed: the closed
    // dog's folded 22,532 of 50,580 and 3,896 (7.7%) stayed after the relaxation, above
    // kHopelessFoldedShare, while every projection that relaxed to under it folded at most
    // 12% (the screwdriver; the data set and the 16 built-in solids). Nor is the tet mesh
    // made for it: the mesh on the unmerged polycube needs tets of another size.
    if (stop_if_folded) {
      const std::size_t folded = folded_triangles(q, on_p.points, p_triangles, *onto_p);
      if (static_cast<double>(folded) > kHopelessProjectedShare * static_cast<double>(q.triangles.size())) {
        result.surface_map.folded_before = result.surface_map.folded_after = folded;
        result.surface_map.rounds = 0;
        result.merged_map_folded = true;
        timer.stop("surface map (projection only)");
        return result;
      }
    }
    start_tets();
    // §5.2.1's local relaxation: where Q's charts do not match P's facets, the projection
    // folds some of Q's triangles on P, and a folded boundary triangle pins inverted tets.
    result.surface_map = relax_surface_map(q, on_p.points, p_triangles, *onto_p);
    if (options.smooth_surface_map) {
      timer.stop("surface map");
      smooth_surface_on_p();
    }
    map_options.boundary_positions = on_p.points;
    timer.stop(options.smooth_surface_map ? "surface map smoothing" : "surface map");
    if (stop_if_folded && static_cast<double>(result.surface_map.folded_after) >
                              kHopelessFoldedShare * static_cast<double>(q.triangles.size())) {
      result.merged_map_folded = true;
      return result;
    }
  }
  take_tets();
  // The volumetric map (5.1), its untangling, the star cavities and the joint untangling of
  // what stays flipped.
  auto make_volumetric_map = [&](const std::string& suffix) {
    if (options.progress)
      status("hex: volumetric map of " + std::to_string(result.tets.tets.size()) + " tets (frames, (5.1), untangling)");
    result.map = volumetric_map(result.tets, aligned, polycube.pseudo.surface, map_options);
    result.flipped_repair = {};
    result.map_untangling = {};
    if (result.map.flipped > 0) {
      result.flipped_repair = repair_flipped_tets(result.tets, result.map.parameter);
      result.map.flipped = result.flipped_repair.flipped_after;
    }
    // From here on a flat tet counts as flipped: the untangling stages above test the sign
    // only, and the bunny's map kept a tet at 1e-16 of its share of the volume (D_v 7e9).
    result.map.flipped = flipped_or_flat_tets(result.tets, result.map.parameter, options.map_untangling.flat);
    if (result.map.flipped > 0 && options.untangle_map_jointly && (map_onto_p || options.untangle_map_onto_q)) {
      // What stays flipped lies where the map's surface folds on P: the region's surface
      // points are freed too (held near P by springs) and the region untangled jointly.
      const std::vector<Vec3>& targets = map_onto_p ? on_p.points : q.points;
      timer.stop("volumetric map" + suffix);
      result.map_untangling =
          untangle_tet_map(result.tets, result.map.parameter, targets.size(), targets, options.map_untangling);
      result.map.flipped = result.map_untangling.flipped_after;
      result.map.released_boundary_points =
          std::max(result.map.released_boundary_points, result.map_untangling.moved_boundary_points);
    }
    // D_v as volumetric_map() measured it, unless a later step moved the map or found a flat tet.
    if (result.map.flipped > 0)
      result.map.volume_distortion = 0;
    else if (result.flipped_repair.flipped_before > 0 || result.map_untangling.rounds > 0)
      result.map.volume_distortion = volume_distortion(result.tets, TetMesh{result.map.parameter, result.tets.tets});
    timer.stop(result.map_untangling.rounds > 0 ? "volumetric map (joint untangling)" + suffix
                                                : "volumetric map" + suffix);
  };
  make_volumetric_map("");
  // A second chance: where tets stay flipped on a map whose surface was not smoothed, the
  // surface map is smoothed (its stretched strips spread, the branch points left after the
  // relaxation often gone with them) and the volumetric map made again; the map with fewer
  // flipped tets is kept. kitten_40k: 46 flipped tets by default, 0 after this, for 16 s.
  // Not the first step for every model: on fertility the smoothing leaves 5 flipped tets
  // where the map without it comes out flip-free.
  if (result.map.flipped > 0 && map_onto_p && !options.smooth_surface_map && options.smooth_surface_map_if_flipped) {
    if (options.progress)
      status("hex: " + std::to_string(result.map.flipped) +
             " tets stay flipped; again with the surface map's distortion smoothed");
    // The tet mesh too: the star cavities of repair_flipped_tets() re-triangulate it and add
    // points, so the first map's parameter belongs to the tets as the first map left them.
    struct Kept {
      std::vector<Vec3> on_p;
      SurfaceMapRelaxation surface_map;
      VolumetricMap map;
      FlippedTetRepair flipped_repair;
      TetMapUntangling map_untangling;
      TetMesh tets;
    } first{on_p.points,           result.surface_map,    std::move(result.map),
            result.flipped_repair, result.map_untangling, result.tets};
    smooth_surface_on_p();
    map_options.boundary_positions = on_p.points;
    timer.stop("surface map smoothing (second chance)");
    make_volumetric_map(" (second chance)");
    result.surface_map_smoothed_after_flips = true;
    if (result.map.flipped >= first.map.flipped) {
      on_p.points = std::move(first.on_p);
      result.surface_map = first.surface_map;
      result.surface_map_smoothing = {};
      result.map = std::move(first.map);
      result.flipped_repair = first.flipped_repair;
      result.map_untangling = first.map_untangling;
      result.tets = std::move(first.tets);
    } else {
      result.surface_map_smoothed_kept = true;
    }
  }
  result.parameter = result.map.parameter;
  if (result.parameter.size() != result.tets.points.size())
    throw Error("hex: the volumetric map has " + std::to_string(result.parameter.size()) + " points, its tet mesh " +
                std::to_string(result.tets.points.size()));

  const HexMesh polycube_grid = polycube_hex_grid(polycube.voxels, result.hex_size);
  if (polycube_grid.hexes.empty()) throw Error("hex: the polycube has no voxels");
  if (options.progress)
    status("hex: grid of " + std::to_string(polycube_grid.hexes.size()) + " hexes (hex size " +
           significant(result.hex_size) + ")");
  // phi^-1: boundary points go to Q along their polycube normal (the sum of the axes of
  // their boundary quads, so a corner of P goes to the corner of Q and an edge point to the
  // edge), as §5.2.1 projects along normals, falling back to the closest point when that
  // line misses Q nearby; interior points are located in M's parameter image. Both are
  // interpolated barycentrically onto the aligned input.
  const std::vector<std::array<Index, 4>> boundary_quads = hex_boundary_quads(polycube_grid);
  std::vector<std::uint8_t> axes_of(polycube_grid.points.size(), 0);  // bit per axis label of its boundary quads
  for (const auto& q : boundary_quads) {
    const auto& points = polycube_grid.points;
    const Vec3 normal = (points[q[2]] - points[q[0]]).cross(points[q[3]] - points[q[1]]);
    const int label = nearest_axis_label(normal);
    for (Index v : q) axes_of[v] |= static_cast<std::uint8_t>(1u << label);
  }
  const hex_detail::TetLocator locator(result.parameter, result.tets.tets);
  const double voxel = polycube.voxels.size;
  const SurfaceProjection onto_input(surface);  // the post-smoothing's boundary
  const SurfaceProjection onto_aligned(aligned);
  timer.stop("hex grid");

  // The hex extraction (phi^-1, padding, smoothing, measures) with the grid's boundary points
  // sent to `boundary_image` (Q's triangles where the map put them). What does not depend on
  // the boundary image is made once above: the extraction may run twice (below).
  // `compare`: only kSweepsBeforeComparison sweeps and no polish; returns the mesh before
  // its smoothing, which finish_smoothing() smooths in full if it is kept.
  auto extract = [&](const TriMesh& boundary_image, const std::string& suffix, bool sweeps_only_if_untangled,
                     bool compare) -> HexMesh {
    HexMesh grid = polycube_grid;
    const SurfaceProjection onto_q(boundary_image);
    std::vector<Vec3> mapped(grid.points.size());
    std::vector<std::uint8_t> outside(grid.points.size(), 0);
    auto on_input = [&](Index triangle, const Vec3& b) {  // b: clamped and normalised by SurfaceProjection
      const auto& t = aligned.triangles[triangle];
      return Vec3(b[0] * aligned.points[t[0]] + b[1] * aligned.points[t[1]] + b[2] * aligned.points[t[2]]);
    };
    auto through_surface = [&](const Vec3& p, std::uint8_t axes) {
      Index triangle = 0;
      Vec3 barycentric;
      const Vec3 closest = onto_q.closest_point(p, &triangle, &barycentric);
      Vec3 normal = Vec3::Zero();
      for (int label = 0; label < kAxisLabels; ++label)
        if (axes & (1u << label)) normal += axis_of_label(label);
      if (normal.squaredNorm() > 0) {
        const double closest_distance = (closest - p).norm();
        Vec3 hit, hit_barycentric;
        Index hit_triangle = 0;
        // Only Q's triangles that face along the normal count: across a narrow gap or a thin
        // slab the nearest one may be the far side's, and a point sent there stretches its
        // hexes across (fertility: a corner of P went to the far side of a gap 4 hexes wide,
        // its three boundary quads became 21-39 degree spikes, the worst hex 0.055).
        if (onto_q.nearest_on_line(p, normal, 4 * voxel + 2 * closest_distance, hit, hit_triangle, hit_barycentric,
                                   &normal) &&
            (hit - p).norm() <= 2 * closest_distance + voxel)
          return on_input(hit_triangle, hit_barycentric);
      }
      return on_input(triangle, barycentric);
    };
    tbb::parallel_for(std::size_t{0}, grid.points.size(), [&](std::size_t v) {
      const Vec3& p = grid.points[v];
      if (axes_of[v] != 0) {
        mapped[v] = through_surface(p, axes_of[v]);
        return;
      }
      const hex_detail::TetLocation where = locator.locate(p);
      if (!where.inside) {
        // Outside Q (P pokes out of it here): the nearest point of Q stands in; the smoothing
        // below moves it back inside.
        outside[v] = 1;
        mapped[v] = through_surface(p, 0);
        return;
      }
      const auto& tet = result.tets.tets[where.tet];
      Vec3 x = Vec3::Zero();
      for (int c = 0; c < 4; ++c) x += where.barycentric[static_cast<std::size_t>(c)] * result.tets.points[tet[c]];
      mapped[v] = x;
    });
    result.interior_points_outside = static_cast<std::size_t>(std::count(outside.begin(), outside.end(), 1));
    grid.points = std::move(mapped);
    result.points_moved_to_facing_sheet =
        move_boundary_points_to_facing_sheet(grid.points, boundary_quads, aligned, onto_aligned);
    timer.stop("inverse map" + suffix);

    // Padding (§5.4's "padding layers"): one pillow layer under the boundary.
    if (options.padding) {
      double edge_sum = 0;
      std::size_t edges = 0;
      for (const auto& q : boundary_quads)  // the grid's, still (its points moved, not its quads)
        for (int i = 0; i < 4; ++i) {
          edge_sum +=
              (grid.points[q[static_cast<std::size_t>(i)]] - grid.points[q[static_cast<std::size_t>((i + 1) % 4)]])
                  .norm();
          ++edges;
        }
      const double depth = options.padding_depth * edge_sum / static_cast<double>(std::max<std::size_t>(edges, 1));
      const std::size_t before = grid.hexes.size();
      grid = pillow(grid, depth);
      result.padding_hexes = grid.hexes.size() - before;
    }
    for (Vec3& p : grid.points) p = polycube.alignment.unapply(p);
    timer.stop("padding" + suffix);

    // Post-smoothing: untangle, then raise the worst scaled Jacobian, boundary on the input.
    HexSmoothingOptions smoothing = extraction_smoothing(options);
    smoothing.sweeps_only_if_untangled = sweeps_only_if_untangled;
    HexMesh unsmoothed;
    if (compare) {
      unsmoothed = grid;
      smoothing.polish_below = 0;
      smoothing.restart_rounds = 0;
      smoothing.mean_below = 0;
      smoothing.iterations = std::min(smoothing.iterations, kSweepsBeforeComparison);
    }
    if (smoothing.iterations > 0)  // 0: the raw map, to inspect it
      result.smoothing = smooth_hex_mesh(grid, walking_onto_input(onto_input), smoothing);
    timer.stop("smoothing" + suffix);

    result.mesh = std::move(grid);
    result.quality = hex_quality(result.mesh);
    result.geometric_deviation = hausdorff_distance(surface, triangulated_boundary(result.mesh)).relative;
    timer.stop("quality" + suffix);
    return unsmoothed;
  };
  // How far the map's untangling took released boundary points from their targets on the
  // domain's boundary (Q's points, or P's nearest to them), in voxels.
  const std::vector<Vec3>& boundary_targets = map_onto_p ? on_p.points : polycube.pseudo.surface.points;
  for (std::size_t i = 0; i < boundary_targets.size(); ++i)
    result.map_boundary_drift =
        std::max(result.map_boundary_drift, (result.parameter[i] - boundary_targets[i]).norm() / voxel);
  if (!map_onto_p) {
    extract(polycube.pseudo.surface, "", false, false);
    return result;
  }
  // The grid's boundary points go to the map's boundary: where the map's untangling released
  // boundary points, that is where they ended, not their place on P (read from P, the grid
  // and the map disagree there: the worst hex of the screwdriver was 0.12 against 0.58, of
  // fertility 0.10 against 0.63). But a released point may end far off P (the bunny's, 74
  // voxels), and the hexes the mesh stretches to follow it are poor (the bunny's worst 0.06
  // from the map's boundary, 0.62 from P). So when the mesh strays more than
  // kLostPartDeviation from the input, a hex stays inverted or the worst is below
  // kRetryBelowQuality, the extraction is made again from P and the better mesh is kept.
  TriMesh map_boundary = on_p;
  std::copy_n(result.parameter.begin(), map_boundary.points.size(), map_boundary.points.begin());
  const bool retry_possible = result.map.released_boundary_points > 0;
  const auto sound = [&] {
    return bad_hexes(result.quality) == 0 && result.geometric_deviation <= kLostPartDeviation &&
           result.quality.scaled_jacobian_stats.min >= kRetryBelowQuality;
  };
  // A released point far off P: the mesh from P first, and if it is sound, the one from the
  // map's boundary is not made. Otherwise that one is made too, in full, and the better kept
  // (with OpenBLAS's AVX-512 kernels, fertility's mesh from P kept inverted hexes where the
  // one from the map's boundary had a worst hex of 0.41).
  if (retry_possible && result.map_boundary_drift > kHopelessDriftVoxels) {
    extract(on_p, " (boundary on P)", false, false);
    result.extraction_retried = true;
    result.boundary_from_p_kept = true;
    if (sound()) {
      result.map_boundary_skipped = true;
      return result;
    }
    Extraction from_p = Extraction::take(result);
    extract(map_boundary, "", false, false);
    result.boundary_from_p_kept = from_p.better_than(result);
    if (result.boundary_from_p_kept) std::move(from_p).put_back(result);
    return result;
  }
  // Where a retry is possible, a first mesh that stays tangled after the untangling gets no
  // smoothing sweeps: it loses to any untangled retry. Otherwise both meshes get
  // kSweepsBeforeComparison sweeps, are compared so, and the kept one is smoothed in full
  // (finish_smoothing).
  HexMesh first_unsmoothed = extract(map_boundary, "", retry_possible, retry_possible);
  if (!retry_possible) return result;
  // Sound after the comparison's sweeps is not sound after all of them: released points
  // drift off the input over many sweeps (the closed dog at 10k hexes: worst hex 0.14, D_g
  // 0.22 after them). So the first mesh is judged again, fully smoothed, before it is kept.
  bool first_finished = false;
  if (sound()) {
    finish_smoothing(surface, onto_input, options, std::move(first_unsmoothed), result);
    if (sound()) return result;
    first_finished = true;
  }
  const bool first_unswept = result.smoothing.sweeps_held_back;
  Extraction first = Extraction::take(result);
  // A first mesh still tangled loses to any untangled second one (better_mesh ranks bad
  // hexes first), so then the second is smoothed in full at once.
  HexMesh second_unsmoothed = extract(on_p, " (boundary on P)", false, !first_unswept);
  result.extraction_retried = true;
  const bool second_better = better_mesh(result.quality, result.geometric_deviation, first.quality, first.deviation);
  if (second_better) {
    if (!first_unswept) finish_smoothing(surface, onto_input, options, std::move(second_unsmoothed), result);
  } else if (first_finished) {
    std::move(first).put_back(result);
  } else if (first_unswept) {
    extract(map_boundary, " (boundary from the map, smoothed)", false, false);
  } else {
    finish_smoothing(surface, onto_input, options, std::move(first_unsmoothed), result);
  }
  result.boundary_from_p_kept = second_better;
  return result;
}

}  // namespace

HexResult polycube_hex_mesh(const TriMesh& surface, const HexOptions& options) {
  if (options.size < 0 || !std::isfinite(options.size))
    throw InputError("hex: --size must be a finite length >= 0, got " + std::to_string(options.size));
  const bool may_retry = options.polycube.merge_planes_within > 0 && options.retry_without_merging;
  HexResult result = polycube_hex_mesh_once(surface, options, build_polycube_for(surface, options), may_retry);
  // Plane merging moves P away from Q by up to two voxels, and the map onto P that this
  // needs folds where Q's charts do not match P's facets (fertility: 40 tets stay flipped,
  // 39 hexes inverted). A valid mesh comes first: then the mesh is made again on the
  // polycube without merging (P within a voxel of Q, the map onto Q), and the better of the
  // two is kept. The same when the surface map onto the merged P stayed folded (the first
  // attempt stopped there and has no mesh to compare).
  if (!may_retry || (!result.merged_map_folded && bad_hexes(result.quality) == 0)) return result;
  if (options.progress)
    status(result.merged_map_folded
               ? "hex: " + std::to_string(result.surface_map.folded_after) +
                     " triangles of Q stay folded on the merged polycube; again with its facet planes unmerged"
               : "hex: " + std::to_string(result.quality.inverted) +
                     " hexes inverted; again with the polycube's facet planes unmerged");
  HexOptions unmerged = options;
  unmerged.polycube.merge_planes_within = 0;
  HexResult second = polycube_hex_mesh_once(surface, unmerged, without_plane_merging(result.polycube), false);
  const bool better = result.merged_map_folded || better_mesh(second.quality, second.geometric_deviation,
                                                              result.quality, result.geometric_deviation);
  const bool map_folded = result.merged_map_folded;
  std::vector<std::pair<std::string, double>> first_stages = std::move(result.stage_seconds);
  if (better)
    result = std::move(second);
  else
    result.stage_seconds = std::move(second.stage_seconds);
  result.merging_retried = true;
  result.merged_map_folded = map_folded;
  // The report's stage times cover both attempts. The polycube's own stages, which the
  // second attempt reuses, keep their names (and count in its "polycube (total)"); the rest
  // of the first attempt is one entry.
  double first_total = 0, first_polycube = 0;
  for (const auto& [name, seconds] : first_stages)
    first_total += name.find("(total)") == std::string::npos ? seconds : 0;
  std::vector<std::pair<std::string, double>> stages;
  for (const auto& [name, seconds] : first_stages) {
    if (name == "polycube (total)") break;  // the polycube's stages come first, then their total
    stages.emplace_back(name, seconds);
    first_polycube += seconds;
  }
  stages.emplace_back("first attempt (planes merged)", first_total - first_polycube);
  for (auto& [name, seconds] : result.stage_seconds)
    if (name == "polycube (total)") seconds += first_polycube;
  result.stage_seconds.insert(result.stage_seconds.begin(), stages.begin(), stages.end());
  result.unmerged_kept = better;
  return result;
}

}  // namespace structmesh
