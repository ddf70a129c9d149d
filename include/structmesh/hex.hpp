// Polycube hex meshing (dissertation chapter 5): the volumetric map of the input solid
// onto its polycube, hex extraction on the polycube's integer grid, padding (pillowing),
// and post-smoothing that never inverts and keeps the boundary on the input surface.
#pragma once

#include "structmesh/mesh.hpp"
#include "structmesh/polycube.hpp"
#include "structmesh/quality.hpp"

#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace structmesh {

// ---------------------------------------------------------------------------
// Hex-mesh building blocks

/// The hex grid of a polycube (a voxel set): per axis, the planes of its facets cut the
/// domain into slabs, each slab is split into max(1, round(thickness / hex_size)) layers
/// (one layer each when hex_size <= 0), and every cell of this tensor-product grid inside the
/// polycube becomes a hex (no facet lies inside a slab, so each cell is wholly in or out).
/// VTK node order, positive orientation, only the points hexes use. Coordinates are the
/// voxel grid's (origin + size * lattice), so facets of the polycube are grid faces.
HexMesh polycube_hex_grid(const VoxelGrid& grid, double hex_size);

/// What polycube_hex_grid() would make, counted without making it (cheap: one pass over the
/// cells of the facet planes' grid): its hexes and its boundary quads.
struct PolycubeGridCount {
  std::size_t hexes = 0, boundary_quads = 0;
};
PolycubeGridCount polycube_hex_count(const VoxelGrid& grid, double hex_size);

/// The boundary of a hex mesh: faces used by one hex, outward, in build_faces() order, on the
/// hex mesh's own point indices.
std::vector<std::array<Index, 4>> hex_boundary_quads(const HexMesh& mesh);

/// Pillowing (padding, one layer): every boundary point p is duplicated; the copy keeps p's
/// position and becomes the new boundary point, the original moves inward by `depth` along the
/// offset direction m of its boundary quads (m . n_f = 1 for each distinct unit normal n_f of
/// its boundary quads, least squares; the exact inward offset of planes for an orthogonal
/// polyhedron), and every boundary quad gets one new hex between its old and new points. So
/// no hex of the result has two faces on the boundary. `outer_of` (if given) receives, per
/// point of the result, the point it was copied from (itself for old points), and
/// `is_outer` 1 for the new boundary points. InputError if depth <= 0.
HexMesh pillow(const HexMesh& mesh, double depth, std::vector<Index>* copied_from = nullptr,
               std::vector<std::uint8_t>* is_outer = nullptr);

/// Closest points and line hits on a triangle surface (one CGAL AABB tree; thread-safe queries).
/// Degenerate triangles are left out; the triangle indices returned are the surface's.
class SurfaceProjection {
 public:
  explicit SurfaceProjection(const TriMesh& surface);
  ~SurfaceProjection();
  SurfaceProjection(SurfaceProjection&&) noexcept;
  SurfaceProjection& operator=(SurfaceProjection&&) noexcept;
  /// Closest point, and (if given) the triangle it lies on and its barycentric coordinates.
  Vec3 closest_point(const Vec3& p, Index* triangle = nullptr, Vec3* barycentric = nullptr) const;
  /// A nearest point found by walking the surface from `triangle` (a triangle of the
  /// surface, updated to the one the answer lies on): on to the closest of the triangles that
  /// share a point with the current one while it is strictly closer. The answer is a local
  /// minimum of the distance to p over the surface, never farther from p than the starting
  /// triangle's closest point. Started near the answer (from the triangle of the last answer
  /// for a point moved by a little, as the smoothing does) it is the closest point, found in
  /// a step or two instead of a tree search. Where the surface has another local minimum,
  /// though, a walk may end there: a point inside a thin slab, nearer its bottom, walks to
  /// the top if it starts on the top (the smoothing's point stays on its sheet, where the
  /// global search jumps across). With `triangle` == kInvalidIndex (or a degenerate one, or
  /// after 256 steps), closest_point(p, &triangle).
  Vec3 closest_point_walking(const Vec3& p, Index& triangle) const;
  /// The point of the surface on the segment p +- reach * direction nearest to p, its
  /// triangle and barycentric coordinates; false when the segment misses the surface.
  /// With `facing`, only triangles whose normal (right-hand rule) has a positive dot
  /// product with *facing count: a point on one side of a thin slab or a narrow gap then does
  /// not land on the sheet across it, which faces the other way.
  bool nearest_on_line(const Vec3& p, const Vec3& direction, double reach, Vec3& hit, Index& triangle,
                       Vec3& barycentric, const Vec3* facing = nullptr) const;
  /// Squared distance from p to the surface.
  double squared_distance(const Vec3& p) const;
  /// The surface's triangles that meet the axis-aligned cube of half-width `radius` around p
  /// (appended to `triangles`, in no particular order).
  void triangles_near(const Vec3& p, double radius, std::vector<Index>& triangles) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The hex extraction's guard against the far sheet of a narrow gap or a thin slab: a
/// boundary point (of `boundary_quads`) whose place on `surface` faces against its boundary
/// neighbours' (the dot product of its surface normal with the sum of theirs is negative)
/// moves to where the line through their centroid along that sum meets a triangle facing
/// that way, within twice the ring's radius. `points` lie on `surface`, which `onto_surface`
/// projects onto. Returns how many points moved.
std::size_t move_boundary_points_to_facing_sheet(std::vector<Vec3>& points,
                                                 const std::vector<std::array<Index, 4>>& boundary_quads,
                                                 const TriMesh& surface, const SurfaceProjection& onto_surface);

struct SurfaceMapRelaxation {
  std::size_t folded_before = 0, folded_after = 0;  ///< source triangles whose image faces into the target
  std::size_t moved_points = 0;
  int sweeps = 0;
  int rounds = 1;  ///< relaxations run (more when they alternate with smooth_surface_map())
  /// Branch points (SurfaceMapDefects::branched_points) the fold relaxation left, and after
  /// their regions were laid out afresh and relaxed again (unwound_regions times).
  std::size_t branched_before = 0, branched_after = 0;
  int unwound_regions = 0;
};

/// §5.2.1's local relaxation of a surface map onto a polycube: `image` holds, per point of
/// `source`, its position on `target` (P's triangles, `onto_target` their projection). A
/// source triangle is folded when its image's normal does not point out of the target (the
/// mean facet axis of its points). The points of folded triangles, and more rings around
/// them while the folds stay, move on the target towards their neighbours' centroid when that
/// raises the worst orientation of their triangles, until nothing is folded or after
/// `max_sweeps` sweeps. Then branch points (a ring wound twice around its point with every
/// triangle facing out, which the fold test does not see) have the region around them laid
/// out afresh by barycentric positions on the target, and the folds that makes relaxed again,
/// the region doubling up to 16 rings while branch points stay.
SurfaceMapRelaxation relax_surface_map(const TriMesh& source, std::vector<Vec3>& image, const TriMesh& target,
                                       const SurfaceProjection& onto_target, int max_sweeps = 100);

/// What keeps a surface map onto a polycube from being one-to-one.
struct SurfaceMapDefects {
  std::size_t folded = 0;  ///< triangles whose image faces into the target (as relax_surface_map())
  /// Points whose image ring winds around them other than once, seen along the target's
  /// normal there: twice at a branch point (the ring covers P twice with every triangle
  /// facing out), never at a point of a one-to-one map.
  std::size_t branched_points = 0;
  /// The image triangles' total area over the target's, minus 1: at most 0 for a one-to-one
  /// map (triangles across P's edges cut its corners), above 0 where the image covers P twice.
  double area_excess = 0;
};

/// The triangles of `source` whose image (per point, on `target`) faces into the target, as
/// relax_surface_map() counts them; nothing moves. InputError when the sizes do not match.
std::size_t folded_triangles(const TriMesh& source, const std::vector<Vec3>& image, const TriMesh& target,
                             const SurfaceProjection& onto_target);

/// Measures `image` (per point of `source`, on `target`) for the defects above.
SurfaceMapDefects surface_map_defects(const TriMesh& source, const std::vector<Vec3>& image, const TriMesh& target,
                                      const SurfaceProjection& onto_target);

struct SurfaceMapUnwinding {
  std::size_t branched_before = 0, branched_after = 0;  ///< SurfaceMapDefects::branched_points
  std::size_t moved_points = 0;                         ///< points of the regions laid out afresh
};

/// Lays out afresh the regions of `image` (per point of `source`, on `target`) within
/// `rings` rings of its branch points: each point of a region goes to the projection onto the
/// target of its neighbours' centroid, sweep after sweep with the region's rim held (Tutte's
/// barycentric embedding, on the target), which winds once around every point. It may fold
/// triangles where the rim is not convex: relax_surface_map(), which calls this while branch
/// points stay, unfolds them. InputError when the sizes do not match or rings < 0.
SurfaceMapUnwinding unwind_surface_map(const TriMesh& source, std::vector<Vec3>& image, const TriMesh& target,
                                       const SurfaceProjection& onto_target, int rings = 2);

struct SurfaceMapSmoothing {
  /// The distortion energy per unit of reference area, over the triangles that are not
  /// folded (1 for a map that is conformal and spreads area evenly).
  double energy_before = 0, energy_after = 0;
  /// The largest area distortion of a triangle, max(a, 1/a) for a = its image area over its
  /// share of the target's (folded triangles left out).
  double worst_area_ratio_before = 1, worst_area_ratio_after = 1;
  std::size_t moved_points = 0;
  int sweeps = 0;
};

/// Lowers the distortion of a fold-free surface map onto a polycube: each point of `image`
/// (one per point of `reference`, on `target`) slides on the target to lower a conformal plus
/// area energy of its triangles against their shapes in `reference`, never folding one, until
/// a sweep gains less than 1e-4 of the energy or after `max_sweeps`. Points of triangles that
/// are folded stay put (relax_surface_map() mends those). Spreads the strips that the
/// projection along the charts' axes stretches over P's facets (§5.2.1).
SurfaceMapSmoothing smooth_surface_map(const TriMesh& reference, std::vector<Vec3>& image, const TriMesh& target,
                                       const SurfaceProjection& onto_target, int max_sweeps = 50);

struct HexSmoothingOptions {
  int iterations = 100;       ///< sweeps over all points (fewer when the gains stop)
  bool move_boundary = true;  ///< boundary points slide on the target surface
  /// Boundary points where two of their boundary quads meet at more than this angle stay
  /// put (sharp edges and corners of the input, §4.5.3); 0: every boundary point slides.
  double feature_angle_degrees = 0;
  /// Stop when neither the worst nor the mean scaled Jacobian gains this much per sweep (over
  /// 5 sweeps). The mean creeps up by about 1e-4 per sweep for dozens of sweeps: at 1e-4 the
  /// hand stopped after 65 sweeps at 0.9386, at 3e-5 it goes on to 100 and 0.9430.
  double min_improvement = 3e-5;
  /// No smoothing sweeps when a hex stays inverted after the untangling: for a caller that
  /// has another extraction to try and would throw this one away (the sweeps are most of
  /// the time, and they do not untangle).
  bool sweeps_only_if_untangled = false;
  /// After the sweeps, while the worst hex is below this, joint ascents of the worst hexes
  /// (each followed by up to 10 sweeps, at most 10 rounds). They cost up to 100 more
  /// sweeps, so they are kept for a worst hex a user would notice; 0: none.
  double polish_below = 0.4;
  /// Before those ascents, while the worst hex is below polish_below, at most this many
  /// rounds of fresh starts of the worst cluster: its points go back to where the smoothing
  /// found them (or on from there to their neighbours' centroids) and are untangled and
  /// swept again, kept only if the worst hex rises (each round tries 1 to 4 rings of points
  /// around the cluster, from either start; 0: none).
  int restart_rounds = 4;
  /// Joint ascents of the mean scaled Jacobian end the smoothing (the worst hex held) while
  /// the mean is below this (0: none, 1: always). They cost about a tenth of the run: the
  /// default leaves a mesh alone whose mean already meets the published polycube results.
  double mean_below = 0.94;
  bool progress = false;
};

struct HexSmoothingResult {
  std::size_t inverted_before = 0, inverted_after = 0;  ///< hexes with scaled Jacobian <= 0
  double min_scaled_jacobian_before = 0, min_scaled_jacobian_after = 0;
  double mean_scaled_jacobian_before = 0, mean_scaled_jacobian_after = 0;
  int sweeps = 0;
  bool sweeps_held_back = false;  ///< by sweeps_only_if_untangled (a bulk tangle gets none anyway)
  int polish_rounds = 0;          ///< joint ascents of the worst hexes after the sweeps
  int mean_ascent_rounds = 0;     ///< joint ascents of the mean after them
  int restarts = 0;               ///< fresh starts of the worst cluster kept
  int restarts_tried = 0;         ///< fresh starts of the worst cluster tried
  double mean_scaled_jacobian_before_ascent = 0;
  std::size_t feature_points = 0;  ///< boundary points held on a sharp feature
  /// Boundary points of hexes the untangling could not fix on the surface, then let off it.
  std::size_t released_boundary_points = 0;
};

/// A projection onto a surface, told where it answered last for the same mesh point:
/// `*triangle` is the surface triangle of its last answer (kInvalidIndex before the first),
/// and the projection sets it to the triangle of this answer. A walk from there
/// (SurfaceProjection::closest_point_walking) visits a triangle or two instead of a tree:
/// most smoothing tries move a point by a fraction of an edge. A projection may ignore it.
using HintedProjection = std::function<Vec3(const Vec3& point, Index* triangle)>;

/// Untangling and smoothing of a hex mesh in place. Inverted hexes are untangled first
/// (each point moved to raise the smallest corner Jacobian of its hexes); then every point
/// moves to improve the worst scaled Jacobian of the hexes around it, and a move is accepted
/// only if that worst value does not drop (so no valid hex ever inverts). Boundary points
/// (points of hex_boundary_quads) are moved and then put back with `project` when
/// move_boundary is set, and stay where they are otherwise; boundary points of hexes still
/// inverted after the untangling are then let off the surface for a second untangling (see
/// HexSmoothingResult::released_boundary_points). `project` must be thread-safe.
HexSmoothingResult smooth_hex_mesh(HexMesh& mesh, const HintedProjection& project,
                                   const HexSmoothingOptions& options = {});

// ---------------------------------------------------------------------------
// The volumetric polycube map (§5.2) and the whole pipeline

/// The preprocessing of §5.2.2, extended: every edge between two boundary points (index <
/// boundary_points) that is not a surface edge is split at its midpoint, in every tet around
/// it, so no tet is fixed entirely by the boundary constraints and no straight segment
/// between two pinned points must stay inside the target. The mesh stays conforming and
/// positively oriented; new points are appended. Returns the number of edges split.
std::size_t split_boundary_tets(TetMesh& tets, std::size_t boundary_points);

struct VolumetricMapOptions {
  int frame_smoothing_iterations = 0;  ///< 0: a direct sparse solve of the frames' smoothness
  int untangle_sweeps = 300;           ///< at most this many sweeps of local untangling
  /// Where boundary point i goes, when not empty (one per boundary point): the polycube
  /// P's points nearest to Q's, so the parameter domain is P's solid (§5.2.1). The frames
  /// still come from boundary_target's triangles, which projection onto P can fold.
  std::vector<Vec3> boundary_positions;
  bool progress = false;
};

struct VolumetricMap {
  std::vector<Vec3> parameter;  ///< per tet-mesh point: its position in the parameter domain
  std::size_t flipped_before_untangling = 0;
  std::size_t flipped = 0;                   ///< tets with non-positive parameter volume after untangling
  std::size_t released_boundary_points = 0;  ///< boundary points the untangling had to move off Q
  double volume_distortion = 0;              ///< D_v of §5.3 (1 for a volume-preserving map)
  double seconds_frames = 0, seconds_solve = 0, seconds_untangle = 0;
};

/// The volumetric map of §5.2.2: a frame field on the tets (boundary tets take the rotation of
/// their boundary face from `boundary_source` to `boundary_target`, interior frames minimise
/// the smoothness energy C_S over the dual graph), then the positions minimising (5.1),
/// sum over tets of vol(t) |grad u^k - X^k|^2, with every boundary point fixed at its target
/// (sparse Cholesky: CHOLMOD), then local untangling of any flipped tet (damped
/// Gauss-Newton on Knupp's untangling function per interior point; boundary points of tets
/// that stay flipped are released as a last resort). `tets` has the
/// surface points first (tetrahedralize()'s layout): point i < boundary_target.size() is
/// boundary point i. InputError when the sizes do not match.
VolumetricMap volumetric_map(const TetMesh& tets, const TriMesh& boundary_source, const TriMesh& boundary_target,
                             const VolumetricMapOptions& options = {});

struct FlippedTetRepair {
  std::size_t flipped_before = 0, flipped_after = 0;
  std::size_t cavities = 0;        ///< cavities re-triangulated as stars
  std::size_t removed_tets = 0;    ///< tets in them
  std::size_t added_tets = 0;      ///< cone tets that replaced them
  std::size_t largest_cavity = 0;  ///< tets
  int largest_ring = 0;            ///< vertex rings the largest growth needed
};

/// The flipped tets a map's untangling leaves, repaired by re-triangulation: around each
/// cluster of flipped tets a cavity (the cluster and its first vertex ring, grown through the
/// faces that keep its boundary from being star-shaped, or by further vertex rings, up to
/// `max_rings` in all) is removed and replaced by the cone from one new point over its boundary faces, placed in the
/// kernel of that boundary both in the source (`tets.points`) and in the parameter domain
/// (`parameter`, one position per point), so every cone tet is positive in both. Where no
/// cavity has both kernels, the cluster stays. The map on the cavities' boundaries, and so
/// every boundary point's image, is unchanged; new points are appended to both arrays, the
/// points inside the cavities stay unreferenced.
FlippedTetRepair repair_flipped_tets(TetMesh& tets, std::vector<Vec3>& parameter, int max_rings = 4);

struct TetMapUntanglingOptions {
  /// Vertex rings around the flipped tets, one joint untangling per entry while tets stay
  /// flipped (a round is kept only if fewer stay flipped).
  std::vector<int> rings{3, 6, 12};
  /// A first round at rings[0] with the surface points pinned to their targets (the map's
  /// boundary stays on P where the interior points alone can untangle it).
  bool pinned_first = true;
  /// The spring that holds a freed surface point near its target, per squared mean image edge
  /// of drift, against a tet's energy of about 3 (the foldover-free energy of a similarity).
  double spring = 1.0;
  int max_steps = 30;        ///< continuation steps (ε updates) per round
  int max_iterations = 200;  ///< L-BFGS iterations per step
  /// Steps of a round after the first that leaves no tet flipped: they only reshape the
  /// region's tets (the bunny's freed round was valid after 2 of its 30 steps, 0.5 of 6.3 s;
  /// with 5 such steps fertility's mean hex fell 0.941 -> 0.939, with 10 it stays 0.940).
  int max_steps_once_valid = 10;
  /// A round stops after this many steps if none has left fewer tets flipped than the round
  /// started with (such a round is not kept). Never, by default; polycube_hex_mesh()'s default
  /// map untangling gives up after 12 (HexOptions::map_untangling).
  int give_up_after_steps = std::numeric_limits<int>::max();
  /// A tet counts as flipped when its det J, normalised to average 1 over the mesh, is at
  /// most this: a tet flattened to 1e-16 of its share passes a sign test but is no map (the
  /// bunny's made D_v read 7e9).
  double flat = 1e-6;
};

struct TetMapUntangling {
  std::size_t flipped_before = 0, flipped_after = 0;  ///< flipped or flat (TetMapUntanglingOptions::flat)
  int rounds = 0, rings = 0;                          ///< rounds run; vertex rings of the last
  std::size_t region_tets = 0;                        ///< tets of the last round's energy
  std::size_t free_points = 0;                        ///< free points of the last kept round
  std::size_t moved_boundary_points = 0;              ///< boundary points off their targets afterwards
  double boundary_drift = 0;                          ///< largest distance of one from its target, in mean image edges
  double min_det_after = 0;                           ///< smallest det J of the last kept round
  int steps = 0;                                      ///< continuation steps of the last kept round
  int rounds_given_up = 0;  ///< rounds stopped by give_up_after_steps (no step left fewer flipped)
};

/// The tets of `source` whose image at `parameter` is inverted or flat: det J, normalised to
/// average 1 over the mesh (image volume over source volume, times the source's total over
/// the image's), at most `flat`. InputError when the sizes do not match.
std::size_t flipped_or_flat_tets(const TetMesh& source, std::span<const Vec3> parameter, double flat = 1e-6);

/// Joint untangling of what a map's untangling leaves flipped (or flat: options.flat): the
/// points within `rings` vertex rings of those tets whose tets all lie in that region move together, surface
/// points (index < boundary_count) included, by the continuation method of Garanzha et al.
/// 2021 on the Jacobians J = E_parameter E_source^-1 of the region's tets, each freed surface
/// point held near `boundary_targets[v]` by a spring. The map outside the region does not
/// change. InputError when the sizes do not match.
TetMapUntangling untangle_tet_map(const TetMesh& source, std::vector<Vec3>& parameter, std::size_t boundary_count,
                                  std::span<const Vec3> boundary_targets, const TetMapUntanglingOptions& options = {});

struct HexOptions {
  PolycubeOptions polycube;
  std::size_t target_hexes = 0;  ///< about this many hexes (0: use `size`)
  double size = 0;               ///< hex edge length in the input's units (0 with no target: 1 per voxel)
  bool padding = true;           ///< one pillow layer under the boundary
  bool features = false;         ///< keep sharp edges and corners (--features; 30 degrees)
  /// The pillow layer's depth, share of the mean boundary edge. 0.5 rather than 0.3: a deeper
  /// layer leaves a padding hex room to follow the surface's bend (worst hex: fertility 0.19 -> 0.39,
  /// bunny 0.08 -> 0.19; mean 0.94 reached on the hand; screwdriver 0.53 -> 0.42).
  double padding_depth = 0.5;
  double tet_size = 0;  ///< tet edge length of the map's mesh (0: the surface's mean edge)
  /// Refuse (Error) a grid of more hexes than this, padding included: a polycube with
  /// thousands of corners has a coarsest grid far above any target (one layer per slab
  /// between facet planes), and meshing it would run for long and end out of memory.
  std::size_t max_hexes = 4'000'000;
  /// When the mesh made on the merged-plane polycube keeps an inverted hex, make it again
  /// with merge_planes_within = 0 and keep the better (fewer inverted, then larger minimum).
  bool retry_without_merging = true;
  /// What the map's untangling and star cavities leave flipped, untangled jointly with the
  /// surface freed on springs (untangle_tet_map(); --no-untangle-map turns it off). On by
  /// default over 3 vertex rings (`map_untangling.rings`): that clears the bunny's, fertility's
  /// and the screwdriver's maps in 1-10 s. --untangle-map widens it to 3, 6 and 12 rings, which
  /// costs up to minutes where 3 rings do not do (kitten_40k: 100 s, still flipped).
  bool untangle_map_jointly = true;
  /// A round gives up after 12 steps that leave no fewer tets flipped than it started with:
  /// the rounds that gain on the data set do so within 7 steps, while kitten_40k's first map
  /// spent 2 x 30 steps, 12 s, on two rounds that never got below their 46 flipped tets.
  /// --untangle-map runs TetMapUntanglingOptions' defaults instead (3, 6 and 12 rings, never
  /// giving up: over 12 rings the closed dog's 180 flipped tets go only after more than 12
  /// steps without a gain).
  TetMapUntanglingOptions map_untangling{.rings = {3}, .give_up_after_steps = 12};
  /// The joint untangling also on a map onto Q (the unmerged polycube's): off by default, as
  /// there it frees nothing over 3 rings (the dogs' 234 and 123 flipped tets, 40 s each);
  /// --untangle-map turns it on (over 12 rings dog0's 234 go to 124, in 4 minutes).
  bool untangle_map_onto_q = false;
  /// smooth_surface_map() on the map's boundary after §5.2.1's relaxation (--smooth-surface-map).
  /// Off as a first step by default: it moves single models' worst hex both ways (the bunny
  /// 0.62 -> 0.66, fertility 0.63 -> 0.56), and on fertility the map it gives keeps 5 flipped
  /// tets where the unsmoothed one comes out flip-free. By default it runs only as the second
  /// chance below.
  bool smooth_surface_map = false;
  /// Without smooth_surface_map: where tets stay flipped after the joint untangling, the
  /// surface map smoothed and the volumetric map made again, keeping the map with fewer
  /// flipped tets (kitten_40k: 46 -> 0).
  bool smooth_surface_map_if_flipped = true;
  /// With smooth_surface_map, while folds stay after it, up to this many more rounds of
  /// relaxation and smoothing (they stop when a round leaves as many folds as the last).
  int surface_map_rounds = 3;
  HexSmoothingOptions smoothing;
  bool progress = false;
};

struct HexResult {
  HexMesh mesh;                 ///< in the input's frame
  PolycubeResult polycube;      ///< the domain (chapter 4)
  TetMesh tets;                 ///< the input solid's tet mesh
  std::size_t split_edges = 0;  ///< edges split by split_boundary_tets()
  std::vector<Vec3> parameter;  ///< its points in the parameter domain
  /// §5.2.1's relaxation of Q's projection onto P (the map's boundary); empty when the map
  /// ends on Q (plane merging off)
  SurfaceMapRelaxation surface_map;
  /// smooth_surface_map() after that relaxation (empty when the map ends on Q).
  SurfaceMapSmoothing surface_map_smoothing;
  VolumetricMap map;  ///< statistics of the map (its `flipped` counts flat tets too: TetMapUntanglingOptions::flat)
  FlippedTetRepair flipped_repair;  ///< the re-triangulation of what the map's untangling left flipped
  TetMapUntangling map_untangling;  ///< the joint untangling of what the star cavities left flipped
  double hex_size = 0;              ///< the grid's target edge length in the parameter domain
  std::size_t padding_hexes = 0;
  std::size_t interior_points_outside = 0;  ///< grid points outside Q, put on it before smoothing
  /// boundary points the map put on a sheet facing against their neighbours', moved back
  /// (move_boundary_points_to_facing_sheet)
  std::size_t points_moved_to_facing_sheet = 0;
  HexSmoothingResult smoothing;
  HexQuality quality;
  double geometric_deviation = 0;  ///< D_g: Hausdorff(hex boundary, input) / input diagonal
  /// The map's untangling released boundary points, and the mesh made with the grid's
  /// boundary on the map's boundary kept an inverted hex, lost a part of the model (D_g >
  /// 0.1) or had a worst hex below 0.3, or those points ended over 50 voxels off P: the
  /// extraction was made (also, or first) with the boundary on P ...
  bool extraction_retried = false;
  bool boundary_from_p_kept = false;  ///< ... and that mesh was better, so this is it
  /// How far the farthest boundary point of the map ended from its target on the domain's
  /// boundary (P's point nearest to Q's, or Q's with unmerged planes), in voxels: the map's
  /// untangling released it ...
  double map_boundary_drift = 0;
  /// ... and it was so far off P (over 50 voxels) that the mesh was made from P first, and
  /// that one was sound (no inverted hex, worst at least 0.3, D_g at most 0.1), so the mesh
  /// from the map's boundary was not made.
  bool map_boundary_skipped = false;
  bool merging_retried = false;  ///< the first mesh had inverted hexes and was made again unmerged
  bool unmerged_kept = false;    ///< ... and the unmerged one was better, so this is it
  /// The surface map onto the merged-plane polycube kept more than 2% of Q's triangles
  /// folded after its relaxation, so the first attempt stopped there and the mesh was made
  /// on the unmerged polycube (merging_retried and unmerged_kept are set too).
  bool merged_map_folded = false;
  /// Tets stayed flipped, so the surface map was smoothed and the volumetric map made again
  /// (HexOptions::smooth_surface_map_if_flipped) ...
  bool surface_map_smoothed_after_flips = false;
  /// ... and that map had fewer flipped tets, so it is the one used (else the first).
  bool surface_map_smoothed_kept = false;
  std::vector<std::pair<std::string, double>> stage_seconds;
};

/// Chapters 4-5 end to end: the polycube, the tet mesh, the volumetric map, the integer grid
/// of the polycube with padding, mapped back by barycentric interpolation, then smoothed.
HexResult polycube_hex_mesh(const TriMesh& surface, const HexOptions& options = {});

}  // namespace structmesh
