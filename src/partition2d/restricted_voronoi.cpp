// Restricted Voronoi diagram of the sites in the domain (design/partition2d.md §2.2):
// every CDT triangle is clipped against the Voronoi cells meeting it (convex ∩
// convex, Yan-Wang-Lévy-Liu 2013 style), vertices carry symbolic keys, and every
// "which side of a bisector" decision is an exact predicate, so neighbouring
// triangles and neighbouring cells always agree and the pieces tile the domain.
#include "partition2d/restricted_voronoi_impl.hpp"

#include "structmesh/error.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_sort.h>
#include <oneapi/tbb/partitioner.h>

#include <algorithm>
#include <array>
#include <utility>

namespace structmesh::partition2d {

namespace rvd {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<Index, Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;

constexpr std::size_t kBlockSize = 1024;

// Semi-static floating-point filter: a double together with the sum of the
// magnitudes of everything that went into it. For the shallow expressions below
// (depth < 12) the rounding error is below 12 eps m < 1e-13 m, so a value larger than
// that decides the sign; otherwise the predicate goes to intervals, then exact.
struct Bounded {
  double v = 0, m = 0;
  explicit Bounded(double x) : v(x), m(std::abs(x)) {}
  Bounded(double value, double magnitude) : v(value), m(magnitude) {}
};
Bounded operator+(const Bounded& x, const Bounded& y) { return {x.v + y.v, x.m + y.m}; }
Bounded operator-(const Bounded& x, const Bounded& y) { return {x.v - y.v, x.m + y.m}; }
Bounded operator*(const Bounded& x, const Bounded& y) { return {x.v * y.v, x.m * y.m}; }

constexpr double kFilterRelative = 1e-13;
constexpr double kFilterAbsolute = 1e-280;  // far above the underflow range

// 0 when the filter cannot decide.
int filtered_sign(const Bounded& x) {
  if (std::abs(x.v) <= kFilterRelative * x.m || std::abs(x.v) <= kFilterAbsolute) return 0;
  return x.v > 0 ? 1 : -1;
}
int certain_sign(const CGAL::Interval_nt<false>& x) { return static_cast<int>(CGAL::sign(x).make_certain()); }
int certain_sign(const CGAL::Exact_rational& x) { return static_cast<int>(CGAL::sign(x)); }

// +1 when q is strictly closer to a than to b, 0 at equal distance, -1 otherwise.
int closer_sign(const Vec2& q, const Vec2& a, const Vec2& b) {
  const double da = (q - a).squaredNorm(), db = (q - b).squaredNorm();
  const int s = filtered_sign(Bounded(db - da, da + db));
  if (s != 0) return s;
  const CGAL::Comparison_result r =
      CGAL::compare_distance_to_point(Point(q.x(), q.y()), Point(a.x(), a.y()), Point(b.x(), b.y()));
  return r == CGAL::SMALLER ? 1 : r == CGAL::LARGER ? -1 : 0;
}

// Sign of d(q, x_l)^2 - d(q, x_i)^2 for q = bisector(i, j) ∩ segment [a, b] (§2.2 step
// 4), multiplied through by D = (b - a)·(x_j - x_i) so it is a polynomial:
//   q = a + (N'/2D)(b - a),  N' = (x_i + x_j - 2a)·(x_j - x_i),
//   D·(d_l^2 - d_i^2) = D(|x_l|^2 - |x_i|^2) - (2D a + N'(b - a))·(x_l - x_i).
// Returns (D, D·(d_l^2 - d_i^2)).
template <class FT>
std::pair<FT, FT> edge_bisector_terms(const Vec2& a, const Vec2& b, const Vec2& xi, const Vec2& xj, const Vec2& xl) {
  const FT ax(a.x()), ay(a.y()), bx(b.x()), by(b.y());
  const FT ix(xi.x()), iy(xi.y()), jx(xj.x()), jy(xj.y()), lx(xl.x()), ly(xl.y());
  const FT ex = bx - ax, ey = by - ay;
  const FT dx = jx - ix, dy = jy - iy;
  const FT big_d = ex * dx + ey * dy;
  const FT n = (ix + jx - ax - ax) * dx + (iy + jy - ay - ay) * dy;
  const FT value = big_d * (lx * lx + ly * ly - ix * ix - iy * iy) -
                   ((big_d * ax + big_d * ax + n * ex) * (lx - ix) + (big_d * ay + big_d * ay + n * ey) * (ly - iy));
  return {big_d, value};
}

int edge_bisector_sign(const Vec2& a, const Vec2& b, const Vec2& xi, const Vec2& xj, const Vec2& xl) {
  {
    const auto [big_d, value] = edge_bisector_terms<Bounded>(a, b, xi, xj, xl);
    const int sd = filtered_sign(big_d), sv = filtered_sign(value);
    if (sd != 0 && sv != 0) return sd * sv;
  }
  {
    CGAL::Protect_FPU_rounding<true> guard;
    try {
      const auto [big_d, value] = edge_bisector_terms<CGAL::Interval_nt<false>>(a, b, xi, xj, xl);
      return certain_sign(big_d) * certain_sign(value);
    } catch (const CGAL::Uncertain_conversion_exception&) {
      // The interval contains 0: fall through to exact arithmetic (rounding restored).
    }
  }
  const auto [big_d, value] = edge_bisector_terms<CGAL::Exact_rational>(a, b, xi, xj, xl);
  return certain_sign(big_d) * certain_sign(value);
}

}  // namespace

struct Engine::Data {
  const DomainMesh* domain = nullptr;
  std::vector<Vec2> sites;
  std::vector<Point> points;
  std::vector<Index> neighbor_offsets{0};
  std::vector<Index> neighbors;
  Index first_site = kInvalidIndex;  ///< a site present in the Delaunay triangulation

  std::span<const Index> neighbors_of(Index site) const {
    return {neighbors.data() + neighbor_offsets[site], neighbors.data() + neighbor_offsets[site + 1]};
  }

  // +1 when q is strictly closer to site c than to site l, 0 on the bisector, -1 when
  // closer to l. Only exact predicates, so every triangle/cell gets the same answer.
  int side(const VertexKey& q, Index c, Index l) const {
    switch (q.kind) {
      case VertexKey::TriVertex:
        return closer_sign(domain->points[q.a], sites[c], sites[l]);
      case VertexKey::EdgeBisector: {
        // q is equidistant from both of its sites, c among them.
        return edge_bisector_sign(domain->points[q.a], domain->points[q.b], sites[q.c], sites[q.d], sites[l]);
      }
      default: {
        // l is closer than the circumcentre's sites iff x_l is inside their circle.
        const CGAL::Orientation o = CGAL::orientation(points[q.a], points[q.b], points[q.c]);
        const CGAL::Oriented_side s = CGAL::side_of_oriented_circle(points[q.a], points[q.b], points[q.c], points[l]);
        return -static_cast<int>(o) * static_cast<int>(s);
      }
    }
  }

  Vec2 position(const VertexKey& key) const {
    switch (key.kind) {
      case VertexKey::TriVertex:
        return domain->points[key.a];
      case VertexKey::EdgeBisector: {
        const Vec2& a = domain->points[key.a];
        const Vec2& b = domain->points[key.b];
        const Vec2 d = sites[key.d] - sites[key.c];
        const Vec2 mid = 0.5 * (sites[key.c] + sites[key.d]);
        const double t = std::clamp((mid - a).dot(d) / (b - a).dot(d), 0.0, 1.0);
        return a + t * (b - a);
      }
      default: {
        const Vec2& o = sites[key.a];
        const Vec2 b = sites[key.b] - o, c = sites[key.c] - o;
        const double twice_cross = 2 * (b.x() * c.y() - b.y() * c.x());
        const double bb = b.squaredNorm(), cc = c.squaredNorm();
        return o + Vec2((c.y() * bb - b.y() * cc) / twice_cross, (b.x() * cc - c.x() * bb) / twice_cross);
      }
    }
  }

  // Greedy walk in the Delaunay graph to the owner of q (nearest site, ties to the
  // lower index): in a Delaunay graph a site with no closer neighbour is the nearest.
  Index owner(const Vec2& q, Index start) const {
    Index current = start;
    for (;;) {
      Index best = current;
      for (const Index j : neighbors_of(current)) {
        const int r = closer_sign(q, sites[j], sites[best]);
        if (r > 0 || (r == 0 && j < best)) best = j;
      }
      if (best == current) return current;
      current = best;
    }
  }
};

namespace {

struct Polygon {
  std::vector<VertexKey> keys;
  std::vector<EdgeTag> tags;
  std::vector<Vec2> positions;
  void clear() {
    keys.clear();
    tags.clear();
    positions.clear();
  }
  void push(const VertexKey& key, const EdgeTag& tag, const Vec2& position) {
    keys.push_back(key);
    tags.push_back(tag);
    positions.push_back(position);
  }
};

// The key of the point where bisector(c, l) crosses an edge of c's piece. An edge on
// both a CDT edge and a bisector gets the CDT name; restricted_voronoi renames such
// points (equidistant from three sites) canonically.
VertexKey intersection_key(const EdgeTag& crossed, Index c, Index l) {
  if (crossed.on_cdt_edge()) {
    return {VertexKey::EdgeBisector, std::min(crossed.cdt_a, crossed.cdt_b), std::max(crossed.cdt_a, crossed.cdt_b),
            std::min(c, l), std::max(c, l)};
  }
  std::array<Index, 3> s{c, crossed.neighbor, l};
  std::sort(s.begin(), s.end());
  return {VertexKey::Voronoi, s[0], s[1], s[2], 0};
}

}  // namespace

Engine::Engine(const DomainMesh& domain, std::span<const Vec2> sites) : data_(std::make_unique<Data>()) {
  Data& d = *data_;
  d.domain = &domain;
  d.sites.assign(sites.begin(), sites.end());
  const std::size_t n = sites.size();
  if (n == 0) throw InputError("restricted Voronoi diagram: no sites");
  d.points.reserve(n);
  std::vector<std::pair<Point, Index>> pairs;
  pairs.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!sites[i].allFinite()) throw Error("restricted Voronoi diagram: site " + std::to_string(i) + " is not finite");
    d.points.emplace_back(sites[i].x(), sites[i].y());
    pairs.emplace_back(d.points.back(), static_cast<Index>(i));
  }
  Delaunay dt;
  dt.insert(pairs.begin(), pairs.end());
  if (dt.number_of_vertices() < n) {
    // Duplicate sites: the tie rule gives the cell to the lowest index, so only that
    // one is inserted; the others stay without neighbours, are never reached and
    // get empty cells.
    std::stable_sort(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) {
      return x.first.x() != y.first.x() ? x.first.x() < y.first.x() : x.first.y() < y.first.y();
    });
    pairs.erase(
        std::unique(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) { return x.first == y.first; }),
        pairs.end());
    dt.clear();
    dt.insert(pairs.begin(), pairs.end());
  }
  std::vector<std::vector<Index>> lists(n);
  for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
    std::vector<Index>& list = lists[v->info()];
    if (d.first_site == kInvalidIndex || v->info() < d.first_site) d.first_site = v->info();
    auto circulator = dt.incident_vertices(v), done = circulator;
    if (circulator == nullptr) continue;
    do {
      if (!dt.is_infinite(circulator)) list.push_back(circulator->info());
    } while (++circulator != done);
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  d.neighbor_offsets.resize(n + 1);
  for (std::size_t i = 0; i < n; ++i) d.neighbor_offsets[i + 1] = d.neighbor_offsets[i] + lists[i].size();
  d.neighbors.reserve(d.neighbor_offsets[n]);
  for (const auto& list : lists) d.neighbors.insert(d.neighbors.end(), list.begin(), list.end());
}

Engine::~Engine() = default;

std::size_t Engine::block_count() const { return (data_->domain->triangles.size() + kBlockSize - 1) / kBlockSize; }

Vec2 Engine::position(const VertexKey& key) const { return data_->position(key); }

VertexKey Engine::canonical(const VertexKey& key) const {
  const Data& d = *data_;
  std::array<Index, 3> triple{key.a, key.b, key.c};
  if (key.kind == VertexKey::TriVertex) return key;
  if (key.kind == VertexKey::EdgeBisector) {
    // A third equidistant site is then a Delaunay neighbour of site c: the sites on
    // the empty circle around the point form a convex polygon of Delaunay edges.
    const Vec2& a = d.domain->points[key.a];
    const Vec2& b = d.domain->points[key.b];
    Index third = kInvalidIndex;
    for (const Index k : d.neighbors_of(key.c)) {
      if (k == key.d) continue;
      if (edge_bisector_sign(a, b, d.sites[key.c], d.sites[key.d], d.sites[k]) == 0) {
        third = k;
        break;
      }
    }
    if (third == kInvalidIndex) return key;
    triple = {key.c, key.d, third};
    std::sort(triple.begin(), triple.end());
  }
  // All sites on the circle through the triple, by growing along Delaunay edges.
  std::vector<Index> circle(triple.begin(), triple.end());
  const Point &p0 = d.points[triple[0]], &p1 = d.points[triple[1]], &p2 = d.points[triple[2]];
  for (std::size_t i = 0; i < circle.size(); ++i) {
    for (const Index k : d.neighbors_of(circle[i])) {
      if (std::find(circle.begin(), circle.end(), k) != circle.end()) continue;
      if (CGAL::side_of_oriented_circle(p0, p1, p2, d.points[k]) == CGAL::ON_ORIENTED_BOUNDARY) circle.push_back(k);
    }
  }
  std::partial_sort(circle.begin(), circle.begin() + 3, circle.end());
  return {VertexKey::Voronoi, circle[0], circle[1], circle[2], 0};
}

void Engine::for_each_piece(const std::function<void(std::size_t, const PieceView&)>& visit) const {
  const Data& d = *data_;
  const DomainMesh& domain = *d.domain;
  const std::size_t blocks = block_count();
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, blocks, 1),
      [&](const tbb::blocked_range<std::size_t>& range) {
        Polygon piece, clipped;
        std::vector<Index> stack, seen;
        std::vector<int> sides;
        for (std::size_t block = range.begin(); block != range.end(); ++block) {
          const std::size_t first = block * kBlockSize;
          const std::size_t last = std::min(first + kBlockSize, domain.triangles.size());
          Index start = d.first_site;
          for (std::size_t t = first; t < last; ++t) {
            const auto& tri = domain.triangles[t];
            // The cells meeting a triangle form an edge-connected subdivision of it
            // (triangle and cells are convex), so a flood fill across bisector edges
            // from the owner of one corner finds them all.
            start = d.owner(domain.points[tri[0]], start);
            stack.assign(1, start);
            seen.assign(1, start);
            bool found = false;
            while (!stack.empty()) {
              const Index c = stack.back();
              stack.pop_back();
              piece.clear();
              for (int k = 0; k < 3; ++k) {
                piece.push({VertexKey::TriVertex, tri[k], 0, 0, 0}, {tri[k], tri[(k + 1) % 3], kInvalidIndex},
                           domain.points[tri[k]]);
              }
              bool alive = true;
              const Vec2& xc = d.sites[c];
              // Largest squared distance from x_c to the piece (at a vertex: convex);
              // clipping only shrinks the piece, so it is recomputed after clips only.
              double reach = 0;
              for (const Vec2& q : piece.positions) reach = std::max(reach, (q - xc).squaredNorm());
              for (const Index l : d.neighbors_of(c)) {
                // Cheap rejection (1% margin, so never wrong): the bisector cannot
                // reach a piece within 0.99 of half the site distance of x_c.
                if (reach < 0.99 * 0.25 * (d.sites[l] - xc).squaredNorm()) continue;
                // Sutherland-Hodgman against the closed half-plane of c (§2.2 step 5).
                const std::size_t m = piece.keys.size();
                sides.resize(m);
                bool inside = false, outside = false;
                for (std::size_t k = 0; k < m; ++k) {
                  sides[k] = d.side(piece.keys[k], c, l);
                  inside = inside || sides[k] > 0;
                  outside = outside || sides[k] < 0;
                }
                // Nothing strictly inside: what is left lies on the bisector line.
                if (!inside) {
                  alive = false;
                  break;
                }
                // An edge with both ends on the bisector lies on it (a CDT edge along
                // the bisector): tag it, for the bisector term and the flood fill.
                for (std::size_t k = 0; k < m; ++k) {
                  if (sides[k] == 0 && sides[k + 1 == m ? 0 : k + 1] == 0) piece.tags[k].neighbor = l;
                }
                if (!outside) continue;
                clipped.clear();
                for (std::size_t k = 0; k < m; ++k) {
                  const std::size_t next = k + 1 == m ? 0 : k + 1;
                  const int sa = sides[k], sb = sides[next];
                  if (sa > 0) {
                    clipped.push(piece.keys[k], piece.tags[k], piece.positions[k]);
                  } else if (sa == 0) {
                    clipped.push(piece.keys[k], sb < 0 ? EdgeTag{kInvalidIndex, kInvalidIndex, l} : piece.tags[k],
                                 piece.positions[k]);
                  }
                  if ((sa > 0 && sb < 0) || (sa < 0 && sb > 0)) {
                    const VertexKey key = intersection_key(piece.tags[k], c, l);
                    clipped.push(key, sa > 0 ? EdgeTag{kInvalidIndex, kInvalidIndex, l} : piece.tags[k],
                                 d.position(key));
                  }
                }
                std::swap(piece, clipped);
                reach = 0;
                for (const Vec2& q : piece.positions) reach = std::max(reach, (q - xc).squaredNorm());
              }
              if (!alive) {
                // Only when the corner's owner touches the triangle in a point or a
                // segment (exact ties): keep searching through its neighbours.
                if (!found) {
                  for (const Index l : d.neighbors_of(c)) {
                    if (std::find(seen.begin(), seen.end(), l) == seen.end()) {
                      seen.push_back(l);
                      stack.push_back(l);
                    }
                  }
                }
                continue;
              }
              found = true;
              visit(block, PieceView{static_cast<Index>(t), c, piece.keys, piece.tags, piece.positions});
              for (const EdgeTag& tag : piece.tags) {
                if (tag.on_bisector() && std::find(seen.begin(), seen.end(), tag.neighbor) == seen.end()) {
                  seen.push_back(tag.neighbor);
                  stack.push_back(tag.neighbor);
                }
              }
            }
          }
        }
      },
      tbb::simple_partitioner());
}

}  // namespace rvd

Tessellation restricted_voronoi(const DomainMesh& domain, std::span<const Vec2> sites) {
  const rvd::Engine engine(domain, sites);
  struct Block {
    std::vector<rvd::VertexKey> keys;
    std::vector<std::uint8_t> on_boundary;  ///< per half-edge: on a region-boundary CDT edge
    std::vector<Index> sizes;
    std::vector<Index> cells;
  };
  std::vector<Block> blocks(engine.block_count());
  engine.for_each_piece([&](std::size_t block, const rvd::PieceView& piece) {
    Block& out = blocks[block];
    out.keys.insert(out.keys.end(), piece.keys.begin(), piece.keys.end());
    const auto& tri = domain.triangles[piece.triangle];
    for (const rvd::EdgeTag& tag : piece.tags) {
      bool boundary = false;
      for (int k = 0; k < 3 && tag.on_cdt_edge(); ++k) {
        boundary = boundary || (tri[k] == tag.cdt_a && domain.neighbors[piece.triangle][k] == kInvalidIndex);
      }
      out.on_boundary.push_back(boundary ? 1 : 0);
    }
    out.sizes.push_back(static_cast<Index>(piece.keys.size()));
    out.cells.push_back(piece.site);
  });
  // Where each block's faces and half-edges start in the output.
  std::vector<std::size_t> key_start(blocks.size() + 1, 0), face_start(blocks.size() + 1, 0);
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    key_start[b + 1] = key_start[b] + blocks[b].keys.size();
    face_start[b + 1] = face_start[b] + blocks[b].sizes.size();
  }

  // Global vertex ids by deduplicating keys (§2.2 step 3): sort (key, half-edge)
  // pairs, number the distinct keys in order. The pairs are totally ordered, so the
  // parallel sort gives the same result whatever the threads.
  const std::size_t half_edges = key_start.back();
  struct Entry {
    rvd::VertexKey key;
    Index half_edge;
    bool operator<(const Entry& other) const {
      return key != other.key ? key < other.key : half_edge < other.half_edge;
    }
  };
  std::vector<Entry> entries(half_edges);
  std::vector<std::uint8_t> on_boundary(half_edges);
  Tessellation tessellation;
  tessellation.cell_count = sites.size();
  tessellation.face_vertices.resize(half_edges);
  tessellation.face_offsets.resize(face_start.back() + 1);
  tessellation.face_cell.resize(face_start.back());
  tbb::parallel_for(std::size_t{0}, blocks.size(), [&](std::size_t b) {
    const Block& block = blocks[b];
    std::size_t h = key_start[b];
    for (std::size_t k = 0; k < block.keys.size(); ++k, ++h) {
      entries[h] = {block.keys[k], static_cast<Index>(h)};
      on_boundary[h] = block.on_boundary[k];
    }
    h = key_start[b];
    for (std::size_t f = 0; f < block.sizes.size(); ++f) {
      h += block.sizes[f];
      tessellation.face_offsets[face_start[b] + f + 1] = static_cast<Index>(h);
      tessellation.face_cell[face_start[b] + f] = block.cells[f];
    }
  });
  blocks.clear();
  tbb::parallel_sort(entries.begin(), entries.end());
  std::vector<rvd::VertexKey> unique;
  for (const Entry& entry : entries) {
    if (unique.empty() || unique.back() != entry.key) unique.push_back(entry.key);
    tessellation.face_vertices[entry.half_edge] = static_cast<Index>(unique.size() - 1);
  }
  entries = {};
  // One name per point under exact degeneracies (see Engine::canonical); without
  // them (the normal case, thanks to the jitter) every key is already canonical.
  std::vector<rvd::VertexKey> names(unique.size());
  tbb::parallel_for(std::size_t{0}, unique.size(), [&](std::size_t v) { names[v] = engine.canonical(unique[v]); });
  if (names != unique) {
    std::vector<rvd::VertexKey> renamed = names;
    tbb::parallel_sort(renamed.begin(), renamed.end());
    renamed.erase(std::unique(renamed.begin(), renamed.end()), renamed.end());
    std::vector<Index> vertex_of(unique.size());
    tbb::parallel_for(std::size_t{0}, unique.size(), [&](std::size_t v) {
      vertex_of[v] = static_cast<Index>(std::lower_bound(renamed.begin(), renamed.end(), names[v]) - renamed.begin());
    });
    for (Index& v : tessellation.face_vertices) v = vertex_of[v];
    names = std::move(renamed);
  }
  tessellation.vertices.resize(names.size());
  tessellation.input_vertex.assign(names.size(), -1);
  tbb::parallel_for(std::size_t{0}, names.size(), [&](std::size_t v) {
    tessellation.vertices[v] = engine.position(names[v]);
    if (names[v].kind == rvd::VertexKey::TriVertex && names[v].a < domain.input_point_count) {
      tessellation.input_vertex[v] = names[v].a;
    }
  });

  // Twins: half-edges sorted by their unordered vertex pair. Pieces on both sides of
  // a CDT edge or a bisector cut it at the same keyed points, so pairs match exactly.
  std::vector<std::pair<std::uint64_t, Index>> halves(half_edges);
  tbb::parallel_for(Index{0}, static_cast<Index>(tessellation.face_count()), [&](Index f) {
    for (Index h = tessellation.face_offsets[f]; h < tessellation.face_offsets[f + 1]; ++h) {
      const Index a = tessellation.face_vertices[h], b = tessellation.face_vertices[tessellation.next(h, f)];
      halves[h] = {(std::uint64_t{std::min(a, b)} << 32) | std::max(a, b), h};
    }
  });
  tbb::parallel_sort(halves.begin(), halves.end());
  tessellation.twin.assign(half_edges, kInvalidIndex);
  for (std::size_t i = 0; i < halves.size();) {
    std::size_t j = i + 1;
    while (j < halves.size() && halves[j].first == halves[i].first) ++j;
    if (j - i == 2) {
      tessellation.twin[halves[i].second] = halves[i + 1].second;
      tessellation.twin[halves[i + 1].second] = halves[i].second;
    } else if (j - i > 2 || !on_boundary[halves[i].second]) {
      // Cannot happen with consistent predicates and canonical names: a bug, or an
      // exact degeneracy that the naming rules miss.
      throw Error("restricted Voronoi diagram: not conforming (" + std::to_string(j - i) +
                  " pieces share an edge); perturb the sites slightly");
    }
    i = j;
  }
  tessellation.boundary_ring.assign(half_edges, -1);
  return tessellation;
}

}  // namespace structmesh::partition2d
