// Star decomposition (dissertation §2.3) by exact region growing from the guards; the
// growth rule and order are explained in star.hpp.
#include "structmesh/error.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/star.hpp"

#include <Eigen/Geometry>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <queue>
#include <string>

namespace structmesh {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

Point to_point(const Vec3& p) { return {p.x(), p.y(), p.z()}; }

// Vertices of the face of a tet opposite its vertex i (any order: the rule compares
// two orientations against the same face).
std::array<Index, 3> face_opposite(const std::array<Index, 4>& tet, int i) {
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  return {tet[kFace[i][0]], tet[kFace[i][1]], tet[kFace[i][2]]};
}

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The mesh's points converted once to CGAL points (the predicates take them by reference).
struct Geometry {
  const TetMesh& mesh;
  std::vector<Point> points;

  explicit Geometry(const TetMesh& m) : mesh(m), points(m.points.size()) {
    tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t v) { points[v] = to_point(m.points[v]); });
  }
  CGAL::Orientation side(Index t, int i, const Point& p) const {
    const auto f = face_opposite(mesh.tets[t], i);
    return CGAL::orientation(points[f[0]], points[f[1]], points[f[2]], p);
  }
  // Whether p lies strictly on tet t's side of the plane of its face opposite vertex i.
  bool inner_side(Index t, int i, const Point& p) const {
    const CGAL::Orientation s = side(t, i, p);
    return s != CGAL::COPLANAR && s == side(t, i, points[mesh.tets[t][i]]);
  }
  // 4: strictly inside t; a value < 4 with no face's plane separating: on t's boundary;
  // -1: outside (some face plane has p strictly on the far side).
  int containment(Index t, const Point& p) const {
    int strict = 0;
    for (int i = 0; i < 4; ++i) {
      const CGAL::Orientation s = side(t, i, p);
      if (s == CGAL::COPLANAR) continue;
      if (s != side(t, i, points[mesh.tets[t][i]])) return -1;
      ++strict;
    }
    return strict;
  }
  Vec3 centroid(Index t) const {
    const auto& tet = mesh.tets[t];
    return 0.25 * (mesh.points[tet[0]] + mesh.points[tet[1]] + mesh.points[tet[2]] + mesh.points[tet[3]]);
  }
  double volume(Index t) const {
    const auto& tet = mesh.tets[t];
    const Vec3& a = mesh.points[tet[0]];
    return std::abs((mesh.points[tet[1]] - a).cross(mesh.points[tet[2]] - a).dot(mesh.points[tet[3]] - a)) / 6.0;
  }
};

void check_input(const TetMesh& solid, const Geometry& geometry, const std::vector<std::array<Index, 4>>& neighbors) {
  if (solid.tets.empty()) throw InputError("star decomposition: the mesh has no tetrahedra");
  for (std::size_t t = 0; t < solid.tets.size(); ++t)
    for (const Index v : solid.tets[t])
      if (v >= solid.points.size())
        throw InputError("star decomposition: tet " + std::to_string(t) + " uses point " + std::to_string(v) + " of " +
                         std::to_string(solid.points.size()));
  std::atomic<std::size_t> flat{std::numeric_limits<std::size_t>::max()};
  std::atomic<std::size_t> overlap{std::numeric_limits<std::size_t>::max()};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, solid.tets.size()), [&](const auto& range) {
    for (std::size_t t = range.begin(); t != range.end(); ++t) {
      const auto& tet = solid.tets[t];
      const auto& p = geometry.points;
      if (CGAL::orientation(p[tet[0]], p[tet[1]], p[tet[2]], p[tet[3]]) == CGAL::COPLANAR) {
        flat = std::min<std::size_t>(flat, t);
        continue;
      }
      // Two tets on the same side of their shared face overlap (one is inverted).
      for (int i = 0; i < 4; ++i) {
        const Index n = neighbors[t][i];
        if (n == kInvalidIndex || n < t) continue;
        const auto f = face_opposite(tet, i);
        Index apex = kInvalidIndex;
        for (const Index w : solid.tets[n])
          if (w != f[0] && w != f[1] && w != f[2]) apex = w;
        if (apex != kInvalidIndex &&
            geometry.side(static_cast<Index>(t), i, p[apex]) == geometry.side(static_cast<Index>(t), i, p[tet[i]]))
          overlap = std::min<std::size_t>(overlap, t);
      }
    }
  });
  if (flat != std::numeric_limits<std::size_t>::max())
    throw InputError("star decomposition: tet " + std::to_string(flat.load()) + " has zero volume (flat)");
  if (overlap != std::numeric_limits<std::size_t>::max())
    throw InputError("star decomposition: tet " + std::to_string(overlap.load()) +
                     " overlaps a face neighbour (both lie on the same side of their shared face: an inverted tet)");
}

// Region growing by the exact rule, all parts from one queue keyed by power distance.
class Grower {
 public:
  Grower(const Geometry& geometry, const std::vector<std::array<Index, 4>>& neighbors, std::vector<Index>& tet_part,
         Progress* progress)
      : geometry_(geometry), neighbors_(neighbors), tet_part_(tet_part), progress_(progress) {
    const TetMesh& mesh = geometry.mesh;
    centers_.resize(mesh.tets.size());
    radius2_.resize(mesh.tets.size());
    tbb::parallel_for(std::size_t{0}, mesh.tets.size(), [&](std::size_t t) {
      // Circumcentre in double, relative to vertex 0: only an ordering key, so
      // rounding costs nothing but a slightly different order; flat tets fall back to
      // the centroid.
      const auto& tet = mesh.tets[t];
      const Vec3& a = mesh.points[tet[0]];
      const Vec3 b = mesh.points[tet[1]] - a, c = mesh.points[tet[2]] - a, d = mesh.points[tet[3]] - a;
      const double det = 2.0 * b.dot(c.cross(d));
      Vec3 offset = (b.squaredNorm() * c.cross(d) + c.squaredNorm() * d.cross(b) + d.squaredNorm() * b.cross(c)) / det;
      if (!offset.allFinite() || offset.squaredNorm() > 1e6 * (b.squaredNorm() + c.squaredNorm() + d.squaredNorm())) {
        centers_[t] = geometry.centroid(static_cast<Index>(t));
        radius2_[t] = 0;
      } else {
        centers_[t] = a + offset;
        radius2_[t] = offset.squaredNorm();
      }
    });
  }

  // Starts part `part` at tet `seed` (which must hold the guard strictly inside).
  void seed(Index part, Index seed_tet, const Vec3& guard) {
    if (guards_.size() <= part) {
      guards_.resize(part + 1);
      guard_points_.resize(part + 1);
    }
    guards_[part] = guard;
    guard_points_[part] = to_point(guard);
    take(seed_tet, part);
  }

  void grow() {
    while (!queue_.empty()) {
      const Entry entry = queue_.top();
      queue_.pop();
      // Admissible when queued, but the relocator may have moved its points since (a
      // part seeded in a leftover round queues its neighbours at once and grows only
      // after the round's later components were repaired: rocker arm, 1 run in 30).
      if (tet_part_[entry.tet] == kInvalidIndex && admissible(entry.tet, entry.part)) take(entry.tet, entry.part);
    }
  }

 private:
  struct Entry {
    double key;
    Index tet, part;
    bool operator<(const Entry& other) const { return key > other.key; }  // min-heap
  };

  bool admissible(Index t, Index part) const {
    for (int i = 0; i < 4; ++i) {
      const Index n = neighbors_[t][i];
      if (n != kInvalidIndex && tet_part_[n] == part) continue;
      if (!geometry_.inner_side(t, i, guard_points_[part])) return false;
    }
    return true;
  }

  void take(Index t, Index part) {
    tet_part_[t] = part;
    if (progress_) progress_->advance();
    for (const Index n : neighbors_[t])
      if (n != kInvalidIndex && tet_part_[n] == kInvalidIndex && admissible(n, part))
        queue_.push({(guards_[part] - centers_[n]).squaredNorm() - radius2_[n], n, part});
  }

  const Geometry& geometry_;
  const std::vector<std::array<Index, 4>>& neighbors_;
  std::vector<Index>& tet_part_;
  Progress* progress_;
  std::vector<Vec3> centers_;
  std::vector<double> radius2_;
  std::vector<Vec3> guards_;
  std::vector<Point> guard_points_;
  std::priority_queue<Entry> queue_;
};

// Connected components of the tets with no part (face adjacency): component id per
// such tet, kInvalidIndex elsewhere.
std::vector<Index> leftover_components(const std::vector<std::array<Index, 4>>& neighbors,
                                       const std::vector<Index>& tet_part, std::vector<std::vector<Index>>* members) {
  std::vector<Index> component(tet_part.size(), kInvalidIndex);
  members->clear();
  std::vector<Index> stack;
  for (Index start = 0; start < tet_part.size(); ++start) {
    if (tet_part[start] != kInvalidIndex || component[start] != kInvalidIndex) continue;
    const auto id = static_cast<Index>(members->size());
    members->emplace_back();
    component[start] = id;
    stack.push_back(start);
    while (!stack.empty()) {
      const Index t = stack.back();
      stack.pop_back();
      members->back().push_back(t);
      for (const Index n : neighbors[t])
        if (n != kInvalidIndex && tet_part[n] == kInvalidIndex && component[n] == kInvalidIndex) {
          component[n] = id;
          stack.push_back(n);
        }
    }
  }
  return component;
}

// The tet of a component farthest (in face steps) from anything outside it: a
// breadth-first search from the component's tets that touch the boundary or a part.
Index deepest_tet(const std::vector<Index>& members, const std::vector<Index>& component, Index id,
                  const std::vector<std::array<Index, 4>>& neighbors, std::vector<std::uint8_t>& visited) {
  std::vector<Index> frontier, next;
  for (const Index t : members)
    for (const Index n : neighbors[t])
      if (n == kInvalidIndex || component[n] != id) {
        frontier.push_back(t);
        visited[t] = 1;
        break;
      }
  if (frontier.empty()) frontier.push_back(members.front()), visited[members.front()] = 1;
  Index last = frontier.front();
  while (!frontier.empty()) {
    last = frontier.front();
    next.clear();
    for (const Index t : frontier)
      for (const Index n : neighbors[t])
        if (n != kInvalidIndex && component[n] == id && !visited[n]) {
          visited[n] = 1;
          next.push_back(n);
        }
    frontier.swap(next);
  }
  for (const Index t : members) visited[t] = 0;
  return last;
}

// A point strictly inside tet t: the centroid, or (for a sliver where rounding puts the
// centroid on a face) a vertex-weighted point.
Vec3 interior_point(const Geometry& geometry, Index t) {
  const Vec3 centroid = geometry.centroid(t);
  if (geometry.containment(t, to_point(centroid)) == 4) return centroid;
  const auto& tet = geometry.mesh.tets[t];
  for (int i = 0; i < 4; ++i) {
    const Vec3 p = 0.4 * geometry.mesh.points[tet[i]] + 0.6 * centroid;
    if (geometry.containment(t, to_point(p)) == 4) return p;
  }
  return centroid;
}

// Vertices of a part visible from its guard within the part (§2.3's report). A ray
// from the guard can only re-enter the part through a boundary face whose plane does
// not have the guard strictly inside (a violating face), so only those can hide a
// vertex: v is hidden when [g, v] meets a violating face anywhere but at v alone.
std::size_t count_visible(const Geometry& geometry, const std::vector<Index>& part_vertices, const Vec3& guard,
                          const std::vector<std::array<Index, 3>>& violating) {
  if (violating.empty()) return part_vertices.size();
  using Triangle = Kernel::Triangle_3;
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  const auto& p = geometry.points;
  std::vector<Triangle> triangles;
  triangles.reserve(violating.size());
  for (const auto& f : violating) triangles.emplace_back(p[f[0]], p[f[1]], p[f[2]]);
  Tree tree(triangles.cbegin(), triangles.cend());
  tree.accelerate_distance_queries();
  const Point g = to_point(guard);
  std::atomic<std::size_t> visible{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, part_vertices.size()), [&](const auto& range) {
    std::vector<Primitive::Id> hits;
    std::size_t count = 0;
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const Index v = part_vertices[k];
      if (p[v] == g) {
        ++count;
        continue;
      }
      hits.clear();
      tree.all_intersected_primitives(Kernel::Segment_3(g, p[v]), std::back_inserter(hits));
      bool hidden = false;
      for (const auto& hit : hits) {
        const auto& f = violating[static_cast<std::size_t>(hit - triangles.cbegin())];
        const bool at_v = f[0] == v || f[1] == v || f[2] == v;
        // A face of v meets the segment at v only, unless the segment lies in its plane.
        if (!at_v || CGAL::orientation(p[f[0]], p[f[1]], p[f[2]], g) == CGAL::COPLANAR) {
          hidden = true;
          break;
        }
      }
      if (!hidden) ++count;
    }
    visible += count;
  });
  return visible;
}

// Part statistics: tets, volume, distinct vertices, kernel violations, visibility.
void measure_parts(const Geometry& geometry, const std::vector<std::array<Index, 4>>& neighbors, StarResult& result) {
  const TetMesh& mesh = geometry.mesh;
  const std::size_t part_count = result.parts.size();
  // (part, vertex) pairs, sorted and deduplicated: each part's distinct vertices.
  std::vector<std::uint64_t> keys(4 * mesh.tets.size());
  tbb::parallel_for(std::size_t{0}, mesh.tets.size(), [&](std::size_t t) {
    for (int i = 0; i < 4; ++i)
      keys[4 * t + i] = (std::uint64_t{result.tet_part[t]} << 32) | std::uint64_t{mesh.tets[t][i]};
  });
  tbb::parallel_sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<std::vector<std::array<Index, 3>>> violating(part_count);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const Index part = result.tet_part[t];
    StarPart& info = result.parts[part];
    ++info.tets;
    info.volume += geometry.volume(static_cast<Index>(t));
  }
  // Violating faces, found in parallel, gathered per part.
  std::vector<std::uint8_t> tet_violations(mesh.tets.size(), 0);
  tbb::parallel_for(std::size_t{0}, mesh.tets.size(), [&](std::size_t t) {
    const Index part = result.tet_part[t];
    const Point g = to_point(result.parts[part].guard);
    std::uint8_t mask = 0;
    for (int i = 0; i < 4; ++i) {
      const Index n = neighbors[t][i];
      if (n != kInvalidIndex && result.tet_part[n] == part) continue;
      if (!geometry.inner_side(static_cast<Index>(t), i, g)) mask |= std::uint8_t(1u << i);
    }
    tet_violations[t] = mask;
  });
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int i = 0; i < 4; ++i)
      if (tet_violations[t] & (1u << i)) violating[result.tet_part[t]].push_back(face_opposite(mesh.tets[t], i));
  std::size_t begin = 0, total_vertices = 0, total_visible = 0;
  std::vector<Index> part_vertices;
  for (std::size_t part = 0; part < part_count; ++part) {
    part_vertices.clear();
    while (begin < keys.size() && (keys[begin] >> 32) == part)
      part_vertices.push_back(static_cast<Index>(keys[begin++] & 0xffffffffu));
    StarPart& info = result.parts[part];
    info.vertices = part_vertices.size();
    info.kernel_violations = violating[part].size();
    info.star_shaped = violating[part].empty();
    info.visible_vertices = count_visible(geometry, part_vertices, info.guard, violating[part]);
    total_vertices += info.vertices;
    total_visible += info.visible_vertices;
  }
  result.visible_fraction = total_vertices ? double(total_visible) / double(total_vertices) : 1.0;
}

// Area of the faces between different parts.
double interface_area(const TetMesh& mesh, const std::vector<std::array<Index, 4>>& neighbors,
                      const std::vector<Index>& tet_part) {
  double area = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int i = 0; i < 4; ++i) {
      const Index n = neighbors[t][i];
      if (n == kInvalidIndex || n < t || tet_part[n] == tet_part[t]) continue;
      const auto f = face_opposite(mesh.tets[t], i);
      area += 0.5 * (mesh.points[f[1]] - mesh.points[f[0]]).cross(mesh.points[f[2]] - mesh.points[f[0]]).norm();
    }
  return area;
}

// Moves interior vertices to repair violations of the growth rule (beyond the
// dissertation, which relaxes the rule and then smooths). Around a vertex at position
// q every constraint is affine in q: an incident tet keeps its orientation
// (det(x - q, y - q, z - q) keeps its sign), and a part-boundary face (q, a, b) of a
// tet with fourth vertex w keeps the part's guard g on the tet's side (det(a - q, b - q,
// g - q) has the sign of det(a - q, b - q, w - q), which the first kind fixes). So the
// admissible positions form a convex polyhedron; alternating projections onto the
// violated half-spaces find a point in it when there is one near. The move is then
// checked with exact predicates and kept only if no tet changes orientation and the
// violated faces around the vertex become a strict subset of what they were.
class Relocator {
 public:
  Relocator(TetMesh& mesh, Geometry& geometry, const std::vector<std::array<Index, 4>>& neighbors,
            const std::vector<Index>& tet_part)
      : mesh_(mesh),
        geometry_(geometry),
        neighbors_(neighbors),
        tet_part_(tet_part),
        vertex_tets_(build_vertex_elements(std::span<const std::array<Index, 4>>(mesh.tets), mesh.points.size())),
        fixed_(mesh.points.size(), 0) {
    for (std::size_t t = 0; t < mesh.tets.size(); ++t)
      for (int i = 0; i < 4; ++i)
        if (neighbors[t][i] == kInvalidIndex)
          for (const Index v : face_opposite(mesh.tets[t], i)) fixed_[v] = 1;  // the solid's boundary stays
  }

  void set_guards(const std::vector<StarPart>& parts) {
    guards_.clear();
    guard_points_.clear();
    for (const StarPart& part : parts) {
      guards_.push_back(part.guard);
      guard_points_.push_back(to_point(part.guard));
    }
  }

  // Violated part-boundary faces (tet * 4 + face) among the faces through v, ascending.
  void violations_around(Index v, std::vector<std::uint64_t>& out) const {
    out.clear();
    for (const Index t : vertex_tets_.row(v)) {
      const Index part = tet_part_[t];
      if (part == kInvalidIndex) continue;
      for (int i = 0; i < 4; ++i) {
        if (mesh_.tets[t][i] == v) continue;  // the face opposite v does not move with it
        const Index n = neighbors_[t][i];
        if (n != kInvalidIndex && tet_part_[n] == part) continue;
        if (!geometry_.inner_side(t, i, guard_points_[part])) out.push_back(4 * std::uint64_t{t} + std::uint64_t(i));
      }
    }
  }

  bool fixed(Index v) const { return fixed_[v] != 0; }
  // Orientation of each tet around v, in vertex_tets order.
  void signs_around(Index v, std::vector<CGAL::Orientation>& out) const {
    out.clear();
    for (const Index t : vertex_tets_.row(v)) out.push_back(tet_sign(t));
  }
  // Puts v at q (mesh and exact-predicate points), without logging.
  void place(Index v, const Vec3& q) {
    mesh_.points[v] = q;
    geometry_.points[v] = to_point(q);
  }

  // Tries to move v; true when it moved. Moves are logged for undo().
  bool relocate(Index v) {
    if (fixed_[v]) return false;
    violations_around(v, before_);
    if (before_.empty()) return false;
    const Vec3 start = mesh_.points[v];
    signs_around(v, signs_before_);
    // The half-spaces u . (q - o) > 0 around v.
    normals_.clear();
    origins_.clear();
    double shortest = std::numeric_limits<double>::infinity();
    for (const Index t : vertex_tets_.row(v)) {
      const auto& tet = mesh_.tets[t];
      int k = 0;
      while (tet[k] != v) ++k;
      for (int i = 0; i < 4; ++i)
        if (i != k) shortest = std::min(shortest, (mesh_.points[tet[i]] - start).norm());
      // Orientation: det(x - q, y - q, z - q) = -N . (q - x), N = (y - x) x (z - x).
      const auto f = face_opposite(tet, k);
      const Vec3 &x = mesh_.points[f[0]], &y = mesh_.points[f[1]], &z = mesh_.points[f[2]];
      const Vec3 n = (y - x).cross(z - x);
      const double side = -n.dot(start - x);
      normals_.push_back(side > 0 ? Vec3(-n) : n);
      origins_.push_back(x);
      const Index part = tet_part_[t];
      if (part == kInvalidIndex) continue;
      for (int i = 0; i < 4; ++i) {
        if (i == k) continue;
        const Index nb = neighbors_[t][i];
        if (nb != kInvalidIndex && tet_part_[nb] == part) continue;
        // The face (v, a, b) opposite vertex w = tet[i].
        Vec3 a = Vec3::Zero(), b = Vec3::Zero();
        int m = 0;
        for (int j = 0; j < 4; ++j)
          if (j != i && j != k) (m++ == 0 ? a : b) = mesh_.points[tet[j]];
        const Vec3& w = mesh_.points[tet[i]];
        const double w_side = -((b - a).cross(w - a)).dot(start - a);
        const Vec3 n_g = (b - a).cross(guards_[part] - a);
        // Wanted: sign(-n_g . (q - a)) == sign(w_side).
        normals_.push_back(w_side > 0 ? Vec3(-n_g) : n_g);
        origins_.push_back(a);
      }
    }
    if (!std::isfinite(shortest) || shortest <= 0) return false;
    Vec3 q = start;
    const double margin = 1e-3 * shortest;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double worst = 0;
      std::size_t worst_index = normals_.size();
      for (std::size_t c = 0; c < normals_.size(); ++c) {
        const double length = normals_[c].norm();
        if (length == 0) continue;
        const double slack = normals_[c].dot(q - origins_[c]) / length - margin;
        if (slack < worst) worst = slack, worst_index = c;
      }
      if (worst_index == normals_.size()) break;
      q -= worst * normals_[worst_index] / normals_[worst_index].norm();
      if ((q - start).norm() > 2 * shortest) return false;  // too far: leave v alone
    }
    place(v, q);
    signs_around(v, signs_after_);
    bool keep = signs_after_ == signs_before_;
    if (keep) {
      violations_around(v, after_);
      keep =
          after_.size() < before_.size() && std::includes(before_.begin(), before_.end(), after_.begin(), after_.end());
    }
    if (!keep) {
      place(v, start);
      return false;
    }
    log_.emplace_back(v, start);
    return true;
  }

  // Repairs the violated faces of the given tets: passes over their vertices until a
  // pass moves none. Returns the number of moves.
  std::size_t repair(std::span<const Index> tets, int passes = 4) {
    std::size_t moves = 0;
    std::vector<Index> vertices;
    for (int pass = 0; pass < passes; ++pass) {
      vertices.clear();
      for (const Index t : tets) {
        const Index part = tet_part_[t];
        if (part == kInvalidIndex) continue;
        for (int i = 0; i < 4; ++i) {
          const Index n = neighbors_[t][i];
          if (n != kInvalidIndex && tet_part_[n] == part) continue;
          if (geometry_.inner_side(t, i, guard_points_[part])) continue;
          for (const Index v : face_opposite(mesh_.tets[t], i))
            if (!fixed_[v]) vertices.push_back(v);
        }
      }
      std::sort(vertices.begin(), vertices.end());
      vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
      std::size_t moved = 0;
      for (const Index v : vertices) moved += relocate(v);
      moves += moved;
      if (moved == 0) break;
    }
    return moves;
  }

  // Violated boundary faces of the given tets' parts, among those tets' faces.
  std::size_t violations(std::span<const Index> tets) const {
    std::size_t count = 0;
    for (const Index t : tets)
      for (int i = 0; i < 4; ++i) {
        const Index part = tet_part_[t];
        const Index n = neighbors_[t][i];
        if (part == kInvalidIndex || (n != kInvalidIndex && tet_part_[n] == part)) continue;
        if (!geometry_.inner_side(t, i, guard_points_[part])) ++count;
      }
    return count;
  }

  std::size_t log_size() const { return log_.size(); }
  // Moves back every vertex moved since the log had `size` entries.
  void undo(std::size_t size) {
    while (log_.size() > size) {
      place(log_.back().first, log_.back().second);
      log_.pop_back();
    }
  }
  std::size_t moved_vertices() const {
    std::vector<Index> vertices;
    for (const auto& entry : log_) vertices.push_back(entry.first);
    std::sort(vertices.begin(), vertices.end());
    return static_cast<std::size_t>(std::unique(vertices.begin(), vertices.end()) - vertices.begin());
  }

 private:
  CGAL::Orientation tet_sign(Index t) const {
    const auto& tet = mesh_.tets[t];
    const auto& p = geometry_.points;
    return CGAL::orientation(p[tet[0]], p[tet[1]], p[tet[2]], p[tet[3]]);
  }

  TetMesh& mesh_;
  Geometry& geometry_;
  const std::vector<std::array<Index, 4>>& neighbors_;
  const std::vector<Index>& tet_part_;
  CompressedRows vertex_tets_;
  std::vector<std::uint8_t> fixed_;
  std::vector<Vec3> guards_;
  std::vector<Point> guard_points_;
  std::vector<std::uint64_t> before_, after_;
  std::vector<CGAL::Orientation> signs_before_, signs_after_;
  std::vector<Vec3> normals_, origins_;
  std::vector<std::pair<Index, Vec3>> log_;
};

// Laplacian smoothing of the inner borders (§2.3; the rule is in star.hpp), on the
// mesh and geometry of `relocator`, whose per-vertex checks it shares. Gauss-Seidel
// sweeps, serial: a move is judged against the current positions of its neighbours and
// kept when no tet around the vertex changes orientation and the rule fails on no more
// faces around it than before. Returns the number of vertices moved at least once.
std::size_t smooth_inner_borders(Relocator& relocator, const TetMesh& mesh,
                                 const std::vector<std::array<Index, 4>>& neighbors, const std::vector<Index>& tet_part,
                                 int iterations) {
  const std::size_t point_count = mesh.points.size();
  std::vector<std::uint8_t> on_interface(point_count, 0);
  std::vector<std::array<Index, 2>> edges;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int i = 0; i < 4; ++i) {
      const Index n = neighbors[t][i];
      if (n == kInvalidIndex || n < t || tet_part[n] == tet_part[t]) continue;
      const auto f = face_opposite(mesh.tets[t], i);
      for (int k = 0; k < 3; ++k) {
        on_interface[f[k]] = 1;
        const Index a = f[k], b = f[(k + 1) % 3];
        edges.push_back({a, b});
        edges.push_back({b, a});
      }
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<std::uint8_t> moved(point_count, 0);
  std::vector<CGAL::Orientation> signs_before, signs_after;
  std::vector<std::uint64_t> failures_before, failures_after;
  for (int sweep = 0; sweep < iterations; ++sweep) {
    std::size_t moves = 0;
    auto edge_begin = edges.begin();
    while (edge_begin != edges.end()) {
      const Index v = (*edge_begin)[0];
      auto edge_end = edge_begin;
      Vec3 mean = Vec3::Zero();
      while (edge_end != edges.end() && (*edge_end)[0] == v) mean += mesh.points[(*edge_end++)[1]];
      const auto degree = static_cast<double>(edge_end - edge_begin);
      edge_begin = edge_end;
      if (relocator.fixed(v) || !on_interface[v]) continue;
      mean /= degree;
      const Vec3 original = mesh.points[v];
      relocator.signs_around(v, signs_before);
      relocator.violations_around(v, failures_before);
      // Halfway to the mean, then shorter steps until the move is allowed.
      for (double step = 0.5; step > 0.05; step *= 0.5) {
        relocator.place(v, original + step * (mean - original));
        relocator.signs_around(v, signs_after);
        if (signs_after == signs_before) {
          relocator.violations_around(v, failures_after);
          if (failures_after.size() <= failures_before.size()) {
            ++moves;
            moved[v] = 1;
            break;
          }
        }
        relocator.place(v, original);
      }
    }
    if (moves == 0) break;
  }
  return static_cast<std::size_t>(std::count(moved.begin(), moved.end(), 1));
}

}  // namespace

std::vector<std::array<Index, 4>> tet_neighbors(const TetMesh& solid) {
  // (sorted face, tet * 4 + local index) records, sorted so the two tets of a face meet.
  struct Record {
    std::array<Index, 3> face;
    std::uint64_t slot;
    bool operator<(const Record& other) const { return face < other.face; }
  };
  std::vector<Record> records(4 * solid.tets.size());
  tbb::parallel_for(std::size_t{0}, solid.tets.size(), [&](std::size_t t) {
    for (int i = 0; i < 4; ++i) {
      std::array<Index, 3> face = face_opposite(solid.tets[t], i);
      std::sort(face.begin(), face.end());
      records[4 * t + i] = {face, 4 * std::uint64_t{t} + std::uint64_t(i)};
    }
  });
  tbb::parallel_sort(records.begin(), records.end());
  std::vector<std::array<Index, 4>> neighbors(solid.tets.size(),
                                              {kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex});
  for (std::size_t k = 0; k < records.size();) {
    std::size_t end = k + 1;
    while (end < records.size() && records[end].face == records[k].face) ++end;
    if (end - k > 2)
      throw InputError("tet mesh: face (" + std::to_string(records[k].face[0]) + ", " +
                       std::to_string(records[k].face[1]) + ", " + std::to_string(records[k].face[2]) +
                       ") belongs to " + std::to_string(end - k) + " tets (non-manifold)");
    if (end - k == 2) {
      const std::uint64_t a = records[k].slot, b = records[k + 1].slot;
      neighbors[a / 4][a % 4] = static_cast<Index>(b / 4);
      neighbors[b / 4][b % 4] = static_cast<Index>(a / 4);
    }
    k = end;
  }
  return neighbors;
}

std::size_t kernel_violations(const TetMesh& solid, std::span<const Index> tet_part, Index part, const Vec3& guard) {
  if (tet_part.size() != solid.tets.size()) throw Error("kernel_violations: one part id per tet expected");
  const Geometry geometry(solid);
  const auto neighbors = tet_neighbors(solid);
  const Point g = to_point(guard);
  std::size_t count = 0;
  for (std::size_t t = 0; t < solid.tets.size(); ++t) {
    if (tet_part[t] != part) continue;
    for (int i = 0; i < 4; ++i) {
      const Index n = neighbors[t][i];
      if (n != kInvalidIndex && tet_part[n] == part) continue;
      if (!geometry.inner_side(static_cast<Index>(t), i, g)) ++count;
    }
  }
  return count;
}

StarResult star_decomposition(const TetMesh& solid, std::span<const Vec3> guards, const StarOptions& options) {
  StarResult result;
  auto stage_start = Clock::now();
  // The relocation of leftover repairs and the smoothing move interior points: they
  // work on a copy.
  TetMesh work = solid;
  Geometry geometry(work);
  if (solid.tets.empty()) throw InputError("star decomposition: the mesh has no tetrahedra");
  const auto neighbors = tet_neighbors(solid);
  check_input(solid, geometry, neighbors);
  result.stage_seconds.emplace_back("adjacency", seconds_since(stage_start));
  const std::size_t tet_count = solid.tets.size();
  result.tet_part.assign(tet_count, kInvalidIndex);
  result.input_guards = guards.size();

  // Locate each guard: the tet holding it strictly inside, else one it touches (the
  // guard then moves a little into that tet), else it is outside the solid.
  stage_start = Clock::now();
  std::vector<std::array<Vec3, 2>> boxes(tet_count);
  tbb::parallel_for(std::size_t{0}, tet_count, [&](std::size_t t) {
    Vec3 lo = solid.points[solid.tets[t][0]], hi = lo;
    for (int i = 1; i < 4; ++i) {
      lo = lo.cwiseMin(solid.points[solid.tets[t][i]]);
      hi = hi.cwiseMax(solid.points[solid.tets[t][i]]);
    }
    boxes[t] = {lo, hi};
  });
  std::vector<Index> seed_tets;
  std::vector<Vec3> seed_guards;
  for (const Vec3& guard : guards) {
    const Point g = to_point(guard);
    std::atomic<Index> inside{kInvalidIndex}, touching{kInvalidIndex};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tet_count), [&](const auto& range) {
      for (std::size_t t = range.begin(); t != range.end(); ++t) {
        const auto& [lo, hi] = boxes[t];
        if ((guard.array() < lo.array()).any() || (guard.array() > hi.array()).any()) continue;
        const int c = geometry.containment(static_cast<Index>(t), g);
        if (c == 4)
          inside = static_cast<Index>(t);
        else if (c >= 0)
          touching = static_cast<Index>(t);
      }
    });
    Index seed = inside;
    Vec3 position = guard;
    if (seed == kInvalidIndex && touching != kInvalidIndex) {
      seed = touching;
      position = interior_point(geometry, seed);
      const Vec3 nudged = guard + 1e-3 * (position - guard);
      if (geometry.containment(seed, to_point(nudged)) == 4) position = nudged;
      ++result.moved_guards;
    }
    if (seed == kInvalidIndex || std::find(seed_tets.begin(), seed_tets.end(), seed) != seed_tets.end()) {
      ++result.dropped_guards;
      continue;
    }
    seed_tets.push_back(seed);
    seed_guards.push_back(position);
  }
  result.stage_seconds.emplace_back("locate guards", seconds_since(stage_start));

  stage_start = Clock::now();
  std::unique_ptr<Progress> progress;
  if (options.progress) progress = std::make_unique<Progress>("star: growing parts", tet_count);
  Grower grower(geometry, neighbors, result.tet_part, progress.get());
  Relocator relocator(work, geometry, neighbors, result.tet_part);
  // All parts grow at once from one queue, a tet going to the first part that may
  // take it. Growing them one after another (each as far as it can, in guard order)
  // left half as many tets to re-guard on rocker-arm (38k against 76k of 307k) but
  // split the U of the tests into 25 parts instead of 2: the first part takes all it
  // sees, up to a jagged shadow boundary the next guard cannot grow against.
  for (std::size_t k = 0; k < seed_tets.size(); ++k) {
    result.parts.push_back({seed_guards[k], false, 0, 0, 0, 0, 0, false});
    grower.seed(static_cast<Index>(k), seed_tets[k], seed_guards[k]);
  }
  grower.grow();
  result.growth_rounds = 1;

  // Leftovers: merge small components (not strict), re-guard the rest, grow again.
  std::vector<std::vector<Index>> members;
  std::vector<std::uint8_t> visited(tet_count, 0);
  std::vector<std::uint32_t> shared(result.parts.size());
  std::vector<Index> order;
  std::vector<Point> guard_points;
  for (const StarPart& part : result.parts) guard_points.push_back(to_point(part.guard));
  while (true) {
    const std::vector<Index> component = leftover_components(neighbors, result.tet_part, &members);
    if (members.empty()) break;
    bool seeded = false;
    relocator.set_guards(result.parts);
    for (std::size_t id = 0; id < members.size(); ++id) {
      const auto& tets = members[id];
      // The parts around the component, most shared faces first.
      shared.assign(result.parts.size(), 0);
      for (const Index t : tets)
        for (const Index n : neighbors[t])
          if (n != kInvalidIndex && component[n] != id && result.tet_part[n] != kInvalidIndex)
            ++shared[result.tet_part[n]];
      order.clear();
      for (Index part = 0; part < shared.size(); ++part)
        if (shared[part] > 0) order.push_back(part);
      std::sort(order.begin(), order.end(), [&](Index a, Index b) { return shared[a] > shared[b]; });
      // Whole, by the exact rule: tets that block one another one at a time (each needs
      // the other in the part first) may pass together.
      const auto whole = std::find_if(order.begin(), order.end(), [&](Index part) {
        const Point& g = guard_points[part];
        for (const Index t : tets)
          for (int i = 0; i < 4; ++i) {
            const Index n = neighbors[t][i];
            if (n != kInvalidIndex && (component[n] == id || result.tet_part[n] == part)) continue;
            if (!geometry.inner_side(t, i, g)) return false;
          }
        return true;
      });
      if (whole != order.end()) {
        for (const Index t : tets) result.tet_part[t] = *whole;
        result.absorbed_tets += tets.size();
        if (progress) progress->advance(tets.size());
        continue;
      }
      // A small component joins a neighbouring part and vertices around it move until
      // the rule holds again (Relocator). --strict keeps the join only if that
      // succeeds, trying the two parts sharing most faces; otherwise the component is
      // merged regardless where the moves left the fewest faces breaking the rule, if
      // they are few (merge_max_violations), else re-guarded.
      const bool try_repair = tets.size() <= options.repair_max_tets;
      const bool may_merge = !options.strict && tets.size() <= options.merge_max_tets;
      if ((try_repair || may_merge) && !order.empty()) {
        bool joined = false, merge_tried = false;
        std::size_t best = 0, fewest = std::numeric_limits<std::size_t>::max();  // over the tries
        const std::size_t tries = try_repair ? std::min<std::size_t>(order.size(), 2) : 0;
        for (std::size_t k = 0; k < tries; ++k) {
          for (const Index t : tets) result.tet_part[t] = order[k];
          const std::size_t mark = relocator.log_size();
          relocator.repair(tets);
          const std::size_t left = relocator.violations(tets);
          if (left == 0) {
            joined = true;
            result.repaired_tets += tets.size();
            break;
          }
          if (left < fewest) fewest = left, best = k;
          // The last try being the best, the merge below would repeat this very repair
          // from the same state: its outcome is decided here.
          if (k + 1 == tries && best == k && may_merge) {
            merge_tried = true;
            if (left <= options.merge_max_violations) {
              joined = true;
              result.merged_tets += tets.size();
              break;
            }
          }
          relocator.undo(mark);
          for (const Index t : tets) result.tet_part[t] = kInvalidIndex;
        }
        if (!joined && may_merge && !merge_tried) {
          // Merged regardless, where the repair left the fewest violations, if they are few.
          for (const Index t : tets) result.tet_part[t] = order[best];
          const std::size_t mark = relocator.log_size();
          relocator.repair(tets);
          if (relocator.violations(tets) <= options.merge_max_violations) {
            joined = true;
            result.merged_tets += tets.size();
          } else {
            relocator.undo(mark);
            for (const Index t : tets) result.tet_part[t] = kInvalidIndex;
          }
        }
        if (joined) {
          if (progress) progress->advance(tets.size());
          continue;
        }
      }
      const Index seed = deepest_tet(tets, component, static_cast<Index>(id), neighbors, visited);
      const Vec3 guard = interior_point(geometry, seed);
      const auto part = static_cast<Index>(result.parts.size());
      result.parts.push_back({guard, true, 0, 0, 0, 0, 0, false});
      guard_points.push_back(to_point(guard));
      grower.seed(part, seed, guard);
      // The seed tet is in the new part now, and a later component of this round may
      // share a vertex with it: the relocator must know the new part's guard. (It read
      // past the end of its guard list here, about a hundred times per kitten run, until
      // 2026-12-05; one bench run then had a --strict part fail the star check.)
      relocator.set_guards(result.parts);
      seeded = true;
    }
    if (!seeded) continue;  // only merges this round; components are recomputed
    grower.grow();
    ++result.growth_rounds;
  }
  if (progress) progress->finish();
  result.stage_seconds.emplace_back("growth", seconds_since(stage_start));

  stage_start = Clock::now();
  result.relocated_vertices = relocator.moved_vertices();
  result.interface_area_before = result.interface_area_after = interface_area(work, neighbors, result.tet_part);
  if (options.smoothing_iterations > 0) {
    relocator.set_guards(result.parts);  // the last round may have added parts
    result.smoothed_vertices =
        smooth_inner_borders(relocator, work, neighbors, result.tet_part, options.smoothing_iterations);
    result.interface_area_after = interface_area(work, neighbors, result.tet_part);
    result.stage_seconds.emplace_back("smoothing", seconds_since(stage_start));
  }
  result.points = work.points;
  stage_start = Clock::now();
  measure_parts(geometry, neighbors, result);
  result.stage_seconds.emplace_back("measure", seconds_since(stage_start));
  return result;
}

}  // namespace structmesh
