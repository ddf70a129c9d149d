// pave(): all-quad mesh of one part by advancing-front paving (Blacker & Stephenson
// 1991; dissertation §3.3.1). The driver: input checks, the front loops, and a work
// queue of loops. Each step on a loop does the first of: close it with a template
// (<= 8 nodes), drop it if it is a zero-area slit, split it (or join a hole's loop to
// it) with a chord where its sides face each other, seam a sharp angle, cut an ear
// off a small loop, or pave one row. A loop that makes no progress twice gets a ring
// closure or, failing that, the triangulate-and-match fallback. Then doublets are
// collapsed, all interior points smoothed and the worst quads optimised; the output
// holds the input points first. A run that still fails is repeated with a slightly
// different target size (up to 8 sizes, 0.7 to 1.25 times it) before an Error is thrown.
#include "quad2d/paving.hpp"
#include "quad2d/grid_interior.hpp"
#include "quad2d/quad_cleanup.hpp"
#include "quad2d/untangle_quads.hpp"

#include "structmesh/check.hpp"
#include "structmesh/error.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numeric>
#include <string>

namespace structmesh {

namespace paving {

Paver::Paver(const Polygon2& boundary, const PavingOptions& options) : options_(options) {
  const std::size_t rings = boundary.ring_count();
  if (rings == 0) throw InputError("pave: the part has no boundary loop");
  if (boundary.points.size() % 2 != 0)
    throw InputError("pave: the part has " + std::to_string(boundary.points.size()) +
                     " boundary points; an all-quad mesh needs an even number");
  if (boundary.points.size() >= kInvalidIndex / 8) throw InputError("pave: too many boundary points");
  double perimeter = 0;
  for (std::size_t r = 0; r < rings; ++r) {
    const auto ring = boundary.ring(r);
    if (ring.size() < 3)
      throw InputError("pave: loop " + std::to_string(r) + " has " + std::to_string(ring.size()) +
                       " points; a loop needs at least 3");
    for (const Vec2& p : ring)
      if (!std::isfinite(p.x()) || !std::isfinite(p.y()))
        throw InputError("pave: loop " + std::to_string(r) + " has a non-finite point");
    const double a = signed_area(ring);
    if (r == 0 && !(a > 0)) throw InputError("pave: the outer loop (ring 0) must be counter-clockwise");
    if (r > 0 && !(a < 0)) throw InputError("pave: hole loop " + std::to_string(r) + " must be clockwise");
    for (std::size_t i = 0; i < ring.size(); ++i) perimeter += (ring[(i + 1) % ring.size()] - ring[i]).norm();
  }
  size_ = options.size > 0 ? options.size : perimeter / static_cast<double>(boundary.points.size());
  if (!(size_ > 0)) throw InputError("pave: the boundary has zero length");

  mesh_.points = boundary.points;
  mesh_.fixed_count = static_cast<Index>(boundary.points.size());
  mesh_.first_record.assign(boundary.points.size(), kInvalidIndex);
  const BoundingBox2 box = boundary.bounding_box();
  const double expected = std::abs(area(boundary)) / (size_ * size_) + static_cast<double>(boundary.points.size());
  grid_.init(box, size_, static_cast<std::size_t>(expected));
  mesh_.points.reserve(static_cast<std::size_t>(1.2 * expected) + 16);
  mesh_.quads.reserve(static_cast<std::size_t>(1.2 * expected) + 16);

  for (std::size_t r = 0; r < rings; ++r) {
    std::vector<Index> ring(boundary.ring_offsets[r + 1] - boundary.ring_offsets[r]);
    std::iota(ring.begin(), ring.end(), boundary.ring_offsets[r]);
    add_loop(ring, signed_area(boundary.ring(r)));
  }
}

Index Paver::add_loop(std::span<const Index> points, double area) {
  const auto id = static_cast<Index>(loops_.size());
  Loop loop;
  loop.alive = true;
  loop.size = static_cast<Index>(points.size());
  loop.area = area;
  Index first = kInvalidIndex, last = kInvalidIndex;
  for (const Index p : points) {
    const Index n = new_node(p, id);
    if (first == kInvalidIndex) {
      first = n;
    } else {
      set_next(last, n);
    }
    last = n;
  }
  set_next(last, first);
  loop.head = first;
  if (loop.area < 0) {
    negative_loops_.push_back(id);
    loop.listed = true;
  }
  loops_.push_back(loop);
  return id;
}

constexpr Index kEarLoop = 12;

bool Paver::step(Index loop) {
  const Loop& l = loops_[loop];
  if (std::abs(l.area) < 1e-9 * size_ * size_ && remove_slit(loop)) return true;
  if (l.area > 0 && l.size <= 8 && !contains_open_hole(loop) && close_with_template(loop)) return true;
  if (splits(loop)) return true;
  if (seams(loop)) return true;
  // Small loops: a whole row would leave notches that no template closes; cut the
  // best-shaped quad off instead.
  if (l.area > 0 && l.size <= kEarLoop && clip_ear(loop)) return true;
  if (row(loop)) {
    smooth_points(released_, options_.smoothing_iterations);
    released_.clear();
    return true;
  }
  return clip_ear(loop);
}

bool Paver::remove_slit(Index loop) {
  // A loop of zero area whose every edge is matched by the reverse edge (what is left
  // of a chord between two closed sides) bounds nothing: its edges are interior edges.
  std::vector<std::pair<Index, Index>> edges;
  for (const Index v : loop_nodes(loop)) edges.emplace_back(node_point_[v], node_point_[node_next_[v]]);
  std::vector<std::pair<Index, Index>> sorted = edges;
  std::sort(sorted.begin(), sorted.end());
  for (const auto& [a, b] : edges)
    if (!std::binary_search(sorted.begin(), sorted.end(), std::make_pair(b, a))) return false;
  for (const Index v : loop_nodes(loop)) kill_node(v);
  loops_[loop].alive = false;
  loops_[loop].size = 0;
  return true;
}

bool Paver::repair_inverted() {
  // Some quads come out of paving with a connectivity that no smoothing can untangle
  // (measured on the Gulf of Mexico: nearly collapsed quads of free points where
  // fronts met at a jagged coast). Their neighbourhood, grown by one more ring of
  // quads each round, is cut out and closed again by the fallback (triangulate and
  // match, which checks every quad it makes); a patch whose boundary it cannot
  // triangulate (overlapping quads around a fold) is grown further.
  const auto inverted = [&](const std::array<Index, 4>& q) {
    const auto& P = mesh_.points;
    return !(scaled_jacobian(P[q[0]], P[q[1]], P[q[2]], P[q[3]]) > 0);
  };
  constexpr int kRounds = 6;
  for (int round = 0; round < kRounds; ++round) {
    std::vector<Index> patch;
    std::vector<std::uint8_t> in_patch(mesh_.quads.size(), 0);
    for (Index id = 0; id < mesh_.quads.size(); ++id) {
      if (mesh_.quads[id][0] == kInvalidIndex || !inverted(mesh_.quads[id])) continue;
      patch.push_back(id);
      in_patch[id] = 1;
    }
    if (patch.empty()) return true;
    std::size_t begin = 0;
    for (int ring = 0; ring <= round; ++ring) {
      const std::size_t end = patch.size();
      for (std::size_t k = begin; k < end; ++k) {
        for (const Index v : mesh_.quads[patch[k]]) {
          mesh_.for_each_quad(v, [&](Index r) {
            if (in_patch[r] || mesh_.quads[r][0] == kInvalidIndex) return;
            in_patch[r] = 1;
            patch.push_back(r);
          });
        }
      }
      begin = end;
    }
    // The patch boundary: its quads' edges whose reverse is in no quad of the patch,
    // walked into closed rings (a point the boundary passes twice ends up in two
    // rings or twice in one; the triangulation merges it).
    std::vector<std::pair<Index, Index>> edges;
    for (const Index id : patch)
      for (int j = 0; j < 4; ++j) edges.emplace_back(mesh_.quads[id][j], mesh_.quads[id][(j + 1) % 4]);
    std::sort(edges.begin(), edges.end());
    std::vector<std::pair<Index, Index>> boundary;
    for (const auto& [a, b] : edges)
      if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(b, a))) boundary.emplace_back(a, b);
    std::vector<std::uint8_t> used(boundary.size(), 0);
    Polygon2 region;
    std::vector<Index> point_of;
    for (std::size_t e = 0; e < boundary.size(); ++e) {
      if (used[e]) continue;
      std::vector<Vec2> ring;
      const Index start = boundary[e].first;
      std::size_t at = e;
      while (true) {
        used[at] = 1;
        ring.push_back(mesh_.points[boundary[at].first]);
        point_of.push_back(boundary[at].first);
        const Index b = boundary[at].second;
        if (b == start) break;
        auto it = std::lower_bound(boundary.begin(), boundary.end(), std::make_pair(b, Index{0}));
        while (it != boundary.end() && it->first == b && used[static_cast<std::size_t>(it - boundary.begin())]) ++it;
        if (it == boundary.end() || it->first != b) break;  // cannot happen: in = out degree
        at = static_cast<std::size_t>(it - boundary.begin());
      }
      region.add_ring(ring);
    }
    try {
      close_region(region, point_of, "paving: remeshing around inverted quads");
    } catch (const Error&) {
      continue;  // a larger patch next round
    }
    for (const Index id : patch) mesh_.quads[id] = {kInvalidIndex, kInvalidIndex, kInvalidIndex, kInvalidIndex};
    mesh_.rebuild_records();
    released_.clear();
    collapse_doublets();
    final_smoothing();
    ++stats_.repairs;
  }
  for (const auto& q : mesh_.quads)
    if (q[0] != kInvalidIndex && inverted(q)) return false;
  return true;
}

bool Paver::untangle_inverted() {
  const auto inverted = [&](const std::array<Index, 4>& q) {
    const auto& P = mesh_.points;
    return !(scaled_jacobian(P[q[0]], P[q[1]], P[q[2]], P[q[3]]) > 0);
  };
  // Wider zones give the points more room but cost more; a zone is every free point
  // within `rings` quad rings of an inverted quad.
  for (const int rings : {3, 10}) {
    std::vector<Index> zone;
    for (const auto& q : mesh_.quads)
      if (q[0] != kInvalidIndex && inverted(q)) zone.insert(zone.end(), q.begin(), q.end());
    if (zone.empty()) return true;
    // A point of several inverted quads is listed once (untangle_quads takes each free
    // point as one variable).
    std::sort(zone.begin(), zone.end());
    zone.erase(std::unique(zone.begin(), zone.end()), zone.end());
    std::vector<std::uint8_t> in_zone(mesh_.points.size(), 0);
    for (const Index v : zone) in_zone[v] = 1;
    std::size_t begin = 0;
    for (int ring = 0; ring < rings; ++ring) {
      const std::size_t end = zone.size();
      for (std::size_t k = begin; k < end; ++k) {
        mesh_.for_each_quad(zone[k], [&](Index r) {
          for (const Index w : mesh_.quads[r])
            if (!in_zone[w]) in_zone[w] = 1, zone.push_back(w);
        });
      }
      begin = end;
    }
    std::vector<Index> free;
    for (const Index v : zone)
      if (v >= mesh_.fixed_count) free.push_back(v);
    std::sort(free.begin(), free.end());
    if (untangle_quads(mesh_.points, mesh_.quads, free, size_).valid &&
        std::none_of(mesh_.quads.begin(), mesh_.quads.end(),
                     [&](const auto& q) { return q[0] != kInvalidIndex && inverted(q); })) {
      ++stats_.untangled;
      return true;
    }
  }
  return false;
}

PavedPart Paver::run() {
  std::deque<Index> queue;
  for (Index l = 0; l < loops_.size(); ++l) queue.push_back(l);
  std::size_t idle = 0;  // consecutive steps without progress
  while (!queue.empty()) {
    const Index l = queue.front();
    queue.pop_front();
    if (!loops_[l].alive) continue;
    const std::size_t loops_before = loops_.size();
    const bool progress = step(l);
    for (Index k = static_cast<Index>(loops_before); k < loops_.size(); ++k) queue.push_back(k);
    if (progress) {
      idle = 0;
      loops_[l].stuck = 0;
      if (loops_[l].alive) queue.push_back(l);
      continue;
    }
    ++loops_[l].stuck;
    // A loop bounding its component that makes no progress twice is closed by the
    // fallback; a hole's loop waits for the front around it.
    if (loops_[l].area > 0 && loops_[l].stuck >= 2) {
      if (!close_with_ring(l)) fallback(l);
      for (Index k = static_cast<Index>(loops_before); k < loops_.size(); ++k) queue.push_back(k);
      idle = 0;
      continue;
    }
    queue.push_back(l);
    if (++idle > 2 * queue.size() + 2) {
      Index outer = kInvalidIndex;
      for (const Index k : queue)
        if (loops_[k].alive && loops_[k].area > 0 && (outer == kInvalidIndex || k < outer)) outer = k;
      if (outer == kInvalidIndex)
        throw Error("paving: " + std::to_string(queue.size()) +
                    " front loop(s) are left without an enclosing front (inconsistent loop orientation?)");
      fallback(outer);
      idle = 0;
    }
  }
  released_.clear();
  collapse_doublets();
  collapse_diamonds();
  final_smoothing();
  if (!untangle_inverted()) repair_inverted();

  // Output: the input points, then the new points still in use, in creation order.
  PavedPart part;
  std::vector<Index> remap(mesh_.points.size(), kInvalidIndex);
  part.points.assign(mesh_.points.begin(), mesh_.points.begin() + mesh_.fixed_count);
  for (Index p = 0; p < mesh_.fixed_count; ++p) remap[p] = p;
  for (Index p = mesh_.fixed_count; p < mesh_.points.size(); ++p) {
    if (mesh_.first_record[p] == kInvalidIndex) continue;
    remap[p] = static_cast<Index>(part.points.size());
    part.points.push_back(mesh_.points[p]);
  }
  part.quads.reserve(mesh_.quads.size());
  std::size_t inverted = 0;
  for (const auto& q : mesh_.quads) {
    if (q[0] == kInvalidIndex) continue;  // merged away (collapse_doublets)
    const auto& P = mesh_.points;
    if (!(scaled_jacobian(P[q[0]], P[q[1]], P[q[2]], P[q[3]]) > 0)) ++inverted;
    part.quads.push_back({remap[q[0]], remap[q[1]], remap[q[2]], remap[q[3]]});
  }
  if (inverted > 0)
    throw Error("paving: " + std::to_string(inverted) + " of " + std::to_string(mesh_.quads.size()) +
                " quads are inverted or degenerate after smoothing");
  part.stats = stats_;
  return part;
}

PavedPart pave_whole(const Polygon2& boundary, const PavingOptions& options, bool polish, int cleanup_passes) {
  // The worst quad that the block meshers accept (MappedMeshOptions); a paved part
  // below it is polished.
  constexpr double kPolishBelow = 0.6;
  // Every paving decision depends on the target size: when a run ends with a quad it
  // could not untangle or a loop nothing closes, a run with a slightly different size
  // takes other decisions and almost always succeeds (deterministic: fixed factors).
  std::string first_error;
  double size = 0;  // the first run's size: every factor applies to it
  // The last factors differ more: a part whose boundary has features near the size
  // (a pass between an island and the shore) may need smaller or larger rows.
  for (const double factor : {1.0, 0.95, 1.06, 0.9, 1.12, 0.8, 1.25, 0.7}) {
    PavingOptions o = options;
    if (factor != 1.0) o.size = size * factor;
    paving::Paver paver(boundary, o);
    if (factor == 1.0) size = paver.size();
    try {
      PavedPart part = paver.run();
      part.stats.retries = first_error.empty() ? 0 : 1;
      const paving::CleanupStats cleanup = paving::clean_up_quads(
          part.points, part.quads, static_cast<Index>(boundary.points.size()), paver.size(), cleanup_passes);
      part.stats.cleanup_operations = cleanup.swaps + cleanup.collapses + cleanup.doublets;
      // A part whose worst quad is poor (a row squeezed between fronts) gets the
      // angle polish of its free points; kept only if the worst quad improves.
      if (polish && paving::min_scaled_jacobian(part.points, part.quads) < kPolishBelow)
        paving::polish_quads(part.points, part.quads, static_cast<Index>(boundary.points.size()), paver.size(),
                             kPolishBelow, paving::kConformalEnergy);
      return part;
    } catch (const InputError&) {
      throw;
    } catch (const Error& e) {
      if (first_error.empty()) {
        first_error = e.what();
        // A boundary that crosses or touches itself (a coarse sampling of a jagged
        // coastline can do that) bounds no region a mesh can fill: say so at once.
        const RegionReport check = check_region({boundary});
        if (check.self_intersections > 0)
          throw InputError("pave: the part boundary crosses or touches itself (" +
                           std::to_string(check.self_intersections) + " times; " + check.problems.front().message +
                           "), so no quad mesh keeps it");
      }
    }
  }
  throw Error(first_error + " (and with target sizes from 0.7 to 1.25 times it)");
}

}  // namespace paving

PavedPart pave(const Polygon2& boundary, const PavingOptions& options) {
  if (options.grid_interior_quads > 0 && options.size > 0 && boundary.ring_count() > 0 &&
      std::abs(area(boundary)) >= static_cast<double>(options.grid_interior_quads) * options.size * options.size)
    if (std::optional<PavedPart> part = paving::pave_with_grid_interior(boundary, options)) return std::move(*part);
  return paving::pave_whole(boundary, options, true);
}

}  // namespace structmesh
