// The adjacency builders against a brute-force reference (sort every edge/face use
// globally) on random meshes with shared, repeated and collapsed vertices, and for
// several thread counts: the output must be identical, entry by entry.
#include "structmesh/error.hpp"
#include "structmesh/mesh.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <random>
#include <tuple>

namespace structmesh {
namespace {

template <std::size_t N>
std::vector<std::array<Index, N>> random_elements(std::size_t count, Index vertices, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<Index> pick(0, vertices - 1);
  std::vector<std::array<Index, N>> out(count);
  for (auto& e : out)
    for (Index& v : e) v = pick(rng);  // small vertex range: many repeats and shared faces
  return out;
}

template <std::size_t N, std::size_t E>
EdgeAdjacency reference_edges(const std::vector<std::array<Index, N>>& elements,
                              const std::array<std::array<int, 2>, E>& table) {
  std::vector<std::tuple<Index, Index, Index>> uses;
  for (std::size_t c = 0; c < elements.size(); ++c)
    for (const auto& [i, j] : table) {
      const Index a = elements[c][i], b = elements[c][j];
      if (a != b) uses.emplace_back(std::min(a, b), std::max(a, b), static_cast<Index>(c));
    }
  std::sort(uses.begin(), uses.end());
  uses.erase(std::unique(uses.begin(), uses.end()), uses.end());
  EdgeAdjacency out;
  for (std::size_t k = 0; k < uses.size(); ++k) {
    const auto [a, b, c] = uses[k];
    if (k == 0 || std::get<0>(uses[k - 1]) != a || std::get<1>(uses[k - 1]) != b) {
      if (k != 0) out.edge_elements.offsets.push_back(static_cast<Index>(out.edge_elements.items.size()));
      out.edges.push_back({a, b});
    }
    out.edge_elements.items.push_back(c);
  }
  if (!uses.empty()) out.edge_elements.offsets.push_back(static_cast<Index>(out.edge_elements.items.size()));
  return out;
}

template <std::size_t N, std::size_t F, std::size_t K>
FaceAdjacency<N> reference_faces(const std::vector<std::array<Index, K>>& cells,
                                 const std::array<std::array<int, N>, F>& table) {
  std::vector<std::tuple<std::array<Index, N>, Index, int>> uses;
  for (std::size_t c = 0; c < cells.size(); ++c)
    for (std::size_t f = 0; f < F; ++f) {
      std::array<Index, N> key;
      for (std::size_t i = 0; i < N; ++i) key[i] = cells[c][table[f][i]];
      std::sort(key.begin(), key.end());
      uses.emplace_back(key, static_cast<Index>(c), static_cast<int>(f));
    }
  std::sort(uses.begin(), uses.end());
  FaceAdjacency<N> out;
  for (std::size_t k = 0; k < uses.size();) {
    std::size_t end = k + 1;
    while (end < uses.size() && std::get<0>(uses[end]) == std::get<0>(uses[k])) ++end;
    std::array<Index, N> oriented;
    for (std::size_t i = 0; i < N; ++i) oriented[i] = cells[std::get<1>(uses[k])][table[std::get<2>(uses[k])][i]];
    const Index face = static_cast<Index>(out.faces.size());
    out.faces.push_back(oriented);
    out.face_cells.push_back({std::get<1>(uses[k]), end > k + 1 ? std::get<1>(uses[k + 1]) : kInvalidIndex});
    for (std::size_t x = k + 2; x < end; ++x) {
      out.extra_cells.push_back(std::get<1>(uses[x]));
      out.extra_faces.push_back(face);
    }
    k = end;
  }
  return out;
}

void expect_same(const EdgeAdjacency& a, const EdgeAdjacency& b) {
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.edge_elements.offsets, b.edge_elements.offsets);
  EXPECT_EQ(a.edge_elements.items, b.edge_elements.items);
}

template <std::size_t N>
void expect_same(const FaceAdjacency<N>& a, const FaceAdjacency<N>& b) {
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.face_cells, b.face_cells);
  EXPECT_EQ(a.extra_cells, b.extra_cells);
  EXPECT_EQ(a.extra_faces, b.extra_faces);
}

class AdjacencyOracle : public testing::TestWithParam<int> {};

TEST_P(AdjacencyOracle, EdgesAndFacesMatchTheGlobalSort) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, GetParam());
  constexpr std::array<std::array<int, 2>, 3> kTriangleEdges{{{0, 1}, {1, 2}, {2, 0}}};
  constexpr std::array<std::array<int, 2>, 4> kQuadEdges{{{0, 1}, {1, 2}, {2, 3}, {3, 0}}};
  for (unsigned seed = 1; seed <= 4; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    // 3000 vertices keeps rows long enough to cross TBB chunk borders; 12 vertices
    // forces faces shared by many cells.
    for (Index vertices : {Index{12}, Index{3000}}) {
      TriMesh tri;
      tri.points.resize(vertices);
      tri.triangles = random_elements<3>(4000, vertices, seed);
      expect_same(build_edges(tri), reference_edges(tri.triangles, kTriangleEdges));
      QuadMesh quad;
      quad.points.resize(vertices);
      quad.quads = random_elements<4>(3000, vertices, seed + 10);
      expect_same(build_edges(quad), reference_edges(quad.quads, kQuadEdges));
      TetMesh tet;
      tet.points.resize(vertices);
      tet.tets = random_elements<4>(3000, vertices, seed + 20);
      expect_same(build_edges(tet), reference_edges(tet.tets, kTetEdges));
      expect_same(build_faces(tet), reference_faces(tet.tets, kTetFaces));
      HexMesh hex;
      hex.points.resize(vertices);
      hex.hexes = random_elements<8>(1500, vertices, seed + 30);
      expect_same(build_edges(hex), reference_edges(hex.hexes, kHexEdges));
      expect_same(build_faces(hex), reference_faces(hex.hexes, kHexFaces));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Threads, AdjacencyOracle, testing::Values(1, 2, 4));

TEST(Adjacency, IndicesPastThePointsAreStillCovered) {
  // Adjacency may be built before validation: an element naming a vertex past the
  // point array must neither crash nor be dropped.
  TriMesh mesh;
  mesh.points.resize(3);
  mesh.triangles = {{0, 1, 2}, {1, 7, 2}};
  const EdgeAdjacency edges = build_edges(mesh);
  ASSERT_EQ(edges.edges.size(), 5u);
  EXPECT_EQ(edges.edges.back(), (std::array<Index, 2>{2, 7}));
}

TEST(BoundarySurface, TwoTetsSharingAFaceGiveSixOutwardTriangles) {
  TetMesh mesh;
  // Point 2 is unused; the two tets share face {0, 1, 3}.
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {9, 9, 9}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
  mesh.tets = {{0, 1, 3, 4}, {0, 3, 1, 5}};
  std::vector<Index> point_of;
  const TriMesh surface = boundary_surface(mesh, &point_of);
  EXPECT_EQ(point_of, (std::vector<Index>{0, 1, 3, 4, 5}));
  ASSERT_EQ(surface.points.size(), 5u);
  ASSERT_EQ(surface.triangles.size(), 6u);
  // Outward: the divergence theorem gives the enclosed volume, 2 * 1/6.
  double volume = 0;
  for (const auto& t : surface.triangles)
    volume += surface.points[t[0]].dot(surface.points[t[1]].cross(surface.points[t[2]])) / 6.0;
  EXPECT_NEAR(volume, 1.0 / 3.0, 1e-12);
  // The shared face {0, 1, 3} (surface points 0, 1, 2) is not on the boundary.
  for (auto t : surface.triangles) {
    std::sort(t.begin(), t.end());
    EXPECT_NE(t, (std::array<Index, 3>{0, 1, 2}));
  }
  mesh.tets.push_back({0, 1, 3, 17});
  EXPECT_THROW(boundary_surface(mesh), InputError);
}

}  // namespace
}  // namespace structmesh
