// guard_surface(): the guarding stage of §2.2 as one function: skeleton candidates,
// visibility, set cover, the face colouring and the guard graph.
#include "guard/kernel_candidates.hpp"
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

// Extra candidates where the skeleton's are few (§2.2.1 adds the vertices no skeleton
// point sees; such a point sees little more than its own faces). Faces seen by fewer
// than 8 candidates get, for their vertices, a point halfway to the skeleton node
// that absorbed the vertex, one three shortest edges inside along the vertex normal and
// one a fifth of the shortest edge inside (which sees at least the vertex's own faces
// where the surface is not folded). The points go in rounds of up to kRoundVertices
// vertices at least `spread` apart, and a round's visibility updates the counts before
// the next round is picked, so most neighbours of an offered vertex need nothing. A face
// still unseen after two of its vertices were offered lies where the surface passes
// through itself (a limb inside another) and is given up.
//
// Measured on TOSCA dog (25k vertices, the same skeleton candidates), ILP guards / extra
// candidates / visibility + cover seconds: before, every vertex of every face no skeleton
// point saw, the points halfway and a fifth inside: 68 / 2,693 / 6.3 s. Rounds with those
// two points and "seen" meaning seen once: 125 guards (each point near the surface ends
// up needed for a few faces). Seen 8 times and the point three edges deep added: 56 / 764
// / 2.1 s; rocker arm 10 -> 6, horse 27 -> 24, gorilla 88 -> 82 guards, TOSCA michael 25
// -> 14 s. Seen 16 times: 52 guards, but CBC ran for 52 s. One edge or six deep instead of
// three: 60 and 59 guards. Without the point a fifth inside: 4 faces unseen.
// Appends to `candidates` and `sets`; returns how many candidates were added.
std::size_t add_candidates_for_unseen_faces(const TriMesh& surface, const CurveSkeleton& skeleton,
                                            const VisibilityOracle& oracle, const GuardOptions& options,
                                            std::vector<Vec3>& candidates, CompressedRows& sets) {
  // Candidates given by the caller are mostly an earlier result's, extras included: only
  // faces none of them sees get more, so the rerun has the same rows.
  const int well_seen = options.candidates.empty() ? 8 : 1;
  if (options.max_added_candidates == 0) return 0;
  constexpr std::size_t kRoundVertices = 32;
  const std::size_t faces = surface.triangles.size(), vertices = surface.points.size();
  std::vector<int> seen_by(faces, 0);
  for (const Index f : sets.items) ++seen_by[f];
  std::vector<double> shortest(vertices, std::numeric_limits<double>::infinity());
  for (const auto& t : surface.triangles)
    for (int k = 0; k < 3; ++k) {
      const double length = (surface.points[t[k]] - surface.points[t[(k + 1) % 3]]).norm();
      shortest[t[k]] = std::min(shortest[t[k]], length);
      shortest[t[(k + 1) % 3]] = std::min(shortest[t[(k + 1) % 3]], length);
    }
  const std::vector<Vec3> normals = vertex_normals(surface);
  const double spread =
      options.added_candidate_spread > 0 ? options.added_candidate_spread : 0.02 * surface.bounding_box().diagonal();
  // The three points of every vertex of an under-seen face, tested inside in one call (the
  // test builds a tree over the surface).
  std::vector<Index> first(vertices + 1, 0);
  std::vector<Vec3> points;
  {
    std::vector<std::uint8_t> open(vertices, 0);
    for (std::size_t f = 0; f < faces; ++f)
      if (seen_by[f] < well_seen)
        for (const Index v : surface.triangles[f]) open[v] = 1;
    for (Index v = 0; v < vertices; ++v) {
      first[v] = static_cast<Index>(points.size());
      if (!open[v]) continue;
      if (!skeleton.vertex_node.empty())
        points.push_back(0.5 * (surface.points[v] + skeleton.nodes[skeleton.vertex_node[v]]));
      points.push_back(surface.points[v] - 3.0 * shortest[v] * normals[v]);
      points.push_back(surface.points[v] - 0.2 * shortest[v] * normals[v]);
    }
    first[vertices] = static_cast<Index>(points.size());
  }
  const std::vector<std::uint8_t> inside = inside_solid(surface, points);
  std::vector<std::uint8_t> offered(vertices, 0), listed(vertices, 0);
  std::size_t added = 0;
  while (added < options.max_added_candidates) {
    std::vector<Index> round;  // vertices of faces still under-seen, in face order, spread out
    std::fill(listed.begin(), listed.end(), std::uint8_t{0});
    for (std::size_t f = 0; f < faces && round.size() < kRoundVertices; ++f) {
      const auto& t = surface.triangles[f];
      // A face its vertices' own points did not see lies where the surface passes through
      // itself (a limb inside another; TOSCA michael: 1,941 such faces).
      if (seen_by[f] >= well_seen || (seen_by[f] == 0 && offered[t[0]] + offered[t[1]] + offered[t[2]] >= 2)) continue;
      for (const Index v : t) {
        if (offered[v] || listed[v] || round.size() == kRoundVertices) continue;
        listed[v] = 1;
        if (std::all_of(round.begin(), round.end(), [&](Index u) {
              return (surface.points[u] - surface.points[v]).squaredNorm() >= spread * spread;
            }))
          round.push_back(v);
      }
    }
    if (round.empty()) break;
    std::vector<Vec3> kept;
    for (const Index v : round) {
      offered[v] = 1;
      for (Index i = first[v]; i < first[v + 1]; ++i)
        if (inside[i] && added + kept.size() < options.max_added_candidates) kept.push_back(points[i]);
    }
    if (kept.empty()) continue;
    const CompressedRows more = visible_faces(oracle, surface, kept);
    for (std::size_t r = 0; r < more.row_count(); ++r) {
      const auto row = more.row(r);
      for (const Index f : row) ++seen_by[f];
      sets.items.insert(sets.items.end(), row.begin(), row.end());
      sets.offsets.push_back(static_cast<Index>(sets.items.size()));
    }
    candidates.insert(candidates.end(), kept.begin(), kept.end());
    added += kept.size();
  }
  return added;
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

// Rounds of kernel candidates (kernel_candidates.hpp) after the cover: points where one
// guard might replace two of the cover's, tested for visibility and added to the
// instance; `improve(cover)` then lowers the cover over the enlarged instance where it
// can. Rounds go on while they lower the count and `budget` seconds last (a round started
// in time finishes). New rows keep only faces of the cover's universe (`element` valid).
// Appends to `candidates`, `sets` and `cover_sets`; counts the candidates in `added`;
// returns the rounds that lowered the count.
//
// Measured on the TOSCA dog (the same skeleton candidates), with the whole ILP as
// `improve`, guards by round: 52, 46, 41, 41 (the ILP 1.4, 6.7 and 1.8 s); the
// screwdriver 5 -> 4, the rocker arm 7 -> 6, the hand 6 -> 5, fertility 12 -> 11, in
// under a second each. The greedy cover over the same candidates gains 0-1 guards on
// those (the points are made for pairs of the cover) but more on the dog (68 -> 54-59).
template <class Improve>
std::size_t refine_with_kernel_candidates(const TriMesh& surface, const VisibilityOracle& oracle,
                                          const std::vector<Index>& element, double budget,
                                          std::vector<Vec3>& candidates, CompressedRows& sets,
                                          CompressedRows& cover_sets, std::vector<Index>& cover, Improve&& improve,
                                          std::size_t& added) {
  constexpr int kMaxRounds = 8;
  const auto start = Clock::now();
  std::size_t improving = 0;
  for (int round = 0; round < kMaxRounds && seconds_since(start) < budget; ++round) {
    const std::vector<Vec3> points = guard_detail::kernel_candidates(surface, sets, candidates, cover);
    const std::vector<std::uint8_t> inside = inside_solid(surface, points);
    std::vector<Vec3> kept;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (inside[i]) kept.push_back(points[i]);
    if (kept.empty()) break;
    const CompressedRows more = visible_faces(oracle, surface, kept);
    for (std::size_t r = 0; r < more.row_count(); ++r) {
      for (const Index f : more.row(r))
        if (element[f] != kInvalidIndex) sets.items.push_back(f), cover_sets.items.push_back(element[f]);
      sets.offsets.push_back(static_cast<Index>(sets.items.size()));
      cover_sets.offsets.push_back(static_cast<Index>(cover_sets.items.size()));
    }
    candidates.insert(candidates.end(), kept.begin(), kept.end());
    added += kept.size();
    const std::size_t before = cover.size();
    improve(cover);
    if (cover.size() >= before) break;
    ++improving;
  }
  return improving;
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
  result.added_candidates = add_candidates_for_unseen_faces(surface, skeleton, oracle, options, candidates, sets);
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
  result.greedy_guards = result.greedy_guards_before_refinement = greedy.size();
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
  result.guards_before_refinement = chosen.size();
  stage("cover");

  // Kernel candidates: after each round the cover's local exchanges (improve_set_cover)
  // run over the enlarged instance, and the ILP solves it again from there in the time
  // left (result.refined_optimal says whether the last one proved its optimum; the ILP's
  // optimum over the candidates before stays proven: result.optimal). Measured on the
  // TOSCA dog with one skeleton, the whole ILP alone each round: 52 -> 46 -> 41 guards;
  // with another, CBC could not prove the first round's optimum in 5 s.
  if (options.refine_seconds > 0 && options.method != GuardMethod::Greedy) {
    if (options.progress) status("guard: kernel candidates for pairs of guards");
    const auto refine_start = Clock::now();
    const auto improve = [&](std::vector<Index>& cover) {
      double remaining = options.refine_seconds - seconds_since(refine_start);
      result.refinement_exchanges += improve_set_cover(
          sets, faces, cover, std::max<std::size_t>(options.pilp_exchange_group, 2), options.time_limit, remaining);
      remaining = options.refine_seconds - seconds_since(refine_start);
      if (options.method == GuardMethod::Ilp && remaining > 0) {
        const IlpSetCoverResult ilp =
            ilp_set_cover(cover_sets, coverable, std::min(options.time_limit, remaining), cover);
        // Its start is `cover` completed per block (the reductions drop dominated sets), so
        // it can come back larger only if CBC found nothing better in time.
        result.refined_optimal = ilp.optimal && ilp.chosen.size() <= cover.size();
        if (ilp.chosen.size() <= cover.size()) cover = ilp.chosen;
        result.refined_lower_bound = ilp.lower_bound;
      } else {
        result.refined_optimal = false;
      }
    };
    result.refinement_rounds =
        refine_with_kernel_candidates(surface, oracle, element, options.refine_seconds, candidates, sets, cover_sets,
                                      chosen, improve, result.kernel_candidates);
    // The greedy cover over the same candidates as the cover, for a fair comparison.
    if (result.kernel_candidates > 0) result.greedy_guards = greedy_set_cover(cover_sets, coverable).size();
  }
  std::sort(chosen.begin(), chosen.end());
  if (!covers_all(cover_sets, coverable, chosen))
    throw Error("guard_surface: the chosen guards miss a face some candidate sees (a bug)");
  stage("refinement");

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
