// split_boundary_tets(): the preprocessing of §5.2.2 ("each boundary tetrahedron only has
// one boundary face ... by splitting each tetrahedron that has two or more"), taken one step
// further: every edge between two surface points that is not itself a surface edge is split.
//
// Such an edge is a straight segment whose two ends the map pins to the polycube. Where the
// target is concave between them (the pseudo-polycube flattens a sharp ridge of S, or the
// projection onto P bends the surface around an edge of P), the segment's image leaves the
// solid and the tets around it invert, whatever the map does with its interior points. The
// dissertation's case is the tet with four surface points (both faces of a ridge): splitting
// it at its centroid does not help (the pieces' volumes add up to the inverted whole). Split
// at its midpoint, in every tet around it, the edge becomes two edges with a point the map can
// move. Splitting only the edges of tets with four surface points left the map onto P with
// tets it could not unfold (fertility: 45 after untangling; with every such edge split and
// the surface relaxed, 8).
//
// Every tet around an edge is split in two by replacing one end of the edge by the
// midpoint, which keeps the orientation. A tet holding several chosen edges is split edge
// after edge in one global order, so a face shared by two tets is cut the same way in both
// and the mesh stays conforming.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"

#include <algorithm>
#include <iterator>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace structmesh {
namespace {

std::uint64_t edge_key(Index a, Index b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

struct ChosenEdge {
  std::size_t order;
  Index midpoint;
};

/// Splits `tet` along the chosen edges it holds (lowest order first) into `out`.
void split_piece(const std::array<Index, 4>& tet, const std::unordered_map<std::uint64_t, ChosenEdge>& chosen,
                 std::vector<std::array<Index, 4>>& out) {
  int best_i = -1, best_j = -1;
  const ChosenEdge* best = nullptr;
  for (const auto& e : kTetEdges) {
    const auto it = chosen.find(edge_key(tet[e[0]], tet[e[1]]));
    if (it != chosen.end() && (!best || it->second.order < best->order)) {
      best = &it->second;
      best_i = e[0];
      best_j = e[1];
    }
  }
  if (!best) {
    out.push_back(tet);
    return;
  }
  std::array<Index, 4> first = tet, second = tet;
  first[static_cast<std::size_t>(best_j)] = best->midpoint;
  second[static_cast<std::size_t>(best_i)] = best->midpoint;
  split_piece(first, chosen, out);
  split_piece(second, chosen, out);
}

}  // namespace

std::size_t split_boundary_tets(TetMesh& tets, std::size_t boundary_points) {
  if (boundary_points > tets.points.size())
    throw InputError("split_boundary_tets: " + std::to_string(boundary_points) + " boundary points of " +
                     std::to_string(tets.points.size()));
  // Edges of the surface (of the tets' boundary faces) are never split: they are S's.
  const FaceAdjacency<3> faces = build_faces(tets);
  std::unordered_set<std::uint64_t> surface_edges;
  for (std::size_t f = 0; f < faces.faces.size(); ++f)
    if (faces.face_cells[f][1] == kInvalidIndex)
      for (int k = 0; k < 3; ++k) surface_edges.insert(edge_key(faces.faces[f][k], faces.faces[f][(k + 1) % 3]));

  std::unordered_map<std::uint64_t, ChosenEdge> chosen;
  std::vector<std::array<Index, 2>> chosen_list;
  for (const auto& tet : tets.tets)
    for (const auto& e : kTetEdges) {
      const Index a = tet[e[0]], b = tet[e[1]];
      if (a >= boundary_points || b >= boundary_points || surface_edges.count(edge_key(a, b)) ||
          chosen.count(edge_key(a, b)))
        continue;
      if (tets.points.size() >= kInvalidIndex) throw InputError("split_boundary_tets: more than 2^32 - 1 points");
      const auto midpoint = static_cast<Index>(tets.points.size());
      tets.points.push_back((tets.points[a] + tets.points[b]) / 2);
      chosen.emplace(edge_key(a, b), ChosenEdge{chosen_list.size(), midpoint});
      chosen_list.push_back({a, b});
    }
  if (chosen.empty()) return 0;

  // The tets around the chosen edges: those holding both ends.
  const CompressedRows point_tets = build_vertex_elements(tets.tets, tets.points.size());
  std::vector<Index> affected;
  for (const auto& [a, b] : chosen_list) {
    const auto ta = point_tets.row(a), tb = point_tets.row(b);
    std::set_intersection(ta.begin(), ta.end(), tb.begin(), tb.end(), std::back_inserter(affected));
  }
  std::sort(affected.begin(), affected.end());
  affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
  std::vector<std::array<Index, 4>> pieces;
  for (const Index t : affected) {
    pieces.clear();
    split_piece(tets.tets[t], chosen, pieces);
    tets.tets[t] = pieces[0];
    tets.tets.insert(tets.tets.end(), pieces.begin() + 1, pieces.end());
  }
  return chosen.size();
}

}  // namespace structmesh
