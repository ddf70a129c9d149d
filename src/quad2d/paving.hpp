// Private pieces of the paving mesher (pave(), quad2d.hpp): the growing mesh, the
// advancing front with its spatial grid, and the Paver that drives rows, seams,
// splits, templates and the fallback (Blacker & Stephenson 1991; dissertation §3.3.1).
//
// Everything is flat arrays with 32-bit indices. The front is a set of closed loops
// stored as doubly linked lists of front nodes; every front edge has the unmeshed
// region on its left, so an outer loop runs counter-clockwise and a hole clockwise.
// A front node refers to a mesh point; a point can carry several front nodes (both
// sides of a chord that joined a hole to the outer loop).
#pragma once

#include "quad2d/quad_cleanup.hpp"
#include "structmesh/mesh.hpp"
#include "structmesh/quad2d.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace structmesh::paving {

inline constexpr double kPi = 3.14159265358979323846;

inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Counter-clockwise angle from direction a to direction b, in [0, 2π).
inline double ccw_angle(const Vec2& a, const Vec2& b) {
  const double t = std::atan2(cross(a, b), a.dot(b));
  return t < 0 ? t + 2 * kPi : t;
}

/// Verdict's quad scaled Jacobian in the plane with +z as reference normal
/// (quality.hpp): the minimum over the corners of the corner's cross product over
/// the two edge lengths; -1 for a zero-length edge so that it is never accepted.
inline double scaled_jacobian(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3) {
  const Vec2 e0 = p1 - p0, e1 = p2 - p1, e2 = p3 - p2, e3 = p0 - p3;
  const double l0 = e0.squaredNorm(), l1 = e1.squaredNorm(), l2 = e2.squaredNorm(), l3 = e3.squaredNorm();
  if (!(l0 > 1e-300 && l1 > 1e-300 && l2 > 1e-300 && l3 > 1e-300)) return -1;
  const double j0 = cross(e3, e0) / std::sqrt(l3 * l0);
  const double j1 = cross(e0, e1) / std::sqrt(l0 * l1);
  const double j2 = cross(e1, e2) / std::sqrt(l1 * l2);
  const double j3 = cross(e2, e3) / std::sqrt(l2 * l3);
  return std::min(std::min(j0, j1), std::min(j2, j3));
}

/// One round of a compass pattern search: tries the eight directions at distance
/// `step` from `at` and moves to every one that raises `quality` (a function of the
/// position); true when it moved. Shared by paving's and the cleanup's optimisation.
template <class Quality>
bool pattern_search_round(Vec2& at, double step, double& now, Quality&& quality) {
  constexpr double kDiag = 0.70710678118654752;
  bool improved = false;
  for (const Vec2& d : {Vec2(1, 0), Vec2(-1, 0), Vec2(0, 1), Vec2(0, -1), Vec2(kDiag, kDiag), Vec2(-kDiag, -kDiag),
                        Vec2(kDiag, -kDiag), Vec2(-kDiag, kDiag)}) {
    const Vec2 to = at + step * d;
    const double q = quality(to);
    if (q > now + 1e-12) {
      now = q;
      at = to;
      improved = true;
    }
  }
  return improved;
}

inline double quad_area(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3) {
  return 0.5 * (cross(p2 - p0, p3 - p1));
}

/// Do the closed segments ab and cd share a point? Exact orientation signs on the
/// double inputs are not needed here: a near-touch counts as a touch (conservative).
bool segments_intersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d);
/// The point of segment ab closest to p.
inline Vec2 closest_on_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  return a + (l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0) * ab;
}
inline double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  return (closest_on_segment(p, a, b) - p).norm();
}

/// The mesh being built: input points first, then new points; quads counter-clockwise.
/// Point -> incident quads as singly linked records in flat arrays (quads are only
/// ever added, never removed).
struct GrowingMesh {
  std::vector<Vec2> points;
  std::vector<std::array<Index, 4>> quads;
  std::vector<Index> first_record;  // per point
  std::vector<Index> record_quad, record_next;
  Index fixed_count = 0;  // input points: never moved

  Index add_point(const Vec2& p);
  Index add_quad(const std::array<Index, 4>& q);
  /// Minimum scaled Jacobian over the quads around point p, with p placed at `at`.
  double min_quality_around(Index p, const Vec2& at) const;
  template <class F>
  void for_each_quad(Index p, F&& f) const {
    for (Index r = first_record[p]; r != kInvalidIndex; r = record_next[r]) f(record_quad[r]);
  }
  int quad_count(Index p) const {
    int c = 0;
    for (Index r = first_record[p]; r != kInvalidIndex; r = record_next[r]) ++c;
    return c;
  }
  /// Moves every quad of point `from` to point `to` (a seam): `from` is left unused.
  void merge_point(Index from, Index to);
  /// Rebuilds the point -> quad records, skipping removed quads (first index invalid).
  void rebuild_records();
};

/// Uniform grid over the part's bounding box holding front edges (by their start
/// node) in every cell their bounding box overlaps. Entries are removed lazily: an
/// entry is stale once its start node died or points to another next node.
class EdgeGrid {
 public:
  void init(const BoundingBox2& box, double cell, std::size_t expected_points);
  void insert(Index node, Index next, const Vec2& a, const Vec2& b);
  /// Visits (node, next) of every live entry in the cells overlapping [lo, hi]; an
  /// edge can be visited more than once. `live(node, next)` says whether it is current.
  template <class Live, class F>
  void visit(const Vec2& lo, const Vec2& hi, Live&& live, F&& f) {
    int x0, y0, x1, y1;
    cell_range(lo, hi, x0, y0, x1, y1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        Index* link = &head_[static_cast<std::size_t>(y) * nx_ + x];
        while (*link != kInvalidIndex) {
          const Index e = *link;
          if (!live(node_[e], next_node_[e])) {
            *link = link_[e];  // unlink the stale entry and recycle it
            link_[e] = free_;
            free_ = e;
            continue;
          }
          if (!f(node_[e], next_node_[e])) return;
          link = &link_[e];
        }
      }
    }
  }
  double cell() const { return cell_; }

 private:
  void cell_range(const Vec2& lo, const Vec2& hi, int& x0, int& y0, int& x1, int& y1) const;
  Vec2 origin_{0, 0};
  double cell_ = 1, inv_cell_ = 1;
  int nx_ = 1, ny_ = 1;
  std::vector<Index> head_;
  std::vector<Index> node_, next_node_, link_;
  Index free_ = kInvalidIndex;
};

struct Loop {
  Index head = kInvalidIndex;
  Index size = 0;
  double area = 0;  // signed: > 0 for the outer boundary of an unmeshed component
  bool alive = false;
  int stuck = 0;  // consecutive steps without progress
  /// Parts of the front may face each other within a few sizes (the last row saw a
  /// short gap or failed somewhere): only then are chord splits searched.
  bool narrow = true;
  bool listed = false;  // in Paver::negative_loops_
};

/// A slot of a quad being added: an existing front node or a planned new point.
struct Slot {
  bool planned = false;
  Index id = kInvalidIndex;  // front node, or planned point
};

/// pave() without the grid interior: paving, retries at other sizes, cleanup (at most
/// `cleanup_passes` passes), and (if `polish`) the polish of a part whose worst quad is
/// below 0.6.
PavedPart pave_whole(const Polygon2& boundary, const PavingOptions& options, bool polish,
                     int cleanup_passes = kCleanupPasses);

class Paver {
 public:
  Paver(const Polygon2& boundary, const PavingOptions& options);
  PavedPart run();
  double size() const { return size_; }

 private:
  // --- front (paving_front.cpp)
  Index new_node(Index point, Index loop);
  void set_next(Index a, Index b);  // links a -> b and registers the edge
  void kill_node(Index n);
  const Vec2& pos(Index node) const { return mesh_.points[node_point_[node]]; }
  double interior_angle(Index node) const;
  /// Would point p, leaving the front with `added` more quads, be an interior point of
  /// valence below 3 (a doublet that no smoothing can fix)?
  /// Points added after the last front node (the fallback's, during repairs) are on no front.
  bool makes_doublet(Index p, int added) const {
    return p >= mesh_.fixed_count && p < point_fronts_.size() && point_fronts_[p] == 1 &&
           mesh_.quad_count(p) + added < 3;
  }
  bool edge_live(Index node, Index next) const { return node_alive_[node] && node_next_[node] == next; }
  /// Does the segment ab cross a front edge not incident to points pa / pb
  /// (kInvalidIndex: a new point)?
  bool segment_blocked(const Vec2& a, const Vec2& b, Index pa, Index pb);
  /// Distance from p to the nearest front edge within `radius`, ignoring edges incident
  /// to the points in `ignore`; `radius` when there is none.
  double clearance(const Vec2& p, double radius, std::span<const Index> ignore);
  /// Distance from the segment ab to the nearest front point within `radius`, ignoring
  /// the points in `ignore`; `radius` when there is none.
  double segment_clearance(const Vec2& a, const Vec2& b, double radius, std::span<const Index> ignore);
  /// Is any front point (other than the quad's) strictly inside the convex quad?
  bool point_inside(const std::array<Vec2, 4>& q, std::span<const Index> ignore);
  /// Adds a quad whose existing nodes form one chain of front edges; new points are
  /// created for the planned slots. Returns false (and changes nothing) when the quad
  /// is not valid: poor shape, leaves the unmeshed region, crosses the front.
  bool try_quad(const std::array<Slot, 4>& slots, double min_quality, double local_size);
  void relabel(Index start, Index stop, Index loop);
  /// Adds a closed front loop through these mesh points (in order) and returns its
  /// id; a loop of negative area (a hole) is listed in negative_loops_.
  Index add_loop(std::span<const Index> points, double area);
  std::vector<Index> loop_nodes(Index loop) const;

  // --- rows, seams and splits (paving_rows.cpp)
  bool row(Index loop);
  bool seams(Index loop);
  bool clip_ear(Index loop);
  bool splits(Index loop);
  /// The open holes (alive loops of negative area, other than `loop`) with an odd
  /// node count, each as a point of its front that lies on no other front; dead
  /// entries leave negative_loops_ on the way.
  std::vector<Vec2> odd_hole_points(Index loop);
  bool apply_chord(Index a, Index b, int interior, bool join);
  double local_size(Index node) const;
  /// Distance from the node along direction dir to the front (edges not at the node),
  /// or `range` when nothing is nearer.
  double ray_gap(Index node, const Vec2& dir, double range);

  // --- templates and fallback (paving_close.cpp)
  bool close_with_template(Index loop);
  /// A ring of quads inside a star-shaped loop whose inner loop (a regular polygon for
  /// small loops, a shrunk copy otherwise) is left to the front.
  bool close_with_ring(Index loop);
  void fallback(Index loop);
  /// Triangulates a region (rings of front points; point_of maps them to mesh
  /// points), pairs the triangles into quads and adds them; Error when that fails.
  void close_region(const Polygon2& region, const std::vector<Index>& point_of, const std::string& where);
  bool contains_open_hole(Index loop) const;
  bool hole_inside(Index hole, Index loop, const std::vector<Vec2>& ring) const;

  // --- the driver (paving.cpp)
  /// One step on a loop: template, slit removal, chord splits, seams, ear clipping of
  /// small loops, or a row; false when nothing could be done.
  bool step(Index loop);
  bool remove_slit(Index loop);

  // --- smoothing (paving_smooth.cpp)
  void smooth_points(std::span<const Index> pts, int sweeps);
  /// Moves an interior point towards the mean of its edge neighbours (Laplacian) when
  /// that does not lower the worst quad around it below min(its old value, 0.5);
  /// returns the distance moved.
  double smooth_point(Index p);
  /// Pattern search maximising the minimum scaled Jacobian of the quads around p.
  bool optimize_point(Index p, double step_scale = 0.15);
  void final_smoothing();
  /// Removes every interior point of valence 2 by merging its two quads.
  void collapse_doublets();
  /// Collapses quads between two valence-3 points where that lowers the singular count.
  void collapse_diamonds();

  void emit_quad(const std::array<Index, 4>& q);
  /// Remeshes the neighbourhood of every quad that smoothing left inverted or
  /// degenerate (paving.cpp); false when some are left.
  bool repair_inverted();
  /// Untangles the zones of inverted quads (their points and a few rings around them)
  /// with untangle_quads(); true when no quad is left inverted.
  bool untangle_inverted();

  const PavingOptions options_;
  double size_ = 0;
  GrowingMesh mesh_;
  EdgeGrid grid_;
  std::vector<Index> node_point_, node_next_, node_prev_, node_loop_;
  std::vector<std::uint8_t> node_alive_;
  std::vector<std::uint32_t> point_fronts_;  // per point: live front nodes on it
  std::vector<Loop> loops_;
  std::vector<Index> negative_loops_;  // loops that had a negative area (holes), once each, dead or alive
  std::vector<Vec2> planned_pos_;
  std::vector<Index> planned_node_;
  std::vector<Index> index_of_;  // scratch: position of a node along its loop (splits)
  std::vector<Index> released_;  // points that left the front since the last smoothing
  PavingStats stats_;
};

}  // namespace structmesh::paving
