// guard_surface(): the guarding stage of §2.2 as one function: skeleton candidates,
// visibility, set cover, the face colouring and the guard graph.
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"
#include "structmesh/io.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/skeleton.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <limits>
#include <string>

namespace structmesh {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Area-weighted vertex normals (outward for an outward-oriented surface).
std::vector<Vec3> vertex_normals(const TriMesh& surface) {
  std::vector<Vec3> normals(surface.points.size(), Vec3::Zero());
  for (const auto& t : surface.triangles) {
    const Vec3 n = (surface.points[t[1]] - surface.points[t[0]]).cross(surface.points[t[2]] - surface.points[t[0]]);
    for (const Index v : t) normals[v] += n;
  }
  for (Vec3& n : normals)
    if (n.norm() > 0) n.normalize();
  return normals;
}

// Returns the number of self-intersecting face pairs (0 unless they are allowed).
std::size_t check_guardable(const TriMesh& surface, bool allow_self_intersections) {
  if (surface.triangles.empty()) throw InputError("guard: the surface has no triangles");
  const SurfaceReport report = check_surface(to_bundle(surface));
  if (report.valid_solid_boundary) return 0;
  const std::size_t crossings = report.self_intersections + report.adjacent_overlaps;
  if (allow_self_intersections && report.closed && report.non_manifold_edges + report.non_manifold_vertices == 0 &&
      report.oriented && report.signed_volume > 0 && report.degenerate_faces == 0)
    return crossings;
  throw InputError("guard: the surface does not bound a solid:" + solid_boundary_problems(report) +
                   " (structmesh guard --repair closes holes, turns an inward surface and guards across "
                   "self-intersections)");
}

// Progressive ILP (§2.2.3): the surface simplified to coarse levels (the coarsest first,
// then `step` more vertices per level, the input last). On each level the faces the
// guards kept so far see are removed, guards that see less than `significance` of the
// level's area are dropped back among the candidates (their faces stay in the
// universe), and the ILP covers what is left; its guards join the kept ones. The
// candidates are the same points on every level (the finest skeleton's), their rows
// recomputed against each level's surface. Returns candidate ids, ascending.
std::vector<Index> progressive_cover(const TriMesh& surface, const std::vector<Vec3>& candidates,
                                     const CompressedRows& finest_rows, const GuardOptions& options,
                                     GuardResult& result) {
  std::vector<std::size_t> targets;
  for (std::size_t n = options.pilp_coarsest_vertices; n > 0 && n < surface.points.size();
       n += options.pilp_level_step) {
    targets.push_back(n);
    if (options.pilp_level_step == 0) break;
  }
  targets.push_back(0);  // the input itself
  std::vector<Index> guards;
  for (const std::size_t target : targets) {
    const auto level_start = Clock::now();
    PilpLevel level;
    TriMesh simplified;
    CompressedRows level_rows;
    const TriMesh* level_surface = &surface;
    const CompressedRows* rows = &finest_rows;
    if (target > 0) {
      try {
        simplified = simplify_surface(surface, target);
        const VisibilityOracle oracle(simplified);
        level_rows = visible_faces(oracle, simplified, candidates);
      } catch (const InputError&) {
        continue;  // the collapse left degenerate faces: skip to the next level
      }
      level_surface = &simplified;
      rows = &level_rows;
    }
    const std::size_t faces = level_surface->triangles.size();
    level.vertices = level_surface->points.size();
    level.faces = faces;
    std::vector<double> area(faces);
    double total_area = 0;
    for (std::size_t f = 0; f < faces; ++f) {
      const auto& t = level_surface->triangles[f];
      const auto& p = level_surface->points;
      area[f] = 0.5 * (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).norm();
      total_area += area[f];
    }
    // Significant guards stay and their faces leave the universe.
    std::vector<std::uint8_t> covered(faces, 0);
    std::vector<Index> kept;
    for (const Index g : guards) {
      double seen = 0;
      for (const Index f : rows->row(g)) seen += area[f];
      if (seen >= options.pilp_significance * total_area) {
        kept.push_back(g);
        for (const Index f : rows->row(g)) covered[f] = 1;
      } else {
        ++level.dropped;
      }
    }
    level.kept = kept.size();
    // The universe: faces some candidate sees that no kept guard sees, renumbered.
    std::vector<Index> element(faces, kInvalidIndex);
    Index universe = 0;
    for (const Index f : rows->items)
      if (!covered[f] && element[f] == kInvalidIndex) element[f] = universe++;
    level.universe = universe;
    std::vector<Index> added;
    if (universe > 0) {
      CompressedRows sub;
      for (std::size_t c = 0; c < rows->row_count(); ++c) {
        for (const Index f : rows->row(c))
          if (element[f] != kInvalidIndex) sub.items.push_back(element[f]);
        sub.offsets.push_back(static_cast<Index>(sub.items.size()));
      }
      const IlpSetCoverResult ilp = ilp_set_cover(sub, universe, options.time_limit);
      level.optimal = ilp.optimal;
      for (const Index c : ilp.chosen)
        if (std::find(kept.begin(), kept.end(), c) == kept.end()) added.push_back(c);
    } else {
      level.optimal = true;
    }
    level.added = added.size();
    guards = kept;
    guards.insert(guards.end(), added.begin(), added.end());
    std::sort(guards.begin(), guards.end());
    level.guards = guards.size();
    level.seconds = seconds_since(level_start);
    result.levels.push_back(level);
  }
  // Guards of coarse levels that the finer ones made redundant: each, least-seeing
  // first, goes if the others still cover every face some candidate sees.
  std::vector<std::uint32_t> coverage(surface.triangles.size(), 0);
  for (const Index g : guards)
    for (const Index f : finest_rows.row(g)) ++coverage[f];
  std::vector<Index> order = guards;
  std::sort(order.begin(), order.end(),
            [&](Index a, Index b) { return finest_rows.row(a).size() < finest_rows.row(b).size(); });
  std::vector<Index> final_guards;
  for (const Index g : order) {
    const auto row = finest_rows.row(g);
    if (std::all_of(row.begin(), row.end(), [&](Index f) { return coverage[f] > 1; })) {
      for (const Index f : row) --coverage[f];
      ++result.pilp_pruned;
    } else {
      final_guards.push_back(g);
    }
  }
  result.pilp_exchanges = improve_set_cover(finest_rows, surface.triangles.size(), final_guards,
                                            options.pilp_exchange_group, options.time_limit);
  std::sort(final_guards.begin(), final_guards.end());
  final_guards.erase(std::unique(final_guards.begin(), final_guards.end()), final_guards.end());
  return final_guards;
}

}  // namespace

GuardResult guard_surface(const TriMesh& surface, const GuardOptions& options) {
  GuardResult result;
  auto start = Clock::now();
  const auto stage = [&](const char* name) {
    result.stage_seconds.emplace_back(name, seconds_since(start));
    start = Clock::now();
  };
  result.self_intersections = check_guardable(surface, options.allow_self_intersections);
  stage("check");

  CurveSkeleton skeleton;
  if (options.candidates.empty()) {
    if (options.progress) status("guard: curve skeleton of " + std::to_string(surface.points.size()) + " vertices");
    skeleton = curve_skeleton(surface, options.skeleton_vertices);
  }
  result.skeleton_nodes = skeleton.nodes.size();
  const double diagonal = surface.bounding_box().diagonal();
  const double spacing = options.spacing > 0 ? options.spacing : 0.01 * diagonal;
  std::vector<Vec3> candidates;
  {
    const std::vector<Vec3> samples =
        options.candidates.empty() ? resample_skeleton(skeleton, spacing) : options.candidates;
    const std::vector<std::uint8_t> inside = inside_solid(surface, samples);
    for (std::size_t i = 0; i < samples.size(); ++i)
      if (inside[i]) candidates.push_back(samples[i]);
  }
  stage("skeleton");

  const VisibilityOracle oracle(surface);
  if (options.progress) status("guard: visibility of " + std::to_string(candidates.size()) + " candidates");
  CompressedRows sets = visible_faces(oracle, surface, candidates);
  const std::size_t faces = surface.triangles.size();
  // Faces no skeleton point sees: for each of their vertices, a candidate halfway to
  // its skeleton node and one a fifth of the shortest incident edge inside along the
  // vertex normal (the dissertation adds the invisible vertices themselves, which see
  // little more than their own faces).
  // One round; what stays unseen is reported and left out of the cover.
  {
    std::vector<std::uint8_t> seen(faces, 0);
    for (const Index f : sets.items) seen[f] = 1;
    std::vector<double> shortest(surface.points.size(), std::numeric_limits<double>::infinity());
    for (const auto& t : surface.triangles)
      for (int k = 0; k < 3; ++k) {
        const double length = (surface.points[t[k]] - surface.points[t[(k + 1) % 3]]).norm();
        shortest[t[k]] = std::min(shortest[t[k]], length);
        shortest[t[(k + 1) % 3]] = std::min(shortest[t[(k + 1) % 3]], length);
      }
    const std::vector<Vec3> normals = vertex_normals(surface);
    std::vector<std::uint8_t> offered(surface.points.size(), 0);
    std::vector<Vec3> extra;
    for (std::size_t f = 0; f < faces; ++f)
      if (!seen[f])
        for (const Index v : surface.triangles[f])
          if (!offered[v]) {
            offered[v] = 1;
            // Halfway to the skeleton node that absorbed v (inside when the flow moved v
            // inward, and seeing far more than a point next to v), and just inside v.
            if (!skeleton.vertex_node.empty())
              extra.push_back(0.5 * (surface.points[v] + skeleton.nodes[skeleton.vertex_node[v]]));
            extra.push_back(surface.points[v] - 0.2 * shortest[v] * normals[v]);
          }
    // At most max_added_candidates, evenly spread: on self-intersecting models (faces
    // inside another limb) tens of thousands of vertices go unseen, and testing each
    // extra candidate against every vertex took minutes (TOSCA michael, 52k vertices).
    if (extra.size() > options.max_added_candidates) {
      std::vector<Vec3> spread;
      const double step = double(extra.size()) / double(options.max_added_candidates);
      for (std::size_t k = 0; k < options.max_added_candidates; ++k) spread.push_back(extra[std::size_t(k * step)]);
      extra.swap(spread);
    }
    if (!extra.empty()) {
      const std::vector<std::uint8_t> inside = inside_solid(surface, extra);
      std::vector<Vec3> kept;
      for (std::size_t i = 0; i < extra.size(); ++i)
        if (inside[i]) kept.push_back(extra[i]);
      const CompressedRows more = visible_faces(oracle, surface, kept);
      for (std::size_t r = 0; r < more.row_count(); ++r) {
        const auto row = more.row(r);
        sets.items.insert(sets.items.end(), row.begin(), row.end());
        sets.offsets.push_back(static_cast<Index>(sets.items.size()));
      }
      candidates.insert(candidates.end(), kept.begin(), kept.end());
      result.added_candidates = kept.size();
    }
  }
  result.candidates = candidates.size();
  result.candidate_points = candidates;
  stage("visibility");

  // The cover is over the faces some candidate sees; the rest are counted.
  std::vector<Index> element(faces, kInvalidIndex);
  Index coverable = 0;
  for (const Index f : sets.items)
    if (element[f] == kInvalidIndex) element[f] = 0;
  for (std::size_t f = 0; f < faces; ++f)
    if (element[f] != kInvalidIndex) element[f] = coverable++;
  result.uncovered_faces = faces - coverable;
  CompressedRows cover_sets;
  for (std::size_t r = 0; r < sets.row_count(); ++r) {
    for (const Index f : sets.row(r)) cover_sets.items.push_back(element[f]);
    cover_sets.offsets.push_back(static_cast<Index>(cover_sets.items.size()));
  }
  const std::vector<Index> greedy = greedy_set_cover(cover_sets, coverable);
  result.greedy_guards = greedy.size();
  std::vector<Index> chosen = greedy;
  if (options.method == GuardMethod::Ilp) {
    if (options.progress) status("guard: exact set cover (ILP, CBC)");
    const IlpSetCoverResult ilp = ilp_set_cover(cover_sets, coverable, options.time_limit);
    chosen = ilp.chosen;
    result.optimal = ilp.optimal;
    result.lower_bound = ilp.lower_bound;
    result.rows_before = ilp.rows_before;
    result.rows_after = ilp.rows_after;
    result.columns_before = ilp.columns_before;
    result.columns_after = ilp.columns_after;
  }
  if (options.method == GuardMethod::Pilp) {
    if (options.progress) status("guard: progressive ILP");
    // The rows over the input's faces (cover_sets numbers only the coverable ones).
    chosen = progressive_cover(surface, candidates, sets, options, result);
  }
  std::sort(chosen.begin(), chosen.end());
  if (!covers_all(cover_sets, coverable, chosen))
    throw Error("guard_surface: the chosen guards miss a face some candidate sees (a bug)");
  stage("cover");

  // Face colouring: each face goes to the nearest chosen guard that sees it.
  result.face_guard.assign(faces, kInvalidIndex);
  std::vector<double> best(faces, std::numeric_limits<double>::infinity());
  for (std::size_t g = 0; g < chosen.size(); ++g) {
    const Vec3& p = candidates[chosen[g]];
    for (const Index f : sets.row(chosen[g])) {
      const auto& t = surface.triangles[f];
      const Vec3 centre = (surface.points[t[0]] + surface.points[t[1]] + surface.points[t[2]]) / 3.0;
      const double distance = (centre - p).squaredNorm();
      if (distance < best[f]) best[f] = distance, result.face_guard[f] = static_cast<Index>(g);
    }
  }
  result.guards.resize(chosen.size());
  for (std::size_t g = 0; g < chosen.size(); ++g) result.guards[g].position = candidates[chosen[g]];
  for (std::size_t f = 0; f < faces; ++f)
    if (result.face_guard[f] != kInvalidIndex)
      result.guards[result.face_guard[f]].faces.push_back(static_cast<Index>(f));
  // Guard graph: guards whose faces meet along a surface edge.
  const EdgeAdjacency edges = build_edges(surface);
  for (std::size_t e = 0; e < edges.edges.size(); ++e) {
    const auto around = edges.edge_elements.row(e);
    for (std::size_t i = 0; i < around.size(); ++i)
      for (std::size_t j = i + 1; j < around.size(); ++j) {
        const Index a = result.face_guard[around[i]], b = result.face_guard[around[j]];
        if (a != b && a != kInvalidIndex && b != kInvalidIndex)
          result.graph.push_back({std::min(a, b), std::max(a, b)});
      }
  }
  std::sort(result.graph.begin(), result.graph.end());
  result.graph.erase(std::unique(result.graph.begin(), result.graph.end()), result.graph.end());
  stage("colouring");
  return result;
}

}  // namespace structmesh
