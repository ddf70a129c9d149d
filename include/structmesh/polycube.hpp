// Polycube domain construction (chapter 4 of the dissertation): principal-axis
// alignment and the rotation-driven pre-deformation of §4.3 into a pseudo-polycube Q,
// voxelization of Q at the Morse resolution of §4.4.1, and the homotopic
// morphological optimisation of §4.4.2 (energy (4.1)) on the voxel set, whose
// boundary is the polycube P.
#pragma once

#include "structmesh/mesh.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace structmesh {

// ---------------------------------------------------------------------------
// Pre-alignment and pre-deformation (§4.3)

/// A rotation about a centre: p -> rotation * (p - centre) + centre.
struct RigidAlignment {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Vec3 centre = Vec3::Zero();
  Vec3 apply(const Vec3& p) const { return rotation * (p - centre) + centre; }
  Vec3 unapply(const Vec3& p) const { return rotation.transpose() * (p - centre) + centre; }
};

/// The rotation taking the principal axes of the solid bounded by `surface` (the
/// eigenvectors of its volume covariance, from signed tetrahedra) to X, Y and Z, the
/// axis of largest extent (variance) first, about the solid's centroid; a proper
/// rotation (det +1). Signs, and the frame inside an eigenspace of equal variances
/// (a cube, a sphere), are the ones nearest the identity (largest trace), so a model
/// already on its principal axes is left alone. InputError if the surface has no
/// triangles or bounds no volume.
RigidAlignment principal_axes_alignment(const TriMesh& surface);

/// Axis labels of faces: 0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z.
inline constexpr int kAxisLabels = 6;
/// The label of the axis nearest to a (non-zero) normal; ties to the lower label.
int nearest_axis_label(const Vec3& normal);
/// The unit vector of a label.
Vec3 axis_of_label(int label);

struct PseudoPolycubeOptions {
  /// Rotation-driven deformation rounds (each: normals, nearest-axis rotations, one
  /// sparse solve, the intersection check); stops earlier when the mean normal deviation
  /// changes by less than `tolerance_degrees`.
  int max_iterations = 30;
  double tolerance_degrees = 0.05;
  bool progress = false;
};

struct PseudoPolycube {
  TriMesh surface;          ///< Q: the input's connectivity, deformed points
  std::vector<int> labels;  ///< per triangle: nearest axis of its normal on Q
  std::size_t charts = 0;   ///< edge-connected groups of triangles with one label
  /// Charts that break the polycube rule of §4.3: adjacent to a chart of the opposite
  /// label, or to fewer than four charts (the "wedges" voxelization corrects).
  std::size_t wedges = 0;
  int iterations = 0;
  /// Vertices the intersection guard froze where the deformation would have made the
  /// surface cross itself (they keep the position they had then).
  std::size_t frozen_vertices = 0;
  /// Area-weighted mean angle (degrees) between the triangles' normals and their
  /// labels' axes, on the input and on Q.
  double input_deviation_degrees = 0, deviation_degrees = 0;
};

/// The rotation-driven deformation of §4.3 (after Gregson et al. 2011), iterated: each
/// triangle normal is rotated towards its nearest axis by the minimal rotation R_t, and
/// the Poisson system of §4.3, x_i - mean(x_j) = mean(R_ij (x~_i - x~_j)) over the
/// one-ring, is solved in the least-squares sense over the edges (uniform weights,
/// sparse Cholesky) with R_ij the mean of the rotations of edge ij's two triangles and
/// x~ the positions before the iteration. (§4.3 prints x~_j - x~_i, which with R = I
/// would reflect the surface through a point, and carries R on the vertices; see
/// src/polycube/pseudo_polycube.cpp for why the triangles carry it here.) Every step is
/// checked with check_surface()'s exact predicates and vertices where the surface would
/// cross itself are frozen, so Q is a valid solid boundary like the input. The result
/// has the input's volume and centroid. InputError if the surface is not a closed,
/// oriented, manifold, intersection-free solid boundary.
PseudoPolycube pseudo_polycube(const TriMesh& surface, const PseudoPolycubeOptions& options = {});

// ---------------------------------------------------------------------------
// Voxel sets (§4.4): the union of closed unit cubes, voxel (x, y, z) spanning
// origin + size * [x, x+1] x [y, y+1] x [z, z+1].

struct VoxelGrid {
  std::array<int, 3> dims{0, 0, 0};
  Vec3 origin = Vec3::Zero();
  double size = 1;
  std::vector<std::uint8_t> occupied;  ///< x fastest, then y, then z; 1 = in the solid

  VoxelGrid() = default;
  VoxelGrid(std::array<int, 3> dims_, Vec3 origin_, double size_)
      : dims(dims_),
        origin(origin_),
        size(size_),
        occupied(static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2], 0) {}
  bool inside(int x, int y, int z) const {
    return x >= 0 && y >= 0 && z >= 0 && x < dims[0] && y < dims[1] && z < dims[2];
  }
  std::size_t index(int x, int y, int z) const {
    return static_cast<std::size_t>(x) +
           static_cast<std::size_t>(dims[0]) * (y + static_cast<std::size_t>(dims[1]) * z);
  }
  /// Whether voxel (x, y, z) is occupied; false outside the grid.
  bool at(int x, int y, int z) const { return inside(x, y, z) && occupied[index(x, y, z)] != 0; }
  void set(int x, int y, int z, bool value) { occupied[index(x, y, z)] = value ? 1 : 0; }
  std::size_t count() const;
  /// Grid vertices: (dims + 1) per axis, x fastest.
  std::size_t vertex_index(int x, int y, int z) const {
    return static_cast<std::size_t>(x) +
           static_cast<std::size_t>(dims[0] + 1) * (y + static_cast<std::size_t>(dims[1] + 1) * z);
  }
  std::size_t vertex_count() const { return static_cast<std::size_t>(dims[0] + 1) * (dims[1] + 1) * (dims[2] + 1); }
  Vec3 vertex_position(int x, int y, int z) const { return origin + size * Vec3(x, y, z); }
  /// The coordinates (x, y, z) of the voxel with this index().
  std::array<int, 3> coordinates(std::size_t index) const {
    const auto nx = static_cast<std::size_t>(dims[0]), ny = static_cast<std::size_t>(dims[1]);
    return {static_cast<int>(index % nx), static_cast<int>(index / nx % ny), static_cast<int>(index / (nx * ny))};
  }
  /// The voxel whose cube holds p, clamped into the grid.
  std::array<int, 3> voxel_of(const Vec3& p) const;
  /// Whether an occupied voxel lies within `radius` voxels of (x, y, z) along every axis
  /// (the (2 radius + 1)^3 block around it, itself included).
  bool occupied_within(int x, int y, int z, int radius) const;
};

/// Topology of the union of the occupied closed cubes (§4.5.1): the cells of the
/// cubical complex (k0 vertices, k1 edges, k2 squares, k3 cubes), the Euler
/// characteristic chi = k0 - k1 + k2 - k3 (4.2), and the Betti numbers: b0 the
/// 26-connected components of the voxels, b2 the 6-connected components of the empty
/// space that do not reach outside the grid (voids), b1 = b0 + b2 - chi (handles).
struct VoxelTopology {
  std::int64_t vertices = 0, edges = 0, squares = 0, cubes = 0;
  std::int64_t euler = 0;
  std::int64_t components = 0, handles = 0, voids = 0;
  bool operator==(const VoxelTopology&) const = default;
};
VoxelTopology voxel_topology(const VoxelGrid& grid);

/// Whether flipping voxel (x, y, z) (removing it when occupied, adding it when empty)
/// keeps the topology of the voxel union and of its complement: the (26, 6) simple
/// point test (Bertrand's topological numbers T26 = 1 and T6 = 1 in the 3x3x3
/// neighbourhood), equivalent to the simple removals of §4.4.2 on the cubical complex.
/// The voxel's own state is ignored. InputError for a voxel outside the grid.
bool is_simple_voxel(const VoxelGrid& grid, int x, int y, int z);

/// Whether the voxel set is well-composed: no 2x2 square of voxels around a grid edge
/// holds exactly two diagonally opposite voxels (of either state), and no 2x2x2 block
/// holds exactly two antipodal voxels of one state. Exactly then the boundary of the
/// union is a 2-manifold, i.e. a valid polycube surface.
bool is_well_composed(const VoxelGrid& grid);
/// The same test restricted to the blocks that contain voxel (x, y, z).
bool is_well_composed_near(const VoxelGrid& grid, int x, int y, int z);

/// The boundary of the voxel union as an outward quad mesh: one quad per face between
/// an occupied and an empty voxel (in voxel scan order, then -X, +X, -Y, +Y, -Z, +Z),
/// on the grid vertices it uses, numbered in vertex_index order. `corner` (if given)
/// gets one flag per returned point: 1 where the incident boundary quads have normals
/// along all three axes (a polycube corner, the E_c of (4.1)). A closed 2-manifold when
/// the set is well-composed.
QuadMesh voxel_boundary(const VoxelGrid& grid, std::vector<std::uint8_t>* corner = nullptr);

/// Corners of the polycube: boundary grid vertices whose incident boundary faces have
/// normals along all three axes. On a well-composed set these are exactly the vertices
/// of the boundary quad mesh whose valence is not 4, the dissertation's corners.
std::size_t polycube_corners(const VoxelGrid& grid);

// ---------------------------------------------------------------------------
// Voxelization (§4.4.1)

/// The voxel size eta of §4.4.1: for each axis the critical heights of the height
/// function on Q (vertices that are local extrema or saddles of x, y or z over their
/// one-ring), grouped when closer than `epsilon`; eta is a third of the smallest gap
/// between consecutive groups on any axis, and at most `max_size`.
struct MorseResolution {
  double size = 0;
  std::array<std::vector<double>, 3> levels;  ///< per axis: the grouped critical heights, ascending
};
MorseResolution morse_voxel_size(const TriMesh& surface, double epsilon, double max_size);

/// The voxels of a grid of edge `size` whose centres are inside the closed surface,
/// with one empty layer around them. InputError for a surface with no triangles or a
/// size <= 0 or more than `max_voxels` voxels.
VoxelGrid voxelize(const TriMesh& surface, double size, std::size_t max_voxels = 200'000'000);

/// For parts of the surface thinner than a voxel, which voxelize() turns into a sieve of
/// voxels (each hole a handle the input lacks): adds empty voxels whose closed cube the
/// surface meets, nearest to the surface first, wherever an addition does not join a
/// 26-connected piece to itself (no new handle), fills the voids that leaves, then removes
/// the added voxels again while they are simple, farthest from the surface first. Returns
/// the number of voxels added that stayed (0 and the grid unchanged when none is needed).
/// InputError for a surface with no triangles.
std::size_t cover_thin_features(VoxelGrid& grid, const TriMesh& surface);

/// For parts of the surface no voxel reaches (an appendage thinner than a voxel, which
/// voxelize() drops without changing the topology): a vertex with no occupied voxel within
/// one voxel of its own is far; the empty voxels that triangles at far vertices meet are
/// added, in rings outwards from the set, each where it touches the set and its addition is
/// simple (is_simple_voxel), so the topology is kept. Returns the number added (0 and the
/// grid unchanged when no vertex is far). InputError for an empty grid.
std::size_t cover_far_points(VoxelGrid& grid, const TriMesh& surface);

/// Unsigned distance from the grid vertices (VoxelGrid::vertex_index) to the surface,
/// exact (closest point) for the vertices within `band` voxels (Chebyshev) of a square
/// on the boundary of the voxel union, where the optimisation can move that boundary;
/// the others get band * size (at most their distance, give or take the voxel the
/// boundary is off the surface). InputError for a surface with no triangles.
std::vector<double> vertex_distances(const VoxelGrid& grid, const TriMesh& surface, int band = 12);

// ---------------------------------------------------------------------------
// Homotopic morphology (§4.4.2) inside a box of voxels [lo, hi) (clamped to the grid).
// Each voxel flips only if it is simple and the set stays well-composed near it, so
// topology and the manifold boundary are kept. Voxels outside the box never change.
// Each returns the number of voxels whose state changed.

struct VoxelBox {
  std::array<int, 3> lo{0, 0, 0}, hi{0, 0, 0};
};
/// One layer: the occupied voxels of `box` with an empty 26-neighbour at the start are
/// removed, in scan order (x fastest), each if it is still simple when reached (and the
/// set well-composed around it after). Candidates refused in a pass are tried again in
/// another until a pass removes nothing: one that waits for a neighbour later in the
/// scan is not left behind (a cube loses its whole outer layer).
std::size_t homotopic_erode(VoxelGrid& grid, const VoxelBox& box);
/// One layer: the empty voxels of `box` with an occupied 26-neighbour are added, likewise.
std::size_t homotopic_dilate(VoxelGrid& grid, const VoxelBox& box);
/// `layers` erosions, then `layers` dilations that add back only voxels the erosions
/// removed (removes ridges thinner than 2 * layers). An opening never adds a voxel, so
/// the occupied voxels around the box do not grow into it.
std::size_t homotopic_open(VoxelGrid& grid, const VoxelBox& box, int layers);
/// `layers` dilations, then `layers` erosions that remove only voxels the dilations
/// added (fills valleys narrower than 2 * layers). A closing never removes a voxel.
std::size_t homotopic_close(VoxelGrid& grid, const VoxelBox& box, int layers);

// ---------------------------------------------------------------------------
// Polycube optimisation, energy (4.1): E_p = E_c + alpha * E_g.

struct PolycubeEnergy {
  std::size_t corners = 0;  ///< E_c
  double deviation = 0;     ///< E_g (see polycube_energy)
  double total = 0;         ///< E_c + alpha * E_g
};
/// E_g has two terms: the distances to the pseudo-polycube Q at the boundary grid vertices
/// (how far P's surface is from Q's), and, when `reference` (Q's voxelization) is given,
/// the distance to Q of every voxel whose state differs from the reference (the volume P
/// gained or lost, weighted by depth). The distance to the nearest surface alone does not
/// see a thick region eroded from one side (its boundary stays near the other side), and
/// a window optimisation on it alone ate half of the genus-3 plate's thickness.
/// `vertex_distance`: per grid vertex (VoxelGrid::vertex_index), its distance to Q in
/// whatever unit E_g is to have (InputError if the size is not vertex_count() or a value
/// is not finite, or if the reference's dimensions differ).
PolycubeEnergy polycube_energy(const VoxelGrid& grid, std::span<const double> vertex_distance, double alpha,
                               const VoxelGrid* reference = nullptr);

struct PolycubeOptimizationOptions {
  double alpha = 20;     ///< the weight of E_g in (4.1)
  int max_window = 5;    ///< the moving window's largest half-size (radius); down to 1
  double threshold = 0;  ///< an operation must lower E_p by more than this
  bool progress = false;
};

struct PolycubeOptimizationResult {
  PolycubeEnergy before, after;
  std::size_t openings = 0, closings = 0;  ///< accepted operations
  std::size_t sweeps = 0;                  ///< passes over the boundary voxels, all windows
  /// Openings refused because they would have cut off points of Q (covered_points below).
  std::size_t refused_openings = 0;
};

/// The moving-window optimisation of §4.4.2: for window radius r from max_window down to
/// 1, every boundary voxel c (occupied, with an empty 26-neighbour; those at the start of
/// a sweep, in scan order) gets the better of a homotopic opening and a homotopic
/// closing of r layers in the box c +- 2r, kept if it lowers E_p by more than the
/// threshold (and by more than the rounding of the distance sums) and undone otherwise;
/// sweeps repeat until a sweep changes nothing. Topology (voxel_topology) never changes,
/// and a well-composed set stays well-composed. Deterministic: TBB threads evaluate windows ahead,
/// and the result does not depend on their number. InputError for a `vertex_distance`
/// of the wrong size or with a value that is not finite, a negative or non-finite alpha
/// or threshold, or max_window < 1.
///
/// With `covered_points` (Q's points, in the grid's frame), an opening is also refused
/// where it would leave one of them that had an occupied voxel within 3 voxels (by index)
/// without one: E_g does not see a thin limb go (its voxels lie near Q, and so does the
/// stump's new boundary).
PolycubeOptimizationResult optimize_polycube(VoxelGrid& grid, std::span<const double> vertex_distance,
                                             const PolycubeOptimizationOptions& options = {},
                                             std::span<const Vec3> covered_points = {});

// ---------------------------------------------------------------------------
// The whole construction of chapter 4.

/// Repairs the critical configurations of is_well_composed(): simple voxels near them are
/// added or removed (additions first, in scan order) when that lowers the number of
/// critical 2x2x2 blocks around the flipped voxel, so the topology is kept.
/// Returns the number of flipped voxels; Error if a configuration cannot be resolved
/// this way (the caller then refines the grid).
std::size_t make_well_composed(VoxelGrid& grid);

struct PlaneMergeResult {
  std::array<std::size_t, 3> planes_before{}, planes_after{};  ///< distinct facet planes per axis
  std::size_t removed = 0;                                     ///< planes emptied
  std::size_t flips = 0;                                       ///< voxels flipped and kept
};

/// Fewer distinct facet planes: every facet of a plane moves onto the nearest plane within
/// `max_shift` voxels that other facets already use, by simple-voxel flips layer by layer;
/// a plane's moves are kept only if the plane is gone, no new plane appeared and the voxels
/// are still well-composed (merge_facet_planes.cpp). The topology is kept. The hex grid of
/// chapter 5 takes at least one layer per slab between planes, so this is what brings its
/// hex count near the one asked for. max_shift 0 only counts the planes.
PlaneMergeResult merge_facet_planes(VoxelGrid& grid, int max_shift = 2, bool progress = false);

struct PolycubeOptions {
  bool align = true;                  ///< principal-axes pre-alignment (§4.3)
  PseudoPolycubeOptions deformation;  ///< pre-deformation (§4.3)
  double epsilon_ratio = 0.01;        ///< Morse grouping epsilon, share of the diagonal (§4.4.1)
  double voxel_size = 0;              ///< 0: the Morse resolution eta, refined until the topology is kept
  int max_resolution =
      160;  ///< the first size: at most this many voxels along the longest axis (refinements may double it)
  /// The moving-window optimisation (§4.4.2); optimization.max_window = 0 skips it.
  PolycubeOptimizationOptions optimization;
  /// After the optimisation, facets move by up to this many voxels onto planes other facets
  /// use (merge_facet_planes; 0: off).
  int merge_planes_within = 2;
  bool progress = false;
};

struct PolycubeResult {
  RigidAlignment alignment;             ///< input -> aligned frame (identity without align)
  PseudoPolycube pseudo;                ///< Q, in the aligned frame
  MorseResolution morse;                ///< eta and the critical levels on Q
  VoxelGrid voxels;                     ///< the optimised polycube's voxels
  VoxelTopology expected;               ///< of the input solid: components, genus, no voids
  VoxelTopology initial, final;         ///< of the voxel set after voxelization and after optimisation
  std::size_t well_composed_flips = 0;  ///< voxels make_well_composed() flipped
  int refinements = 0;                  ///< times the voxel size was halved to keep the topology
  /// Times the pre-deformation was redone with half the rounds because no voxel size
  /// kept the topology of the deformed surface Q (the deformation brought two parts of
  /// the surface closer than a voxel, or made it touch itself).
  int deformation_retries = 0;
  /// Voxels cover_thin_features() added because the voxels with centres inside Q did
  /// not keep its topology at the size used (0: not needed).
  std::size_t thin_feature_voxels = 0;
  /// Voxels cover_far_points() added for parts of Q that no voxel reached.
  std::size_t far_point_voxels = 0;
  /// Whether the optimisation ran again with Q's points guarded (optimize_polycube's
  /// covered_points) because the first run cut off a limb: a point of Q that had a voxel
  /// within 3 had none within 10 after it.
  bool optimization_guarded = false;
  PolycubeOptimizationResult optimization;  ///< its `after` energy includes the plane merging
  PolycubeEnergy before_merge;              ///< the optimisation's own result, before plane merging
  PlaneMergeResult plane_merge;
  /// The optimised voxels before plane merging (empty when merging is off), so that
  /// without_plane_merging() need not redo chapter 4.
  VoxelGrid voxels_before_merge;
  QuadMesh surface;                  ///< P = the boundary of the voxels (outward quads)
  std::vector<std::uint8_t> corner;  ///< per point of `surface`: a polycube corner
  std::vector<std::pair<std::string, double>> stage_seconds;
};

/// Chapter 4 end to end: alignment, pseudo-polycube Q, voxelization of Q at the Morse
/// resolution (halved, at most three times, until the voxel set has the input's
/// components, handles and no voids), well-composed repair, and the optimisation of
/// (4.1). InputError for a surface that does not bound a solid; Error if no resolution
/// within max_resolution keeps the topology.
PolycubeResult build_polycube(const TriMesh& surface, const PolycubeOptions& options = {});

/// The polycube build_polycube() gives with merge_planes_within = 0, from one built with
/// merging (its voxels_before_merge): the same Q and optimised voxels, the facet planes
/// left where the optimisation put them, in a fraction of the time of building it again.
PolycubeResult without_plane_merging(const PolycubeResult& merged);

}  // namespace structmesh
