// The cell graph G (dual of the tessellation, design/partition2d.md §2.6), the corner
// structure behind the separator angle deviation (3.6)-(3.8) (design §1.4), and the
// connectivity repair of §2.7 (region growing).
//
// Everything is flat arrays indexed by 32-bit Index; the only super-linear steps are
// sorts (O(n log n)), so a 1M half-edge tessellation takes a fraction of a second.
#include "partition2d/partition_internal.hpp"

#include "structmesh/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

namespace structmesh::partition2d {

namespace {

constexpr double kHalfPi = 0.5 * std::numbers::pi;
constexpr double kTwoPi = 2 * std::numbers::pi;

// Union-find with path halving; union by smaller root id keeps it deterministic.
struct DisjointSets {
  std::vector<Index> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), Index{0}); }
  Index find(Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(Index a, Index b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    parent[a] = b;
  }
};

// One spoke before grouping by corner: it leaves `cluster` (root of the contracted
// vertex cluster) from vertex `from` towards vertex `to`.
struct SpokeRecord {
  Index cluster;
  Index from, to;
  Index left_node;  // node on the counter-clockwise side of the spoke, or kInvalidIndex
  bool boundary;    // lies on the region boundary (else: separates two nodes)
  double angle;
};

// Labels with "outside the region" as a label of its own (int32 labels cannot reach it).
constexpr std::int64_t kOutside = std::numeric_limits<std::int64_t>::min();

inline std::int64_t sector_label(const CellGraph::Spoke& spoke, std::span<const std::int32_t> node_label) {
  return spoke.left_node == kInvalidIndex ? kOutside : node_label[spoke.left_node];
}

void check_labels(const CellGraph& graph, std::span<const std::int32_t> node_label, std::size_t parts,
                  const char* where) {
  if (node_label.size() != graph.node_count()) {
    throw Error(std::string(where) + ": " + std::to_string(node_label.size()) + " labels for " +
                std::to_string(graph.node_count()) + " nodes");
  }
  for (const std::int32_t label : node_label) {
    if (label < 0 || static_cast<std::size_t>(label) >= parts) {
      throw Error(std::string(where) + ": label " + std::to_string(label) + " outside [0, " + std::to_string(parts) +
                  ")");
    }
  }
}

// Connected components of the parts: component id per node (numbered in order of
// their smallest node, so deterministic), plus each component's label and area.
struct Components {
  std::vector<Index> of_node;
  std::vector<std::int32_t> label;
  std::vector<double> area;
  std::vector<Index> first_node;
};

Components part_components(const CellGraph& graph, std::span<const std::int32_t> node_label) {
  const std::size_t n = graph.node_count();
  Components c;
  c.of_node.assign(n, kInvalidIndex);
  std::vector<Index> queue;
  queue.reserve(n);
  for (Index start = 0; start < n; ++start) {
    if (c.of_node[start] != kInvalidIndex) continue;
    const Index id = static_cast<Index>(c.label.size());
    const std::int32_t label = node_label[start];
    double area = 0;
    queue.clear();
    queue.push_back(start);
    c.of_node[start] = id;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const Index v = queue[q];
      area += graph.node_area[v];
      for (Index a = graph.adjacency_offsets[v]; a < graph.adjacency_offsets[v + 1]; ++a) {
        const Index w = graph.adjacency[a];
        if (c.of_node[w] == kInvalidIndex && node_label[w] == label) {
          c.of_node[w] = id;
          queue.push_back(w);
        }
      }
    }
    c.label.push_back(label);
    c.area.push_back(area);
    c.first_node.push_back(start);
  }
  return c;
}

}  // namespace

CellGraph build_cell_graph(const Tessellation& tessellation, double contraction_length) {
  const std::size_t face_count = tessellation.face_count();
  const std::size_t half_edge_count = tessellation.face_vertices.size();
  const std::size_t vertex_count = tessellation.vertices.size();
  if (tessellation.face_offsets.size() != face_count + 1 || tessellation.face_offsets.back() != half_edge_count ||
      tessellation.twin.size() != half_edge_count) {
    throw Error("build_cell_graph: inconsistent tessellation arrays");
  }
  const auto& fv = tessellation.face_vertices;
  const auto& twin = tessellation.twin;
  const auto& pos = tessellation.vertices;

  std::vector<Index> half_edge_face(half_edge_count);
  for (Index f = 0; f < face_count; ++f)
    std::fill(half_edge_face.begin() + tessellation.face_offsets[f],
              half_edge_face.begin() + tessellation.face_offsets[f + 1], f);
  const auto head = [&](Index h) { return fv[tessellation.next(h, half_edge_face[h])]; };

  // Nodes: faces of one cell joined across interior half-edges (§2.6), numbered in
  // order of their first face so a tessellation with one face per cell and no
  // splits has node = face.
  CellGraph graph;
  {
    DisjointSets faces(face_count);
    for (Index h = 0; h < half_edge_count; ++h) {
      const Index t = twin[h];
      if (t == kInvalidIndex || t < h) continue;
      const Index f = half_edge_face[h], g = half_edge_face[t];
      if (tessellation.face_cell[f] == tessellation.face_cell[g]) faces.unite(f, g);
    }
    const std::vector<double> areas = face_areas(tessellation);
    std::vector<Index> node_of_root(face_count, kInvalidIndex);
    graph.face_node.resize(face_count);
    for (Index f = 0; f < face_count; ++f) {
      Index& node = node_of_root[faces.find(f)];
      if (node == kInvalidIndex) {
        node = static_cast<Index>(graph.node_cell.size());
        graph.node_cell.push_back(tessellation.face_cell[f]);
        graph.node_area.push_back(0.0);
      }
      graph.face_node[f] = node;
      graph.node_area[node] += areas[f];
    }
  }
  const std::size_t node_count = graph.node_count();
  const auto node_of = [&](Index h) { return graph.face_node[half_edge_face[h]]; };

  // Arcs: one record per node-separating edge, sorted by (node pair, half-edge) so
  // the sums are deterministic; both directions get the very same double (METIS
  // needs a symmetric adjwgt).
  struct EdgeRecord {
    std::uint64_t pair;
    Index half_edge;
    double length;
  };
  std::vector<EdgeRecord> separating;
  for (Index h = 0; h < half_edge_count; ++h) {
    const Index t = twin[h];
    if (t == kInvalidIndex || t < h) continue;
    const Index a = node_of(h), b = node_of(t);
    if (a == b) continue;
    const std::uint64_t pair = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
    separating.push_back({pair, h, (pos[head(h)] - pos[fv[h]]).norm()});
  }
  std::sort(separating.begin(), separating.end(), [](const EdgeRecord& x, const EdgeRecord& y) {
    return x.pair != y.pair ? x.pair < y.pair : x.half_edge < y.half_edge;
  });
  double separating_length = 0;
  {
    struct Arc {
      Index low, high;
      double length;
    };
    std::vector<Arc> arcs;
    for (const EdgeRecord& e : separating) {
      separating_length += e.length;
      const Index low = static_cast<Index>(e.pair >> 32), high = static_cast<Index>(e.pair & 0xffffffffu);
      if (!arcs.empty() && arcs.back().low == low && arcs.back().high == high) {
        arcs.back().length += e.length;
      } else {
        arcs.push_back({low, high, e.length});
      }
    }
    // Counting sort into CSR. Arcs are sorted by (low, high), so node x first receives
    // its neighbours below x (in increasing order), then those above: rows come out sorted.
    std::vector<Index> degree(node_count + 1, 0);
    for (const Arc& arc : arcs) ++degree[arc.low], ++degree[arc.high];
    graph.adjacency_offsets.assign(node_count + 1, 0);
    for (std::size_t v = 0; v < node_count; ++v)
      graph.adjacency_offsets[v + 1] = graph.adjacency_offsets[v] + degree[v];
    graph.adjacency.resize(graph.adjacency_offsets.back());
    graph.arc_length.resize(graph.adjacency_offsets.back());
    std::vector<Index> fill(graph.adjacency_offsets.begin(), graph.adjacency_offsets.end() - 1);
    for (const Arc& arc : arcs) {
      graph.adjacency[fill[arc.low]] = arc.high;
      graph.arc_length[fill[arc.low]++] = arc.length;
      graph.adjacency[fill[arc.high]] = arc.low;
      graph.arc_length[fill[arc.high]++] = arc.length;
    }
  }

  // Corners (design §1.4). Contract node-separating edges shorter than the
  // contraction length: near co-circular sites Voronoi edges are tiny with arbitrary
  // directions, and the two vertices are one corner of the partition. The length
  // that counts is that of the whole straight *chain* the edge belongs to (pieces
  // joined at pass-through vertices, where a Voronoi edge crosses a CDT edge): the
  // pieces of a long edge near a finely sampled boundary are tiny, but contracting
  // them would glue real corners together along the edge.
  DisjointSets clusters(vertex_count);
  std::size_t contracted = 0;
  {
    constexpr Index kNone = kInvalidIndex;
    std::vector<std::array<Index, 2>> incident(vertex_count, {kNone, kNone});  // first two separating edges
    std::vector<std::uint8_t> degree(vertex_count, 0);  // separating edges, saturating at 3; 3 also marks boundary
    const auto touch = [&](Index v, Index e) {
      if (degree[v] < 2) incident[v][degree[v]] = e;
      if (degree[v] < 3) ++degree[v];
    };
    for (Index e = 0; e < separating.size(); ++e) {
      touch(fv[separating[e].half_edge], e);
      touch(head(separating[e].half_edge), e);
    }
    for (Index h = 0; h < half_edge_count; ++h) {
      if (twin[h] != kInvalidIndex) continue;
      degree[fv[h]] = 3;
      degree[head(h)] = 3;
    }
    DisjointSets chains(separating.size());
    for (Index v = 0; v < vertex_count; ++v) {
      if (degree[v] != 2) continue;
      const auto far_end = [&](Index e) {
        const Index h = separating[e].half_edge;
        return fv[h] == v ? head(h) : fv[h];
      };
      const Vec2 a = pos[far_end(incident[v][0])] - pos[v], b = pos[far_end(incident[v][1])] - pos[v];
      const double cross = a.x() * b.y() - a.y() * b.x();
      if (a.dot(b) < 0 && std::abs(cross) <= 1e-9 * a.norm() * b.norm()) chains.unite(incident[v][0], incident[v][1]);
    }
    std::vector<double> chain_length(separating.size(), 0.0);
    for (Index e = 0; e < separating.size(); ++e) chain_length[chains.find(e)] += separating[e].length;
    // Short chains, shortest first; a chain joins the clusters at its ends only while
    // the merged cluster stays within contraction_length across (bounding box
    // diagonal), so a run of short edges along a finely sampled boundary cannot grow
    // one cluster over many real corners.
    std::vector<std::pair<Index, Index>> short_edges;  // (chain, edge)
    for (Index e = 0; e < separating.size(); ++e) {
      const Index chain = chains.find(e);
      if (chain_length[chain] < contraction_length) short_edges.emplace_back(chain, e);
    }
    std::sort(short_edges.begin(), short_edges.end(), [&](const auto& x, const auto& y) {
      if (chain_length[x.first] != chain_length[y.first]) return chain_length[x.first] < chain_length[y.first];
      return x < y;
    });
    std::vector<Vec2> box_min(pos.begin(), pos.end()), box_max(pos.begin(), pos.end());  // per cluster root
    for (std::size_t begin = 0; begin < short_edges.size();) {
      std::size_t end = begin;
      while (end < short_edges.size() && short_edges[end].first == short_edges[begin].first) ++end;
      Vec2 lo = box_min[clusters.find(fv[separating[short_edges[begin].second].half_edge])], hi = lo;
      for (std::size_t i = begin; i < end; ++i) {
        const Index h = separating[short_edges[i].second].half_edge;
        for (const Index v : {fv[h], head(h)}) {
          const Index r = clusters.find(v);
          lo = lo.cwiseMin(box_min[r]);
          hi = hi.cwiseMax(box_max[r]);
        }
      }
      if ((hi - lo).norm() <= contraction_length) {
        for (std::size_t i = begin; i < end; ++i) {
          const Index h = separating[short_edges[i].second].half_edge;
          clusters.unite(fv[h], head(h));
          ++contracted;
        }
        const Index r = clusters.find(fv[separating[short_edges[begin].second].half_edge]);
        box_min[r] = lo;
        box_max[r] = hi;
      }
      begin = end;
    }
  }
  // Spokes: every node-separating and every region-boundary edge at its ends. The
  // half-edge from u to v has its face on the left, i.e. counter-clockwise after the
  // direction u -> v at u; a boundary edge has the outside on the left at v.
  // Directions are those of the edge leaving the cluster (measured on the primal
  // graph, not from the cluster's mean position, which would bend long edges).
  std::vector<SpokeRecord> records;
  const auto add_spoke = [&](Index from, Index to, Index left, bool boundary) {
    const Index cluster = clusters.find(from);
    if (cluster == clusters.find(to)) return;  // contracted, or closes a loop inside the cluster
    const Vec2 d = pos[to] - pos[from];
    records.push_back({cluster, from, to, left, boundary, std::atan2(d.y(), d.x())});
  };
  for (Index h = 0; h < half_edge_count; ++h) {
    const Index t = twin[h];
    const Index u = fv[h], v = head(h);
    if (t == kInvalidIndex) {
      add_spoke(u, v, node_of(h), true);
      add_spoke(v, u, kInvalidIndex, true);
    } else if (node_of(h) != node_of(t)) {
      add_spoke(u, v, node_of(h), false);  // the twin adds the spoke at v
    }
  }
  // Group by cluster (counting sort keeps it linear), then sort each group by angle.
  std::vector<Index> cluster_offsets(vertex_count + 1, 0);
  for (const SpokeRecord& r : records) ++cluster_offsets[r.cluster + 1];
  std::partial_sum(cluster_offsets.begin(), cluster_offsets.end(), cluster_offsets.begin());
  std::vector<SpokeRecord> grouped(records.size());
  {
    std::vector<Index> fill(cluster_offsets.begin(), cluster_offsets.end() - 1);
    for (const SpokeRecord& r : records) grouped[fill[r.cluster]++] = r;
  }
  records.clear();
  records.shrink_to_fit();
  // Mean positions of the clusters' vertices.
  std::vector<Vec2> cluster_sum(vertex_count, Vec2::Zero());
  std::vector<Index> cluster_size(vertex_count, 0);
  if (contracted > 0) {
    for (Index v = 0; v < vertex_count; ++v) {
      const Index root = clusters.find(v);
      cluster_sum[root] += pos[v];
      ++cluster_size[root];
    }
  }

  std::size_t pass_through = 0;
  for (Index c = 0; c < vertex_count; ++c) {
    const auto begin = grouped.begin() + cluster_offsets[c], end = grouped.begin() + cluster_offsets[c + 1];
    const auto count = end - begin;
    if (count < 2) continue;
    if (std::all_of(begin, end, [](const SpokeRecord& r) { return r.boundary; })) continue;  // plain boundary
    std::sort(begin, end, [](const SpokeRecord& x, const SpokeRecord& y) {
      if (x.angle != y.angle) return x.angle < y.angle;
      if (x.left_node != y.left_node) return x.left_node < y.left_node;
      return x.to < y.to;
    });
    if (count == 2 && !begin[0].boundary && !begin[1].boundary) {
      // A vertex splitting one straight separator (e.g. where a Voronoi edge crosses a
      // CDT edge) is not a vertex of the partition's primal graph: leaving it out
      // keeps N_C of (3.8) from counting the same edge twice.
      const Vec2 a = pos[begin[0].to] - pos[begin[0].from], b = pos[begin[1].to] - pos[begin[1].from];
      const double cross = a.x() * b.y() - a.y() * b.x();
      if (a.dot(b) < 0 && std::abs(cross) <= 1e-9 * a.norm() * b.norm()) {
        ++pass_through;
        continue;
      }
    }
    for (auto it = begin; it != end; ++it) graph.spokes.push_back({it->angle, it->left_node});
    graph.corner_offsets.push_back(static_cast<Index>(graph.spokes.size()));
    graph.corner_position.push_back(cluster_size[c] > 1 ? Vec2(cluster_sum[c] / cluster_size[c]) : pos[c]);
  }

  // node -> corners: corners are visited in increasing order, so each node's list is
  // sorted and a node seen in several sectors of one corner gives adjacent duplicates.
  const std::size_t corner_count = graph.corner_position.size();
  {
    std::vector<Index> offsets(node_count + 1, 0);
    for (const CellGraph::Spoke& s : graph.spokes)
      if (s.left_node != kInvalidIndex) ++offsets[s.left_node + 1];
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    std::vector<Index> corners(offsets.back());
    std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
    for (Index c = 0; c < corner_count; ++c)
      for (Index s = graph.corner_offsets[c]; s < graph.corner_offsets[c + 1]; ++s) {
        const Index node = graph.spokes[s].left_node;
        if (node != kInvalidIndex) corners[fill[node]++] = c;
      }
    graph.node_corner_offsets.assign(node_count + 1, 0);
    graph.node_corners.reserve(corners.size());
    for (std::size_t v = 0; v < node_count; ++v) {
      for (Index i = offsets[v]; i < offsets[v + 1]; ++i)
        if (i == offsets[v] || corners[i] != corners[i - 1]) graph.node_corners.push_back(corners[i]);
      graph.node_corner_offsets[v + 1] = static_cast<Index>(graph.node_corners.size());
    }
  }

  // lambda = beta * mean Voronoi edge length (design §1.9): an "edge" is a separator
  // piece between two vertices of the partition's primal graph, so pieces joined at a
  // pass-through vertex count once and contracted edges not at all.
  const std::size_t pieces = separating.size() - contracted;
  const std::size_t edges = pieces > pass_through ? pieces - pass_through : pieces;
  graph.mean_arc_length = edges > 0 ? separating_length / static_cast<double>(edges) : 0.0;
  return graph;
}

double angle_deviation(double theta) {
  // Eq. (3.6) read as the distance to the nearest multiple of pi/2 (design §1.4).
  double r = std::fmod(theta, kHalfPi);
  if (r < 0) r += kHalfPi;
  return std::min(r, kHalfPi - r);
}

CornerCost corner_cost_at(const CellGraph& graph, Index corner, std::span<const std::int32_t> node_label) {
  CornerCost cost;
  const Index begin = graph.corner_offsets[corner], end = graph.corner_offsets[corner + 1];
  const Index count = end - begin;
  const CellGraph::Spoke* spokes = graph.spokes.data() + begin;
  // Spoke s separates sector s - 1 (clockwise side) from sector s. Active = the two
  // labels differ; boundary spoke = one side outside.
  const auto previous = [count](Index s) { return s == 0 ? count - 1 : s - 1; };
  Index active = 0, first = kInvalidIndex;
  for (Index s = 0; s < count; ++s) {
    if (sector_label(spokes[previous(s)], node_label) != sector_label(spokes[s], node_label)) {
      if (first == kInvalidIndex) first = s;
      ++active;
    }
  }
  if (active < 2) return cost;
  const auto is_boundary = [&](Index s) {
    return spokes[s].left_node == kInvalidIndex || spokes[previous(s)].left_node == kInvalidIndex;
  };
  const auto add = [&](Index a, Index b) {
    const bool boundary_a = is_boundary(a), boundary_b = is_boundary(b);
    if (boundary_a && boundary_b) return;  // a bend of the region boundary: not ours
    double theta = spokes[b].angle - spokes[a].angle;
    if (theta < 0) theta += kTwoPi;
    const double delta = angle_deviation(theta);
    if (boundary_a || boundary_b) {
      cost.boundary_sum += delta;
      ++cost.boundary_corners;
    } else {
      cost.separator_sum += delta;
      ++cost.separator_corners;
    }
  };
  // Walk the active spokes counter-clockwise from the first; each consecutive pair
  // bounds one sector run of a single label (design §1.4: s >= 3 gives s corners).
  Index last = first;
  for (Index k = 1; k <= count; ++k) {
    const Index s = (first + k) % count;
    if (sector_label(spokes[previous(s)], node_label) == sector_label(spokes[s], node_label)) continue;
    if (active == 2 && s == first) break;  // s = 2: one corner, the angle between them (δ symmetric)
    add(last, s);
    last = s;
  }
  return cost;
}

CornerCost corner_cost(const CellGraph& graph, std::span<const std::int32_t> node_label) {
  if (node_label.size() != graph.node_count()) {
    throw Error("corner_cost: " + std::to_string(node_label.size()) + " labels for " +
                std::to_string(graph.node_count()) + " nodes");
  }
  CornerCost total;
  const Index corners = static_cast<Index>(graph.corner_position.size());
  for (Index c = 0; c < corners; ++c) total += corner_cost_at(graph, c, node_label);
  return total;
}

std::size_t max_components_per_part(const CellGraph& graph, std::span<const std::int32_t> node_label,
                                    std::size_t parts) {
  check_labels(graph, node_label, parts, "max_components_per_part");
  const Components components = part_components(graph, node_label);
  std::vector<std::size_t> per_part(parts, 0);
  for (const std::int32_t label : components.label) ++per_part[static_cast<std::size_t>(label)];
  return parts == 0 ? 0 : *std::max_element(per_part.begin(), per_part.end());
}

// Region growing (design §2.7). Each move takes a whole non-largest component C of
// part A to a part B adjacent to it; C was a maximal A-component, so A loses one
// component and B gains none (C touches B). To keep that argument exact while moving
// several components per round, a component next to a node already moved in this
// round waits for the next round (its components are recomputed). So the total
// number of components falls with every move and the loop ends. The largest
// component of a part never moves, so no non-empty part becomes empty; parts that
// are empty on entry stay empty (the caller's problem). A component with no
// neighbour of another label (a separate component of the graph itself) cannot be
// repaired and stays.
std::size_t repair_connectivity(const CellGraph& graph, std::span<std::int32_t> node_label, std::size_t parts) {
  check_labels(graph, node_label, parts, "repair_connectivity");
  const std::size_t n = graph.node_count();
  std::size_t moved = 0;
  std::vector<std::uint8_t> moved_now(n, 0);
  std::vector<double> shared(parts, 0.0);
  std::vector<std::uint8_t> is_touched(parts, 0);
  std::vector<std::int32_t> touched;
  std::vector<Index> order(n);
  for (;;) {
    const Components c = part_components(graph, node_label);
    const std::size_t component_count = c.label.size();
    // The largest component of each part (ties: the one with the smaller first node).
    std::vector<Index> keep(parts, kInvalidIndex);
    for (Index id = 0; id < component_count; ++id) {
      Index& best = keep[static_cast<std::size_t>(c.label[id])];
      if (best == kInvalidIndex || c.area[id] > c.area[best]) best = id;
    }
    // Nodes grouped by component (counting sort; components in id order).
    std::vector<Index> offsets(component_count + 1, 0);
    for (Index v = 0; v < n; ++v) ++offsets[c.of_node[v] + 1];
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    {
      std::vector<Index> fill(offsets.begin(), offsets.end() - 1);
      for (Index v = 0; v < n; ++v) order[fill[c.of_node[v]]++] = v;
    }
    std::fill(moved_now.begin(), moved_now.end(), 0);
    std::size_t moves = 0;
    for (Index id = 0; id < component_count; ++id) {
      if (keep[static_cast<std::size_t>(c.label[id])] == id) continue;
      bool wait = false;
      touched.clear();
      for (Index i = offsets[id]; i < offsets[id + 1] && !wait; ++i) {
        const Index v = order[i];
        for (Index a = graph.adjacency_offsets[v]; a < graph.adjacency_offsets[v + 1]; ++a) {
          const Index w = graph.adjacency[a];
          if (moved_now[w]) {
            wait = true;
            break;
          }
          const std::int32_t label = node_label[w];
          if (label == c.label[id]) continue;
          if (!is_touched[static_cast<std::size_t>(label)]) {
            is_touched[static_cast<std::size_t>(label)] = 1;
            touched.push_back(label);
          }
          shared[static_cast<std::size_t>(label)] += graph.arc_length[a];
        }
      }
      std::int32_t target = -1;
      for (const std::int32_t label : touched) {
        const double s = shared[static_cast<std::size_t>(label)];
        if (target < 0 || s > shared[static_cast<std::size_t>(target)] ||
            (s == shared[static_cast<std::size_t>(target)] && label < target))
          target = label;
      }
      for (const std::int32_t label : touched) {
        shared[static_cast<std::size_t>(label)] = 0.0;
        is_touched[static_cast<std::size_t>(label)] = 0;
      }
      if (wait) continue;        // next round, with recomputed components
      if (target < 0) continue;  // isolated in the graph: nothing to join
      for (Index i = offsets[id]; i < offsets[id + 1]; ++i) {
        node_label[order[i]] = target;
        moved_now[order[i]] = 1;
      }
      moved += offsets[id + 1] - offsets[id];
      ++moves;
    }
    if (moves == 0) break;  // a waiting component implies a move before it
  }
  return moved;
}

}  // namespace structmesh::partition2d
