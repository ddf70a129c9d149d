// pave_with_grid_interior(): a large part gets a structured grid of squares in its
// interior and paving only in a band along its boundary.
//
// Paving costs the same per quad wherever the quad is (rows, seams, smoothing, cleanup:
// about 90k quads/s per core), but far from the boundary its rows are parallel and its
// quads nearly square anyway. The grid-based (overlay) methods (Schneiders 1996,
// "A grid-based algorithm for the generation of hexahedral element meshes", Engineering
// with Computers 12) fill the interior with a grid and mesh only the rest; here the rest
// is paved, so the boundary samples stay exactly as they are and the part still conforms
// to its neighbours. On a part of 250k quads the band holds a few percent of them.
//
// The grid is rotated to the dominant direction of the boundary (the length-weighted
// mean of 4θ over its segments, so that a rectangle gets an aligned grid). A cell is
// kept when it lies inside the part and its centre is at least kMarginCells + √2/2 cell
// sizes from every boundary segment; the 4-connected sets of kept cells that are not
// tiny stay (each a grid of its own; a part that narrows somewhere has several),
// cleaned until their boundary is a set of simple lattice loops: no cell with two
// opposite empty neighbours (a corridor one cell wide), no two cells that touch only at
// a corner, no hole without a hole of the part inside. The band between the part's loops
// and the grid's loops is paved with the grid's boundary vertices fixed; a hole of a
// grid (around an island of the part, or around a smaller grid) is paved on its own. The
// lattice loops have an even length, so every band keeps the parity an all-quad mesh
// needs whenever the part's loops inside it do. Then the points around the seam between
// grid and band are relaxed together (untangle_quads' barrier energy, never folding a quad).
//
// Anything that does not work out (a part too thin for a grid, a band whose paving
// fails, a band of odd parity) returns nullopt and the part is paved whole.
#include "quad2d/grid_interior.hpp"

#include "quad2d/paving.hpp"

#include "structmesh/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace structmesh::paving {

namespace {

/// Cells whose centre is closer than this many sizes (plus half a diagonal) to the
/// boundary are left to paving: about two rows from each side of the band.
constexpr double kMarginCells = 2.0;
/// A set of cells apart from the largest is a grid of its own from this many cells on.
/// With the largest set only, a part whose interior narrows somewhere had its other lobes
/// paved whole: a Gulf part of 820k quads at 20M quads (two lobes joined by a neck under
/// the margin) got a grid of 408k quads and took 5.3 s, with both lobes 776k and 3.0 s.
/// A set this small saves little paving.
constexpr std::size_t kMinGridCells = 256;
/// Rings of quads on each side of the seam that the final relaxation moves.
constexpr int kSeamRings = 3;
/// Laplacian sweeps over them.
constexpr int kSeamSweeps = 10;
/// Cleanup passes of a band (clean_up_quads()), against kCleanupPasses for a part paved
/// whole. A band lies between the part's boundary and the grid's staircase loop, whose
/// corners keep edge rotations going through every pass while few of them pay (a Key part
/// at 20M quads: 12k cleanup moves for a band of 8k quads). Measured on two threads, 30
/// passes against 10: Gulf at 20M quads paving 28.8 -> 19.2 s, singular vertices 49,887 ->
/// 50,518; Key at 20M 23.8 -> 18.6 s, 36,975 -> 37,127; Key at 2M in 64 parts 4.5 -> 3.4 s,
/// 7,988 -> 7,998 (15 passes: Gulf 21.3 s, 49,555).
constexpr int kBandCleanupPasses = 10;

struct Lattice {
  Vec2 axis_u, axis_v;  // the grid's directions
  double u0 = 0, v0 = 0, h = 0;
  std::int64_t nx = 0, ny = 0;  // cells
  std::size_t cell(std::int64_t i, std::int64_t j) const { return static_cast<std::size_t>(j * nx + i); }
  std::size_t vertex(std::int64_t i, std::int64_t j) const { return static_cast<std::size_t>(j * (nx + 1) + i); }
  Vec2 position(std::size_t vertex_id) const {
    const auto i = static_cast<std::int64_t>(vertex_id % static_cast<std::size_t>(nx + 1));
    const auto j = static_cast<std::int64_t>(vertex_id / static_cast<std::size_t>(nx + 1));
    const double u = u0 + static_cast<double>(i) * h, v = v0 + static_cast<double>(j) * h;
    return u * axis_u + v * axis_v;
  }
};

double dominant_direction(const Polygon2& boundary) {
  double c4 = 0, s4 = 0;
  for (std::size_t r = 0; r < boundary.ring_count(); ++r) {
    const auto ring = boundary.ring(r);
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Vec2 d = ring[(i + 1) % ring.size()] - ring[i];
      const double length = d.norm();
      if (!(length > 0)) continue;
      const double angle = std::atan2(d.y(), d.x());
      c4 += length * std::cos(4 * angle);
      s4 += length * std::sin(4 * angle);
    }
  }
  return 0.25 * std::atan2(s4, c4);
}

/// Labels the 4-connected sets of cells whose flag is `value` 0, 1, 2, ... in the
/// row-major order of their first cell (-1 for the other cells); returns their sizes.
std::vector<std::size_t> label_sets(const Lattice& L, const std::vector<std::uint8_t>& keep, std::uint8_t value,
                                    std::vector<std::int32_t>& label) {
  label.assign(keep.size(), -1);
  std::vector<std::size_t> sizes, stack;
  for (std::size_t c = 0; c < keep.size(); ++c) {
    if (keep[c] != value || label[c] >= 0) continue;
    const auto id = static_cast<std::int32_t>(sizes.size());
    std::size_t size = 0;
    label[c] = id;
    stack.push_back(c);
    while (!stack.empty()) {
      const std::size_t at = stack.back();
      stack.pop_back();
      ++size;
      const auto i = static_cast<std::int64_t>(at % static_cast<std::size_t>(L.nx));
      const auto j = static_cast<std::int64_t>(at / static_cast<std::size_t>(L.nx));
      const std::int64_t di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
      for (int k = 0; k < 4; ++k) {
        const std::int64_t a = i + di[k], b = j + dj[k];
        if (a < 0 || b < 0 || a >= L.nx || b >= L.ny) continue;
        const std::size_t n = L.cell(a, b);
        if (keep[n] == value && label[n] < 0) {
          label[n] = id;
          stack.push_back(n);
        }
      }
    }
    sizes.push_back(size);
  }
  return sizes;
}

/// Keeps the 4-connected sets of cells with keep = 1 that hold at least kMinGridCells
/// cells (the largest one whatever its size).
void keep_large_components(const Lattice& L, std::vector<std::uint8_t>& keep) {
  std::vector<std::int32_t> label;
  const std::vector<std::size_t> sizes = label_sets(L, keep, 1, label);
  if (sizes.empty()) return;
  const auto largest = static_cast<std::int32_t>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  for (std::size_t c = 0; c < keep.size(); ++c)
    keep[c] = keep[c] && (label[c] == largest || sizes[static_cast<std::size_t>(label[c])] >= kMinGridCells);
}

/// Removes cells until the kept set's boundary is a set of simple lattice loops: no
/// cell with both left and right, or both lower and upper, neighbours empty, and no
/// lattice vertex with exactly two diagonally opposite kept cells. True if it changed.
bool remove_thin_cells(const Lattice& L, std::vector<std::uint8_t>& keep) {
  bool changed = false;
  auto kept = [&](std::int64_t i, std::int64_t j) {
    return i >= 0 && j >= 0 && i < L.nx && j < L.ny && keep[L.cell(i, j)] != 0;
  };
  for (bool again = true; again;) {
    again = false;
    for (std::int64_t j = 0; j < L.ny; ++j)
      for (std::int64_t i = 0; i < L.nx; ++i) {
        if (!kept(i, j)) continue;
        const bool thin = (!kept(i - 1, j) && !kept(i + 1, j)) || (!kept(i, j - 1) && !kept(i, j + 1));
        if (thin) {
          keep[L.cell(i, j)] = 0;
          again = changed = true;
        }
      }
    // Vertex (i, j) is the lower-left corner of cell (i, j).
    for (std::int64_t j = 0; j <= L.ny; ++j)
      for (std::int64_t i = 0; i <= L.nx; ++i) {
        const bool a = kept(i - 1, j - 1), b = kept(i, j - 1), c = kept(i, j), d = kept(i - 1, j);
        if (a && c && !b && !d) {
          keep[L.cell(i - 1, j - 1)] = 0;
          again = changed = true;
        } else if (b && d && !a && !c) {
          keep[L.cell(i, j - 1)] = 0;
          again = changed = true;
        }
      }
  }
  return changed;
}

/// Labels the 4-connected sets of empty cells: 0 for the one touching the lattice's
/// border (cell 0 is on the empty border row), 1, 2, ... for the grid's holes.
std::vector<std::int32_t> label_empty(const Lattice& L, const std::vector<std::uint8_t>& keep, std::int32_t& count) {
  std::vector<std::int32_t> label;
  count = static_cast<std::int32_t>(label_sets(L, keep, 0, label).size());
  return label;
}

struct Component {
  Polygon2 polygon;
  std::vector<Index> source;  // per boundary point: a part point (< part count) or part count + lattice vertex
};

}  // namespace

std::optional<PavedPart> pave_with_grid_interior(const Polygon2& boundary, const PavingOptions& options) {
  const double h = options.size;
  if (!(h > 0) || boundary.ring_count() == 0) return std::nullopt;
  Lattice L;
  const double theta = dominant_direction(boundary);
  L.axis_u = Vec2(std::cos(theta), std::sin(theta));
  L.axis_v = Vec2(-std::sin(theta), std::cos(theta));
  L.h = h;
  double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
  for (const Vec2& p : boundary.points) {
    const double u = p.dot(L.axis_u), v = p.dot(L.axis_v);
    umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v), vmax = std::max(vmax, v);
  }
  // One empty cell of border on each side; the lattice is anchored to the part's
  // extent so the result does not depend on where the part lies in the plane.
  L.u0 = umin - h, L.v0 = vmin - h;
  L.nx = static_cast<std::int64_t>(std::ceil((umax - L.u0) / h)) + 2;
  L.ny = static_cast<std::int64_t>(std::ceil((vmax - L.v0) / h)) + 2;
  if (L.nx < 8 || L.ny < 8 || static_cast<double>(L.nx) * static_cast<double>(L.ny) > 2.0e8) return std::nullopt;

  // Inside: even-odd crossings of each cell row's centre line.
  std::vector<std::uint8_t> keep(static_cast<std::size_t>(L.nx * L.ny), 0);
  {
    std::vector<std::pair<std::int64_t, double>> crossings;
    for (std::size_t r = 0; r < boundary.ring_count(); ++r) {
      const auto ring = boundary.ring(r);
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const Vec2 a = ring[k], b = ring[(k + 1) % ring.size()];
        const double ua = a.dot(L.axis_u), va = a.dot(L.axis_v), ub = b.dot(L.axis_u), vb = b.dot(L.axis_v);
        const double lo = std::min(va, vb), hi = std::max(va, vb);
        // Rows j with centre v_j in [lo, hi): half-open so a vertex on a row counts once.
        auto j = static_cast<std::int64_t>(std::ceil((lo - L.v0) / h - 0.5));
        for (; j < L.ny; ++j) {
          const double vc = L.v0 + (static_cast<double>(j) + 0.5) * h;
          if (vc >= hi) break;
          if (vc < lo) continue;
          const double t = (vc - va) / (vb - va);
          crossings.emplace_back(j, ua + t * (ub - ua));
        }
      }
    }
    std::sort(crossings.begin(), crossings.end());
    for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) {
      if (crossings[k].first != crossings[k + 1].first) return std::nullopt;  // an open loop
      const std::int64_t j = crossings[k].first;
      const auto i0 = static_cast<std::int64_t>(std::ceil((crossings[k].second - L.u0) / h - 0.5));
      const auto i1 = static_cast<std::int64_t>(std::ceil((crossings[k + 1].second - L.u0) / h - 0.5));
      for (std::int64_t i = std::max<std::int64_t>(i0, 0); i < std::min(i1, L.nx); ++i) keep[L.cell(i, j)] = 1;
    }
  }
  // Near the boundary: every cell whose centre is within the margin of a segment.
  const double reach = (kMarginCells + 0.7072) * h;
  for (std::size_t r = 0; r < boundary.ring_count(); ++r) {
    const auto ring = boundary.ring(r);
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const Vec2 a(ring[k].dot(L.axis_u), ring[k].dot(L.axis_v));
      const Vec2 b(ring[(k + 1) % ring.size()].dot(L.axis_u), ring[(k + 1) % ring.size()].dot(L.axis_v));
      const auto i0 =
          std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor((std::min(a.x(), b.x()) - reach - L.u0) / h)));
      const auto i1 = std::min<std::int64_t>(
          L.nx - 1, static_cast<std::int64_t>(std::floor((std::max(a.x(), b.x()) + reach - L.u0) / h)));
      const auto j0 =
          std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor((std::min(a.y(), b.y()) - reach - L.v0) / h)));
      const auto j1 = std::min<std::int64_t>(
          L.ny - 1, static_cast<std::int64_t>(std::floor((std::max(a.y(), b.y()) + reach - L.v0) / h)));
      for (std::int64_t j = j0; j <= j1; ++j)
        for (std::int64_t i = i0; i <= i1; ++i) {
          const std::size_t c = L.cell(i, j);
          if (!keep[c]) continue;
          const Vec2 centre(L.u0 + (static_cast<double>(i) + 0.5) * h, L.v0 + (static_cast<double>(j) + 0.5) * h);
          if ((centre - closest_on_segment(centre, a, b)).squaredNorm() < reach * reach) keep[c] = 0;
        }
    }
  }

  // The large clean sets of cells; holes of them without a hole of the part are filled.
  std::int32_t empty_count = 0;
  std::vector<std::int32_t> empty_label;
  std::vector<std::int32_t> ring_label(boundary.ring_count(), 0);
  for (int round = 0;; ++round) {
    if (round == 8) return std::nullopt;
    keep_large_components(L, keep);
    while (remove_thin_cells(L, keep)) keep_large_components(L, keep);
    empty_label = label_empty(L, keep, empty_count);
    std::vector<std::uint8_t> has_ring(static_cast<std::size_t>(empty_count), 0), odd(has_ring.size(), 0);
    std::vector<std::array<std::int64_t, 2>> ring_cell(boundary.ring_count());
    has_ring[0] = 1;
    for (std::size_t r = 1; r < boundary.ring_count(); ++r) {
      const Vec2 p = boundary.ring(r)[0];
      const auto i = static_cast<std::int64_t>(std::floor((p.dot(L.axis_u) - L.u0) / h));
      const auto j = static_cast<std::int64_t>(std::floor((p.dot(L.axis_v) - L.v0) / h));
      if (i < 0 || j < 0 || i >= L.nx || j >= L.ny) return std::nullopt;
      const std::size_t c = L.cell(i, j);
      if (keep[c]) return std::nullopt;  // cannot happen: cells at the boundary are empty
      ring_label[r] = empty_label[c];
      ring_cell[r] = {i, j};
      has_ring[static_cast<std::size_t>(ring_label[r])] = 1;
      odd[static_cast<std::size_t>(ring_label[r])] ^= static_cast<std::uint8_t>(boundary.ring(r).size() % 2);
    }
    bool changed = false;
    for (std::size_t c = 0; c < keep.size(); ++c)
      if (!keep[c] && !has_ring[static_cast<std::size_t>(empty_label[c])]) keep[c] = 1, changed = true;
    // A hole of the grid whose islands have an odd number of points in all could not be
    // paved on its own: a corridor three cells wide joins it to the outer band.
    for (std::size_t r = 1; r < boundary.ring_count(); ++r) {
      const std::int32_t label = ring_label[r];
      if (label == 0 || !odd[static_cast<std::size_t>(label)]) continue;
      odd[static_cast<std::size_t>(label)] = 0;
      const auto [i0, j] = ring_cell[r];
      for (std::int64_t i = i0; i < L.nx; ++i) {
        if (i > i0 && !keep[L.cell(i, j)] && empty_label[L.cell(i, j)] == 0) break;
        for (std::int64_t dj = -1; dj <= 1; ++dj)
          if (j + dj >= 0 && j + dj < L.ny) keep[L.cell(i, j + dj)] = 0;
      }
      changed = true;
    }
    if (!changed) break;
  }
  const std::size_t kept_cells = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), std::uint8_t{1}));
  if (kept_cells < 64) return std::nullopt;

  // The grid's boundary loops, with the grid on the right of every directed edge (each
  // cell's empty sides clockwise): an outer loop runs clockwise (a hole of the band
  // around it) and a loop around a hole of the grid counter-clockwise.
  const std::size_t vertex_count = static_cast<std::size_t>((L.nx + 1) * (L.ny + 1));
  std::vector<Index> next_vertex(vertex_count, kInvalidIndex);
  std::vector<std::int32_t> left_label(vertex_count, -1);  // the empty set on the left of the edge leaving a vertex
  auto kept = [&](std::int64_t i, std::int64_t j) {
    return i >= 0 && j >= 0 && i < L.nx && j < L.ny && keep[L.cell(i, j)] != 0;
  };
  for (std::int64_t j = 0; j < L.ny; ++j)
    for (std::int64_t i = 0; i < L.nx; ++i) {
      if (!kept(i, j)) continue;
      auto edge = [&](std::size_t from, std::size_t to, std::int64_t ei, std::int64_t ej) {
        next_vertex[from] = static_cast<Index>(to);
        left_label[from] = empty_label[L.cell(ei, ej)];
      };
      if (!kept(i, j - 1)) edge(L.vertex(i + 1, j), L.vertex(i, j), i, j - 1);
      if (!kept(i - 1, j)) edge(L.vertex(i, j), L.vertex(i, j + 1), i - 1, j);
      if (!kept(i, j + 1)) edge(L.vertex(i, j + 1), L.vertex(i + 1, j + 1), i, j + 1);
      if (!kept(i + 1, j)) edge(L.vertex(i + 1, j + 1), L.vertex(i + 1, j), i + 1, j);
    }

  // Bands: label 0 is the part's outer loop, the holes of the part outside the grid
  // and the grid's outer loop; label k > 0 is a hole of the grid with the part's holes
  // inside it.
  const auto part_count = static_cast<Index>(boundary.points.size());
  std::vector<Component> bands(static_cast<std::size_t>(empty_count));
  auto add_part_ring = [&](Component& band, std::size_t r) {
    band.polygon.add_ring(boundary.ring(r));
    for (Index p = boundary.ring_offsets[r]; p < boundary.ring_offsets[r + 1]; ++p) band.source.push_back(p);
  };
  add_part_ring(bands[0], 0);
  // Every lattice loop, then the loops into their bands: a band k > 0 (a hole of one
  // set of cells) has that hole's loop, counter-clockwise, as its first ring and the
  // outer loops of the sets inside the hole as holes of its own.
  struct LatticeLoop {
    std::int32_t label;
    bool counter_clockwise;
    std::vector<Vec2> points;
    std::vector<Index> source;
  };
  std::vector<LatticeLoop> lattice_loops;
  std::vector<std::uint8_t> visited(vertex_count, 0);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    if (next_vertex[v] == kInvalidIndex || visited[v]) continue;
    LatticeLoop loop{left_label[v], false, {}, {}};
    for (std::size_t at = v; !visited[at]; at = next_vertex[at]) {
      visited[at] = 1;
      loop.points.push_back(L.position(at));
      loop.source.push_back(part_count + static_cast<Index>(at));
      if (left_label[at] != loop.label) return std::nullopt;  // cannot happen for a clean set
    }
    loop.counter_clockwise = signed_area(loop.points) > 0;
    // The empty set around the lattice (label 0) meets only outer (clockwise) loops.
    if (loop.label == 0 && loop.counter_clockwise) return std::nullopt;
    lattice_loops.push_back(std::move(loop));
  }
  for (const bool first : {true, false})
    for (const LatticeLoop& loop : lattice_loops) {
      if ((loop.label > 0 && loop.counter_clockwise) != first) continue;
      Component& band = bands[static_cast<std::size_t>(loop.label)];
      if (first && band.polygon.ring_count() > 0) return std::nullopt;                      // two loops around one hole
      if (!first && loop.label > 0 && band.polygon.ring_count() == 0) return std::nullopt;  // no outer loop
      band.polygon.add_ring(loop.points);
      band.source.insert(band.source.end(), loop.source.begin(), loop.source.end());
    }
  for (std::size_t r = 1; r < boundary.ring_count(); ++r)
    add_part_ring(bands[static_cast<std::size_t>(ring_label[r])], r);
  for (const Component& band : bands)
    if (band.polygon.ring_count() < 2 || band.polygon.points.size() % 2 != 0) return std::nullopt;

  // Pave the bands (not with a grid again).
  // Not polished: polish_quads() works on the whole band at once, which costs more
  // than paving it; the seam relaxation below and the merge's relaxation follow.
  const PavingOptions& band_options = options;
  std::vector<PavedPart> paved(bands.size());
  try {
    for (std::size_t b = 0; b < bands.size(); ++b)
      paved[b] = pave_whole(bands[b].polygon, band_options, false, kBandCleanupPasses);
  } catch (const Error&) {
    return std::nullopt;
  }

  // Assemble: the part's points first (as every mesher returns them), then the band
  // interiors, then the grid's vertices.
  PavedPart part;
  part.points = boundary.points;
  std::vector<Index> lattice_point(vertex_count, kInvalidIndex);
  auto point_of = [&](Index source) -> Index {
    if (source < part_count) return source;
    Index& at = lattice_point[source - part_count];
    if (at == kInvalidIndex) {
      at = static_cast<Index>(part.points.size());
      part.points.push_back(L.position(source - part_count));
    }
    return at;
  };
  std::vector<std::uint8_t> seam_point;  // per part point: on the grid's boundary loops
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const PavedPart& band = paved[b];
    std::vector<Index> map(band.points.size());
    for (std::size_t k = 0; k < bands[b].source.size(); ++k) map[k] = point_of(bands[b].source[k]);
    for (std::size_t k = bands[b].source.size(); k < band.points.size(); ++k) {
      map[k] = static_cast<Index>(part.points.size());
      part.points.push_back(band.points[k]);
    }
    for (const auto& q : band.quads) part.quads.push_back({map[q[0]], map[q[1]], map[q[2]], map[q[3]]});
    part.stats.rows += band.stats.rows;
    part.stats.seams += band.stats.seams;
    part.stats.splits += band.stats.splits;
    part.stats.templates += band.stats.templates;
    part.stats.fallback_loops += band.stats.fallback_loops;
    part.stats.repairs += band.stats.repairs;
    part.stats.untangled += band.stats.untangled;
    part.stats.retries = std::max(part.stats.retries, band.stats.retries);
    part.stats.cleanup_operations += band.stats.cleanup_operations;
  }
  seam_point.assign(part.points.size(), 0);
  for (std::size_t v = 0; v < vertex_count; ++v)
    if (next_vertex[v] != kInvalidIndex) seam_point[lattice_point[v]] = 1;
  const std::size_t band_quads = part.quads.size();
  for (std::int64_t j = 0; j < L.ny; ++j)
    for (std::int64_t i = 0; i < L.nx; ++i)
      if (kept(i, j)) {
        const auto base = static_cast<Index>(part_count);
        part.quads.push_back({point_of(base + static_cast<Index>(L.vertex(i, j))),
                              point_of(base + static_cast<Index>(L.vertex(i + 1, j))),
                              point_of(base + static_cast<Index>(L.vertex(i + 1, j + 1))),
                              point_of(base + static_cast<Index>(L.vertex(i, j + 1)))});
      }
  seam_point.resize(part.points.size(), 0);
  part.stats.grid_interior_quads = part.quads.size() - band_quads;

  // Relax the seam: a guarded Laplacian of its points and kSeamRings rings of points
  // around them (the grid's corners stand fixed while the band is paved). A move is
  // kept only if the worst quad around the point gets no worse, so no quad folds and
  // the part's worst quad stays what paving gave (with the paver's floor of 0.5
  // instead, a Gulf part's worst quad fell from 0.66 to 0.51).
  const CompressedRows quads_of =
      build_vertex_elements(std::span<const std::array<Index, 4>>(part.quads), part.points.size());
  std::vector<std::uint8_t> in_zone(part.points.size(), 0);
  std::vector<Index> zone;
  for (Index p = 0; p < part.points.size(); ++p)
    if (seam_point[p]) in_zone[p] = 1, zone.push_back(p);
  for (int ring = 0, begin = 0; ring < kSeamRings; ++ring) {
    const auto end = static_cast<int>(zone.size());
    for (int k = begin; k < end; ++k) {
      for (const Index id : quads_of.row(zone[static_cast<std::size_t>(k)]))
        for (const Index v : part.quads[id])
          if (!in_zone[v] && v >= part_count) in_zone[v] = 1, zone.push_back(v);
    }
    begin = end;
  }
  std::sort(zone.begin(), zone.end());
  auto worst_around = [&](Index p) {
    double worst = 2;
    for (const Index id : quads_of.row(p)) {
      const auto& q = part.quads[id];
      const auto& P = part.points;
      worst = std::min(worst, scaled_jacobian(P[q[0]], P[q[1]], P[q[2]], P[q[3]]));
    }
    return worst;
  };
  for (int sweep = 0; sweep < kSeamSweeps; ++sweep)
    for (const Index p : zone) {
      Vec2 target(0, 0);
      int count = 0;
      for (const Index id : quads_of.row(p)) {
        const auto& q = part.quads[id];
        int j = 0;
        while (q[j] != p) ++j;
        target += 0.5 * (part.points[q[(j + 1) % 4]] + part.points[q[(j + 3) % 4]]);
        ++count;
      }
      if (count == 0) continue;
      target /= count;
      const Vec2 now = part.points[p];
      const double floor = worst_around(p);
      part.points[p] = target;
      const double after = worst_around(p);
      if (!(after >= floor && after > 0)) part.points[p] = now;
    }
  return part;
}

}  // namespace structmesh::paving
