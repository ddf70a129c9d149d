// 3D shape guarding (dissertation §2.2): which boundary vertices and faces a point
// inside a solid sees (§2.2.1), and the set cover that picks the fewest guards
// (§2.2.2, ILP (2.2)-(2.3)) with the reductions of the progressive ILP (§2.2.3).
//
// Set-cover vocabulary. The candidates' visibility is passed as CompressedRows
// `sets`: sets.row(c) lists the elements (boundary faces) candidate c covers. In the
// ILP (2.2)-(2.3) there is one binary variable x_c per set and one constraint per
// element, so SetCoverReduction and IlpSetCoverResult say "rows" for elements and
// "columns" for sets, as the dissertation's reduction rules and the solvers do.
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace structmesh {

// ---------------------------------------------------------------------------
// Visibility (§2.2.1)

struct VisibilityOptions {
  /// The part of the segment next to the target vertex v that the ray test leaves
  /// out, as a fraction of the segment: the ray p -> v stops at t = 1 - eps. v's own
  /// faces meet the ray at t = 1 and must not count as blockers; rounding the
  /// coordinates to float moves that hit by about 1e-7 of the coordinates' size, so
  /// eps is widened to `float_margin` x (bounding-box diagonal) / |v - p| for short
  /// segments. A surface crossing inside the excluded window that is not on a face of
  /// v goes unseen (a sheet thinner than eps |v - p| right in front of v).
  double relative_eps = 1e-5;
  double float_margin = 1e-5;
  /// Embree's robust mode (RTC_SCENE_FLAG_ROBUST: no optimisations that cost
  /// accuracy), so that a ray through a shared edge or vertex hits a triangle there
  /// rather than slipping between them. On segments through edges and vertices that
  /// are exact in float (the tests) both settings block every one; the cost of robust
  /// mode was within the noise of a loaded 2-core machine.
  bool robust = true;
};

/// Vertex visibility of §2.2.1 against a closed, outward-oriented triangle surface.
///
/// Rule. Boundary vertex v is visible from p iff the segment [p, v] meets the surface
/// only at v and leaves v into the solid's interior. Touching counts as meeting:
///  - a segment that passes through an edge or a vertex of the surface before v, or
///    runs along a face, is blocked, even if it never leaves the solid (grazing past a
///    reflex edge is blocked);
///  - at v, the direction p - v must point strictly into the solid's interior cone at
///    v. The test takes the feature of v's face fan nearest to the direction (a face,
///    an edge of v, or v itself) and the sign against that feature's (pseudo)normal
///    (Bærentzen and Aanæs 2005), which is right at convex, concave and saddle vertices
///    alike; a direction in the plane of one of v's faces (the segment runs along
///    it) is blocked. So a point outside the solid sees no vertex whose
///    neighbourhood it approaches from outside, even when nothing lies in between.
/// p == v is visible (the segment is the single point v).
///
/// Precision. The local test at v is in double. The segment test runs in Embree in
/// float: coordinates are translated to the bounding box's centre and rounded to float
/// (a relative error of about 6e-8 of the box's size), so segments that pass within
/// about that distance of an edge or vertex may be decided either way, and hits in the
/// last eps of the segment (VisibilityOptions) are not looked for.
///
/// Built once per surface; holds the Embree device and scene (released on
/// destruction). Movable, not copyable. sees() is thread-safe.
class VisibilityOracle {
 public:
  /// InputError when the surface is not closed and consistently oriented (every edge
  /// in exactly two faces, traversed once each way), has a zero-area face, or encloses
  /// negative volume (inward normals).
  explicit VisibilityOracle(const TriMesh& surface, const VisibilityOptions& options = {});
  ~VisibilityOracle();
  VisibilityOracle(VisibilityOracle&&) noexcept;
  VisibilityOracle& operator=(VisibilityOracle&&) noexcept;
  VisibilityOracle(const VisibilityOracle&) = delete;
  VisibilityOracle& operator=(const VisibilityOracle&) = delete;

  /// Whether surface vertex `vertex` is visible from p (the rule above).
  bool sees(const Vec3& p, Index vertex) const;
  /// visible[i] = sees(p, vertices[i]) for every i, the rays traced as one stream
  /// (1.4x faster on the TOSCA dog than one call per vertex; sees() is a stream of
  /// one). Embree may trace a longer stream in packets, whose kernels may decide a ray
  /// that grazes an edge or vertex otherwise than its single-ray one (both block such
  /// rays up to float rounding); the answers depend only on p and `vertices`, so equal
  /// calls give equal answers.
  void sees_many(const Vec3& p, std::span<const Index> vertices, std::span<std::uint8_t> visible) const;
  /// Whether the segment [p, v] meets the surface before the excluded window at v
  /// (the ray part of the rule alone, without the test at v).
  bool segment_blocked(const Vec3& p, Index vertex) const;
  /// Whether direction d, leaving vertex v, points strictly into the solid (the test
  /// at v alone).
  bool enters_interior(Index vertex, const Vec3& d) const;

  std::size_t vertex_count() const;
  std::size_t face_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Row c lists, ascending, the faces of `surface` whose three vertices are all visible
/// from candidates[c] (face visibility of §2.2). `surface` must be the mesh the oracle
/// was built from. Each vertex used by a face is tested once per candidate. Parallel
/// over candidates (TBB); the result does not depend on the thread count.
CompressedRows visible_faces(const VisibilityOracle& oracle, const TriMesh& surface, std::span<const Vec3> candidates);

// ---------------------------------------------------------------------------
// Set cover (§2.2.2-2.2.3)

/// Whether the union of sets.row(c) over c in `chosen` is {0, ..., element_count - 1}.
bool covers_all(const CompressedRows& sets, std::size_t element_count, std::span<const Index> chosen);

/// Greedy set cover (§2.2.2): repeatedly take the set covering the most still
/// uncovered elements, ties to the lowest index. Deterministic; O(total size x log)
/// with counts updated through the element -> sets transpose and a lazy priority
/// queue. Returns the chosen sets in the order picked. InputError when an element
/// index is out of range or an element is in no set (names the first such element
/// and how many there are).
std::vector<Index> greedy_set_cover(const CompressedRows& sets, std::size_t element_count);

/// The instance left after the reduction rules of §2.2.3, applied until none applies:
///  - essential column (rule 1): a row (element) in only one column (set) forces
///    that column; the rows it covers are removed with it;
///  - duplicate rows: rows with the same columns; one is kept (the lowest index);
///  - row dominance (rule 2): a row whose columns are a superset of another row's is
///    covered whenever that row is: removed;
///  - column dominance (rule 3): a column whose rows are a subset of another column's
///    is never needed: removed (of two equal columns the lower index is kept).
/// Rule 4 (splitting into independent blocks) is applied by ilp_set_cover().
/// Every optimal cover of the reduced instance plus the forced columns is an optimal
/// cover of the input.
struct SetCoverReduction {
  std::size_t rows_before = 0, rows_after = 0;        // elements
  std::size_t columns_before = 0, columns_after = 0;  // sets
  std::vector<Index> forced;                          // sets every cover includes (ascending)
  std::vector<Index> kept_rows;                       // elements left, ascending (input ids)
  std::vector<Index> kept_columns;                    // sets left, ascending (input ids)
  /// Row k: the elements set kept_columns[k] covers, as positions in kept_rows.
  CompressedRows reduced_sets;
  std::size_t rounds = 0;  // passes over the four rules until nothing changed
};

/// InputError as for greedy_set_cover().
SetCoverReduction reduce_set_cover(const CompressedRows& sets, std::size_t element_count);

struct IlpSetCoverResult {
  std::vector<Index> chosen;  // ascending set ids; always a cover
  bool optimal = false;       // proven optimal by CBC (or by the reductions alone)
  double lower_bound = 0;     // on the number of sets of any cover
  std::size_t rows_before = 0, rows_after = 0, columns_before = 0, columns_after = 0;
  std::size_t greedy_size = 0;  // size of the greedy cover of the reduced instance plus the forced sets
  std::size_t blocks = 0;       // independent blocks of the reduced instance, solved one by one (rule 4)
  double seconds = 0;
};

/// Minimum set cover, ILP (2.2)-(2.3): min sum x_c subject to sum_{c covering e} x_c >= 1
/// for every element e, x binary; after reduce_set_cover(), split into independent
/// blocks (rule 4 of §2.2.3: sets linked through shared elements), each solved by COIN-OR CBC
/// (stand-alone solver defaults, no log) within `time_limit_seconds` of wall time. CBC
/// starts from the greedy cover, or from `start` (set ids, completed greedily to a cover
/// of each block) where that is smaller, and the best is returned, so a time-out still
/// gives a cover (optimal = false, lower_bound from CBC's bound). InputError as for
/// greedy_set_cover(); Error if the result were not a cover.
IlpSetCoverResult ilp_set_cover(const CompressedRows& sets, std::size_t element_count, double time_limit_seconds = 60,
                                std::span<const Index> start = {});

/// Local search on a cover (the progressive ILP's last step): each set with the
/// group_size - 1 sets of `cover` sharing most elements with it is replaced by fewer sets
/// when an exact ILP (ilp_set_cover(), `time_limit_seconds` each) over the elements only
/// that group covers finds fewer; repeated until no group improves. A group as large as
/// the cover makes it the exact optimum. `cover` stays a cover; returns how many sets it
/// lost. No group starts after `total_seconds`. InputError when `cover` is not a cover of
/// every element some set covers, or names a set that does not exist.
std::size_t improve_set_cover(const CompressedRows& sets, std::size_t element_count, std::vector<Index>& cover,
                              std::size_t group_size, double time_limit_seconds = 60,
                              double total_seconds = std::numeric_limits<double>::infinity());

// ---------------------------------------------------------------------------
// The whole guarding stage (§2.2): candidates from the curve skeleton, visibility,
// set cover.

enum class GuardMethod : std::uint8_t { Greedy, Ilp, Pilp };

struct GuardOptions {
  GuardMethod method = GuardMethod::Ilp;
  /// Skeleton resampling spacing; 0: 1% of the bounding-box diagonal.
  double spacing = 0;
  /// The skeleton is computed on the surface simplified to this many vertices (0: the
  /// surface itself); visibility is always tested against the input surface.
  std::size_t skeleton_vertices = 10000;
  /// CBC time limit of the ILP (seconds); the best cover found so far is kept. For the
  /// progressive ILP, per level.
  double time_limit = 60;
  /// Progressive ILP (§2.2.3): the coarsest level's vertex count, the vertices each
  /// finer level adds (the dissertation's 5k and 10k), and the share of a level's
  /// surface area below which a guard is insignificant and re-examined (its ε, 10%).
  std::size_t pilp_coarsest_vertices = 5000;
  std::size_t pilp_level_step = 10000;
  double pilp_significance = 0.1;
  /// Progressive ILP, at the end: groups of this many guards (one and those sharing most
  /// faces with it) are replaced by fewer when a small exact ILP over the faces only
  /// they see finds a smaller cover (a local search beyond the dissertation; 0 or 1: off).
  /// Groups of 8 rather than 4, measured with the same candidates: rocker arm 10 -> 9 (the
  /// ILP's 9), gorilla 90 -> 87 (ILP 86), victoria 115 -> 113 (112), dog 74 -> 73 (72),
  /// for 1-5 s more; 12 found no more than 8.
  std::size_t pilp_exchange_group = 8;
  bool progress = false;
  /// Guard a surface that intersects itself (scanned models such as the TOSCA ones)
  /// instead of refusing it: visibility is then taken against the surface as it is,
  /// and inside tests count ray crossings. It must still be closed, manifold and
  /// outward-oriented (fill_holes() of check.hpp closes holes).
  bool allow_self_intersections = false;
  /// After the ILP or progressive ILP: rounds of candidates where one guard might replace
  /// two of the cover (in the kernel of the faces only those two see), each round
  /// followed by local exchanges of the cover (improve_set_cover), while they gain and
  /// for about this many seconds (0: off); the ILP then tries to prove the optimum over
  /// all candidates in the time left.
  double refine_seconds = 3;
  /// At most this many extra candidates for faces no skeleton point sees.
  std::size_t max_added_candidates = 4000;
  /// Extra candidates are added in rounds, each round's vertices at least this far apart
  /// (0: 2% of the bounding-box diagonal).
  double added_candidate_spread = 0;
  /// Candidate guards given by the caller instead of the skeleton's (those outside the
  /// solid are left out; faces none of them sees still get extra candidates, until each
  /// is seen once: after the skeleton, until each is seen 8 times). With the
  /// candidate_points of an earlier result, reruns share their candidates: CGAL's
  /// skeleton is not repeatable within a process (it orders edges by address).
  std::vector<Vec3> candidates;
};

struct Guard {
  Vec3 position;
  /// The input faces this guard is responsible for (it sees each of them; a face seen
  /// by several chosen guards goes to the nearest), ascending.
  std::vector<Index> faces;
};

/// One level of the progressive ILP.
struct PilpLevel {
  std::size_t vertices = 0, faces = 0;  ///< of the level's surface
  std::size_t kept = 0;                 ///< guards of coarser levels kept (significant)
  std::size_t dropped = 0;              ///< ... re-examined (insignificant): back among the candidates
  std::size_t universe = 0;             ///< faces left to cover
  std::size_t added = 0;                ///< guards the level's ILP added
  std::size_t guards = 0;               ///< after the level
  bool optimal = false;                 ///< the level's ILP proved optimal
  double seconds = 0;
};

struct GuardResult {
  std::vector<Guard> guards;
  std::vector<Index> face_guard;  ///< per input face: its guard (kInvalidIndex: seen by no candidate)
  /// Guards whose face sets share a surface edge (the guard graph of §2.4).
  std::vector<std::array<Index, 2>> graph;
  std::size_t skeleton_nodes = 0;
  std::size_t candidates = 0;          ///< inside the solid, after resampling
  std::vector<Vec3> candidate_points;  ///< every candidate (skeleton points, then added ones)
  std::size_t added_candidates = 0;    ///< inward offsets of vertices no skeleton point saw
  std::size_t uncovered_faces = 0;     ///< seen by no candidate at all (left out of the cover)
  std::size_t self_intersections = 0;  ///< face pairs that cross (allow_self_intersections only)
  /// The greedy cover's size over the same candidates as the cover (kernel ones included).
  std::size_t greedy_guards = 0;
  std::size_t greedy_guards_before_refinement = 0;  ///< ... over the candidates before the kernel rounds
  std::size_t guards_before_refinement = 0;         ///< the cover's size before the kernel rounds
  std::size_t kernel_candidates = 0;     ///< candidates the kernel rounds added (see GuardOptions::refine_seconds)
  std::size_t refinement_rounds = 0;     ///< kernel rounds that lowered the guard count
  std::size_t refinement_exchanges = 0;  ///< guards the kernel rounds' local exchanges saved
  /// ILP only: the cover after the kernel rounds is proven optimal over every candidate,
  /// kernel ones included (`optimal` is about the candidates before them).
  bool refined_optimal = false;
  double refined_lower_bound = 0;
  bool optimal = false;    ///< the ILP proved its cover minimal
  double lower_bound = 0;  ///< the ILP's bound on the minimum
  std::size_t rows_before = 0, rows_after = 0, columns_before = 0, columns_after = 0;
  std::vector<PilpLevel> levels;   ///< progressive ILP only, coarsest first
  std::size_t pilp_pruned = 0;     ///< progressive ILP: guards found redundant at the end
  std::size_t pilp_exchanges = 0;  ///< progressive ILP: guards saved by the local exchanges at the end
  std::vector<std::pair<std::string, double>> stage_seconds;
};

/// Fewest interior points that together see every face of a closed surface (§2.2):
/// curve-skeleton candidates (resampled, joints kept, inside the solid), face
/// visibility by VisibilityOracle, then the greedy, exact (ILP) or progressive (PILP:
/// coarse-to-fine levels of the surface, see GuardOptions) set cover. Faces no
/// skeleton point sees get candidates halfway between each of their vertices and the
/// skeleton node that absorbed it, and just inside the vertex (the dissertation adds
/// the invisible vertices themselves). InputError for an open, non-manifold,
/// self-intersecting or inward-oriented surface.
GuardResult guard_surface(const TriMesh& surface, const GuardOptions& options = {});

}  // namespace structmesh
