// Voxel sets of the polycube construction (§4.4, §4.5.1): topology, simple points,
// well-composedness, the boundary surface, homotopic morphology and energy (4.1).
#include "polycube/voxel_window.hpp"
#include "structmesh/error.hpp"
#include "structmesh/polycube.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

using namespace structmesh;

namespace {

using Triple = std::array<int, 3>;

VoxelGrid make_grid(int nx, int ny, int nz) { return VoxelGrid({nx, ny, nz}, Vec3(0.5, -1.0, 2.0), 0.25); }

void fill(VoxelGrid& grid, Triple lo, Triple hi, bool value = true) {
  for (int z = lo[2]; z < hi[2]; ++z)
    for (int y = lo[1]; y < hi[1]; ++y)
      for (int x = lo[0]; x < hi[0]; ++x) grid.set(x, y, z, value);
}

VoxelBox whole(const VoxelGrid& grid) { return VoxelBox{{0, 0, 0}, grid.dims}; }

std::array<std::int64_t, 3> betti(const VoxelTopology& t) { return {t.components, t.handles, t.voids}; }
/// Euler characteristic and Betti numbers (the cell counts change with the shape).
std::array<std::int64_t, 4> invariants(const VoxelGrid& grid) {
  const VoxelTopology t = voxel_topology(grid);
  return {t.euler, t.components, t.handles, t.voids};
}

/// 6-components of the empty voxels, the outside (an empty layer around the grid)
/// included: a plain breadth-first search, independent of voxel_topology().
int empty_components(const VoxelGrid& grid) {
  const int nx = grid.dims[0] + 2, ny = grid.dims[1] + 2, nz = grid.dims[2] + 2;
  std::vector<char> seen(static_cast<std::size_t>(nx) * ny * nz, 0);
  const auto id = [&](int x, int y, int z) { return x + nx * (y + ny * z); };
  const auto empty = [&](int x, int y, int z) { return !grid.at(x - 1, y - 1, z - 1); };
  int components = 0;
  std::vector<Triple> queue;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        if (seen[id(x, y, z)] || !empty(x, y, z)) continue;
        ++components;
        seen[id(x, y, z)] = 1;
        queue.assign(1, {x, y, z});
        while (!queue.empty()) {
          const Triple c = queue.back();
          queue.pop_back();
          for (int d = 0; d < 6; ++d) {
            Triple n = c;
            n[d / 2] += d % 2 ? 1 : -1;
            if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= nx || n[1] >= ny || n[2] >= nz) continue;
            if (seen[id(n[0], n[1], n[2])] || !empty(n[0], n[1], n[2])) continue;
            seen[id(n[0], n[1], n[2])] = 1;
            queue.push_back(n);
          }
        }
      }
  return components;
}

/// Critical configurations found by looking at every 2x2 square around a grid edge and
/// every 2x2x2 block around a grid vertex, written out without tables.
bool naive_well_composed(const VoxelGrid& grid) {
  for (int z = -1; z < grid.dims[2]; ++z)
    for (int y = -1; y < grid.dims[1]; ++y)
      for (int x = -1; x < grid.dims[0]; ++x) {
        bool v[2][2][2];
        int count = 0;
        for (int c = 0; c < 8; ++c) {
          v[c & 1][(c >> 1) & 1][c >> 2] = grid.at(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2));
          count += v[c & 1][(c >> 1) & 1][c >> 2];
        }
        // Squares: fix one coordinate of the block.
        for (int s = 0; s < 2; ++s) {
          const auto diagonal = [](bool a, bool b, bool c, bool d) { return a == d && b == c && a != b; };
          if (diagonal(v[s][0][0], v[s][1][0], v[s][0][1], v[s][1][1])) return false;
          if (diagonal(v[0][s][0], v[1][s][0], v[0][s][1], v[1][s][1])) return false;
          if (diagonal(v[0][0][s], v[1][0][s], v[0][1][s], v[1][1][s])) return false;
        }
        if (count == 2 || count == 6)
          for (int c = 0; c < 8; ++c) {
            const bool a = v[c & 1][(c >> 1) & 1][c >> 2], b = v[1 - (c & 1)][1 - ((c >> 1) & 1)][1 - (c >> 2)];
            if (a == b && a == (count == 2)) return false;
          }
      }
  return true;
}

/// Removes voxels that sit in critical configurations until there are none.
void remove_critical_voxels(VoxelGrid& grid) {
  while (!is_well_composed(grid))
    for (int z = 0; z < grid.dims[2]; ++z)
      for (int y = 0; y < grid.dims[1]; ++y)
        for (int x = 0; x < grid.dims[0]; ++x)
          if (grid.at(x, y, z) && !is_well_composed_near(grid, x, y, z)) grid.set(x, y, z, false);
}

/// Thresholded sum of Gaussian bumps: a smooth random blob inside a margin of 2.
VoxelGrid noise_blob(Triple dims, unsigned seed, int bumps, double threshold) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), weight(0.6, 1.0);
  std::vector<std::pair<Vec3, double>> centres;
  for (int b = 0; b < bumps; ++b) {
    Vec3 centre;
    for (int a = 0; a < 3; ++a) centre[a] = 4.0 + unit(rng) * (dims[a] - 8.0);
    centres.push_back({centre, weight(rng)});
  }
  const double sigma = std::min({dims[0], dims[1], dims[2]}) / 8.0;
  VoxelGrid grid = make_grid(dims[0], dims[1], dims[2]);
  for (int z = 2; z < dims[2] - 2; ++z)
    for (int y = 2; y < dims[1] - 2; ++y)
      for (int x = 2; x < dims[0] - 2; ++x) {
        const Vec3 p(x + 0.5, y + 0.5, z + 0.5);
        double value = 0;
        for (const auto& [c, w] : centres) value += w * std::exp(-(p - c).squaredNorm() / (2 * sigma * sigma));
        grid.set(x, y, z, value > threshold);
      }
  remove_critical_voxels(grid);
  return grid;
}
VoxelGrid noise_blob(int n, unsigned seed, int bumps, double threshold) {
  return noise_blob({n, n, n}, seed, bumps, threshold);
}

/// A solid torus around the z axis through the grid's centre.
VoxelGrid torus(int n, double major, double minor) {
  VoxelGrid grid = make_grid(n, n, n);
  const double c = n / 2.0;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double px = x + 0.5 - c, py = y + 0.5 - c, pz = z + 0.5 - c;
        const double ring = std::hypot(px, py) - major;
        grid.set(x, y, z, ring * ring + pz * pz < minor * minor);
      }
  return grid;
}

/// A plate with three square through-holes: genus 3.
VoxelGrid genus_three_plate() {
  VoxelGrid grid = make_grid(26, 12, 8);
  fill(grid, {2, 2, 2}, {24, 10, 6});
  for (int hole = 0; hole < 3; ++hole) fill(grid, {5 + 6 * hole, 4, 2}, {8 + 6 * hole, 8, 6}, false);
  return grid;
}

}  // namespace

// ---------------------------------------------------------------------------
// voxel_topology

TEST(VoxelTopology, SingleVoxelIsOneCube) {
  VoxelGrid grid = make_grid(3, 3, 3);
  grid.set(1, 1, 1, true);
  const VoxelTopology t = voxel_topology(grid);
  EXPECT_EQ(t.vertices, 8);
  EXPECT_EQ(t.edges, 12);
  EXPECT_EQ(t.squares, 6);
  EXPECT_EQ(t.cubes, 1);
  EXPECT_EQ(t.euler, 1);
  EXPECT_EQ(betti(t), (std::array<std::int64_t, 3>{1, 0, 0}));
  EXPECT_EQ(grid.count(), 1u);
}

TEST(VoxelTopology, VoxelAtTheGridCorner) {
  VoxelGrid grid = make_grid(1, 1, 1);
  grid.set(0, 0, 0, true);
  EXPECT_EQ(betti(voxel_topology(grid)), (std::array<std::int64_t, 3>{1, 0, 0}));
  EXPECT_EQ(voxel_topology(grid).euler, 1);
}

TEST(VoxelTopology, EmptyGrid) {
  const VoxelTopology t = voxel_topology(make_grid(4, 3, 2));
  EXPECT_EQ(t, VoxelTopology{});
}

TEST(VoxelTopology, SolidBoxCountsItsCells) {
  VoxelGrid grid = make_grid(7, 8, 9);
  fill(grid, {1, 2, 3}, {4, 6, 8});  // 3 x 4 x 5
  const VoxelTopology t = voxel_topology(grid);
  EXPECT_EQ(t.vertices, 4 * 5 * 6);
  EXPECT_EQ(t.edges, 3 * 5 * 6 + 4 * 4 * 6 + 5 * 4 * 5);
  EXPECT_EQ(t.squares, 3 * 4 * 6 + 3 * 5 * 5 + 4 * 5 * 4);
  EXPECT_EQ(t.cubes, 60);
  EXPECT_EQ(t.euler, 1);
  EXPECT_EQ(betti(t), (std::array<std::int64_t, 3>{1, 0, 0}));
}

TEST(VoxelTopology, HollowBoxHasOneVoid) {
  VoxelGrid grid = make_grid(7, 7, 7);
  fill(grid, {1, 1, 1}, {6, 6, 6});
  fill(grid, {2, 2, 2}, {5, 5, 5}, false);
  const VoxelTopology t = voxel_topology(grid);
  EXPECT_EQ(t.euler, 2);
  EXPECT_EQ(betti(t), (std::array<std::int64_t, 3>{1, 0, 1}));
  // A cavity that reaches the grid's edge is open to the outside: no void.
  VoxelGrid full = make_grid(3, 3, 3);
  fill(full, {0, 0, 0}, {3, 3, 3});
  full.set(0, 1, 1, false);
  EXPECT_EQ(voxel_topology(full).voids, 0);
  full.set(0, 1, 1, true);
  full.set(1, 1, 1, false);
  EXPECT_EQ(voxel_topology(full).voids, 1);
}

TEST(VoxelTopology, RingHasOneHandle) {
  VoxelGrid grid = make_grid(5, 5, 3);
  fill(grid, {1, 1, 1}, {4, 4, 2});
  grid.set(2, 2, 1, false);
  const VoxelTopology t = voxel_topology(grid);
  EXPECT_EQ(t.euler, 0);
  EXPECT_EQ(betti(t), (std::array<std::int64_t, 3>{1, 1, 0}));
  const VoxelTopology solid_torus = voxel_topology(torus(20, 5.5, 2.5));
  EXPECT_EQ(betti(solid_torus), (std::array<std::int64_t, 3>{1, 1, 0}));
}

TEST(VoxelTopology, PlateWithThreeHolesHasGenusThree) {
  const VoxelTopology t = voxel_topology(genus_three_plate());
  EXPECT_EQ(t.euler, -2);
  EXPECT_EQ(betti(t), (std::array<std::int64_t, 3>{1, 3, 0}));
}

TEST(VoxelTopology, VoxelsTouchingAtAVertexOrEdgeAreOneComponent) {
  VoxelGrid grid = make_grid(4, 4, 4);
  grid.set(1, 1, 1, true);
  grid.set(2, 2, 2, true);  // shares the vertex (2, 2, 2) only
  VoxelTopology t = voxel_topology(grid);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.euler, 1);  // two cubes glued at a point
  EXPECT_EQ(t.handles, 0);
  grid.set(2, 2, 2, false);
  grid.set(2, 2, 1, true);  // shares an edge
  t = voxel_topology(grid);
  EXPECT_EQ(betti(t), (std::array<std::int64_t, 3>{1, 0, 0}));
  grid.set(2, 2, 1, false);
  grid.set(3, 3, 3, true);  // apart
  t = voxel_topology(grid);
  EXPECT_EQ(betti(t), (std::array<std::int64_t, 3>{2, 0, 0}));
}

TEST(VoxelTopology, FourVoxelsAroundAnEdgeRingLeaveAHandle) {
  // Four voxels meeting pairwise at edges around an empty centre column close a loop.
  VoxelGrid grid = make_grid(3, 3, 1);
  grid.set(1, 0, 0, true);
  grid.set(0, 1, 0, true);
  grid.set(2, 1, 0, true);
  grid.set(1, 2, 0, true);
  EXPECT_EQ(betti(voxel_topology(grid)), (std::array<std::int64_t, 3>{1, 1, 0}));
}

// ---------------------------------------------------------------------------
// is_simple_voxel

TEST(SimpleVoxel, MatchesBettiNumbersOfSetAndComplementOnRandomNeighbourhoods) {
  // A voxel is simple exactly when flipping it keeps the Betti numbers of the set and
  // the number of components of the complement (the complement's other Betti numbers
  // follow by Alexander duality: b1 is the set's b1, b2 its b0). On a 3x3x3
  // neighbourhood this holds for all 2^26 configurations (checked once, exhaustively,
  // with the same Betti numbers; too slow for a unit test), so no corner case is
  // excluded here.
  std::mt19937 rng(7);
  int simple = 0, not_simple = 0;
  for (const double density : {0.15, 0.3, 0.45, 0.55, 0.7, 0.85}) {
    std::bernoulli_distribution occupied(density);
    for (int trial = 0; trial < 3000; ++trial) {
      VoxelGrid grid = make_grid(3, 3, 3);
      for (int i = 0; i < 27; ++i) grid.set(i % 3, (i / 3) % 3, i / 9, occupied(rng));
      grid.set(1, 1, 1, true);
      const VoxelTopology with = voxel_topology(grid);
      const int outside_with = empty_components(grid);
      const bool answer_with = is_simple_voxel(grid, 1, 1, 1);
      grid.set(1, 1, 1, false);
      const VoxelTopology without = voxel_topology(grid);
      const int outside_without = empty_components(grid);
      const bool answer_without = is_simple_voxel(grid, 1, 1, 1);
      EXPECT_EQ(outside_with, with.voids + 1);
      EXPECT_EQ(outside_without, without.voids + 1);
      const bool brute = betti(with) == betti(without) && outside_with == outside_without;
      ASSERT_EQ(answer_with, brute) << "density " << density << " trial " << trial;
      ASSERT_EQ(answer_without, brute);
      (brute ? simple : not_simple)++;
    }
  }
  EXPECT_GT(simple, 2000);
  EXPECT_GT(not_simple, 2000);
}

TEST(SimpleVoxel, ClassicCases) {
  VoxelGrid grid = make_grid(3, 3, 3);
  grid.set(1, 1, 1, true);
  EXPECT_FALSE(is_simple_voxel(grid, 1, 1, 1));  // isolated: removing it deletes a component
  fill(grid, {0, 0, 0}, {3, 3, 3});
  EXPECT_FALSE(is_simple_voxel(grid, 1, 1, 1));  // interior: removing it opens a cavity
  EXPECT_TRUE(is_simple_voxel(grid, 0, 0, 0));   // a corner of a box
  EXPECT_TRUE(is_simple_voxel(grid, 1, 1, 0));   // the middle of a face
  VoxelGrid bridge = make_grid(3, 1, 1);
  fill(bridge, {0, 0, 0}, {3, 1, 1});
  EXPECT_FALSE(is_simple_voxel(bridge, 1, 0, 0));  // cuts a rod in two
  EXPECT_TRUE(is_simple_voxel(bridge, 2, 0, 0));   // shortens it
  EXPECT_THROW(is_simple_voxel(bridge, 3, 0, 0), InputError);
}

// ---------------------------------------------------------------------------
// Well-composedness

TEST(WellComposed, CriticalConfigurations) {
  VoxelGrid grid = make_grid(4, 4, 4);
  EXPECT_TRUE(is_well_composed(grid));
  grid.set(1, 1, 1, true);
  grid.set(2, 2, 1, true);  // diagonal across an edge
  EXPECT_FALSE(is_well_composed(grid));
  EXPECT_FALSE(is_well_composed_near(grid, 1, 1, 1));
  EXPECT_FALSE(is_well_composed_near(grid, 2, 1, 1));  // the empty voxels of the square too
  EXPECT_TRUE(is_well_composed_near(grid, 3, 3, 3));
  grid.set(2, 1, 1, true);  // now an L
  EXPECT_TRUE(is_well_composed(grid));

  VoxelGrid antipodal = make_grid(2, 2, 2);
  antipodal.set(0, 0, 0, true);
  antipodal.set(1, 1, 1, true);
  EXPECT_FALSE(is_well_composed(antipodal));
  // The same with the roles of occupied and empty swapped.
  fill(antipodal, {0, 0, 0}, {2, 2, 2});
  antipodal.set(0, 1, 0, false);
  antipodal.set(1, 0, 1, false);
  EXPECT_FALSE(is_well_composed(antipodal));
  antipodal.set(0, 1, 0, true);
  EXPECT_TRUE(is_well_composed(antipodal));

  // Diagonal squares of empty voxels inside a solid.
  VoxelGrid solid = make_grid(4, 4, 3);
  fill(solid, {0, 0, 0}, {4, 4, 3});
  solid.set(1, 1, 1, false);
  solid.set(2, 2, 1, false);
  EXPECT_FALSE(is_well_composed(solid));
  // At the grid's edge the outside is empty: a voxel diagonal to an inside one there is
  // still critical.
  VoxelGrid edge = make_grid(2, 2, 1);
  edge.set(0, 0, 0, true);
  edge.set(1, 1, 0, true);
  EXPECT_FALSE(is_well_composed(edge));
}

TEST(WellComposed, FineSets) {
  EXPECT_TRUE(is_well_composed(genus_three_plate()));
  VoxelGrid box = make_grid(5, 5, 5);
  fill(box, {1, 1, 1}, {4, 4, 4});
  EXPECT_TRUE(is_well_composed(box));
  box.set(1, 1, 1, false);  // a notch at a corner
  EXPECT_TRUE(is_well_composed(box));
  VoxelGrid single = make_grid(1, 1, 1);
  single.set(0, 0, 0, true);
  EXPECT_TRUE(is_well_composed(single));
}

TEST(WellComposed, AgreesWithNaiveCheckAndLocalTests) {
  std::mt19937 rng(11);
  int well = 0, not_well = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::bernoulli_distribution occupied(trial % 2 ? 0.9 : 0.1);
    VoxelGrid grid = make_grid(4, 3, 5);
    for (std::size_t i = 0; i < grid.occupied.size(); ++i) grid.occupied[i] = occupied(rng);
    const bool expected = naive_well_composed(grid);
    ASSERT_EQ(is_well_composed(grid), expected);
    bool all_near = true;
    for (int z = 0; z < 5; ++z)
      for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) all_near = all_near && is_well_composed_near(grid, x, y, z);
    ASSERT_EQ(all_near, expected);
    (expected ? well : not_well)++;
  }
  EXPECT_GT(well, 20);
  EXPECT_GT(not_well, 20);
}

// ---------------------------------------------------------------------------
// voxel_boundary, polycube_corners

namespace {

/// Checks that the quads form a closed, consistently oriented 2-manifold and returns its
/// Euler characteristic.
std::int64_t check_closed_manifold(const QuadMesh& mesh) {
  std::map<std::pair<Index, Index>, int> directed;
  std::vector<std::vector<std::pair<Index, Index>>> link(mesh.points.size());
  for (const auto& quad : mesh.quads)
    for (int k = 0; k < 4; ++k) {
      ++directed[{quad[k], quad[(k + 1) % 4]}];
      link[quad[k]].push_back({quad[(k + 1) % 4], quad[(k + 3) % 4]});
    }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " in two quads the same way";
    const auto reverse = directed.find({edge.second, edge.first});
    EXPECT_TRUE(reverse != directed.end()) << "edge " << edge.first << "-" << edge.second << " in one quad";
  }
  // The quads around each vertex form one fan: following next -> previous from any of
  // them comes back after visiting them all.
  for (std::size_t v = 0; v < link.size(); ++v) {
    EXPECT_GE(link[v].size(), 3u) << "vertex " << v;
    std::map<Index, Index> next;
    for (const auto& [from, to] : link[v]) EXPECT_TRUE(next.emplace(from, to).second) << "vertex " << v;
    if (link[v].empty()) continue;
    Index at = link[v][0].first;
    std::size_t steps = 0;
    do {
      const auto it = next.find(at);
      if (it == next.end()) break;
      at = it->second;
      ++steps;
    } while (at != link[v][0].first && steps <= link[v].size());
    EXPECT_EQ(steps, link[v].size()) << "vertex " << v << " is not a manifold vertex";
  }
  return static_cast<std::int64_t>(mesh.points.size()) - static_cast<std::int64_t>(directed.size() / 2) +
         static_cast<std::int64_t>(mesh.quads.size());
}

/// Each quad's normal points from an occupied voxel to an empty one.
void check_outward(const VoxelGrid& grid, const QuadMesh& mesh) {
  for (const auto& quad : mesh.quads) {
    const Vec3 p0 = mesh.points[quad[0]], p1 = mesh.points[quad[1]], p3 = mesh.points[quad[3]];
    const Vec3 normal = (p1 - p0).cross(p3 - p0).normalized();
    const Vec3 centre = 0.25 * (p0 + p1 + mesh.points[quad[2]] + p3);
    const Vec3 inner = (centre - 0.5 * grid.size * normal - grid.origin) / grid.size;
    const Vec3 outer = (centre + 0.5 * grid.size * normal - grid.origin) / grid.size;
    const auto voxel = [&](const Vec3& p) {
      return grid.at(static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())),
                     static_cast<int>(std::floor(p.z())));
    };
    ASSERT_TRUE(voxel(inner));
    ASSERT_FALSE(voxel(outer));
  }
}

}  // namespace

TEST(VoxelBoundary, CubeHasEightCornersAndSixNSquaredQuads) {
  for (const int n : {1, 3, 4}) {
    VoxelGrid grid = make_grid(n + 2, n + 2, n + 2);
    fill(grid, {1, 1, 1}, {n + 1, n + 1, n + 1});
    std::vector<std::uint8_t> corner;
    const QuadMesh mesh = voxel_boundary(grid, &corner);
    EXPECT_EQ(mesh.quads.size(), static_cast<std::size_t>(6 * n * n));
    EXPECT_EQ(mesh.points.size(), static_cast<std::size_t>(6 * n * n + 2));
    ASSERT_EQ(corner.size(), mesh.points.size());
    EXPECT_EQ(std::count(corner.begin(), corner.end(), 1), 8);
    EXPECT_EQ(polycube_corners(grid), 8u);
    for (std::size_t p = 0; p < corner.size(); ++p) {
      // The corners are the cube's: every coordinate at the cube's extremes.
      const Vec3 q = (mesh.points[p] - grid.origin) / grid.size;
      const bool extreme = (std::abs(q.x() - 1) < 1e-9 || std::abs(q.x() - n - 1) < 1e-9) &&
                           (std::abs(q.y() - 1) < 1e-9 || std::abs(q.y() - n - 1) < 1e-9) &&
                           (std::abs(q.z() - 1) < 1e-9 || std::abs(q.z() - n - 1) < 1e-9);
      EXPECT_EQ(corner[p] == 1, extreme);
    }
    EXPECT_EQ(check_closed_manifold(mesh), 2);
    check_outward(grid, mesh);
  }
}

TEST(VoxelBoundary, WellComposedSetsBoundClosedManifolds) {
  std::vector<VoxelGrid> grids{noise_blob(24, 3, 6, 0.55), noise_blob(24, 5, 4, 0.45), torus(20, 5.5, 2.5),
                               genus_three_plate()};
  VoxelGrid hollow = make_grid(9, 9, 9);
  fill(hollow, {1, 1, 1}, {8, 8, 8});
  fill(hollow, {3, 3, 3}, {6, 6, 6}, false);
  grids.push_back(hollow);
  for (const VoxelGrid& grid : grids) {
    ASSERT_TRUE(is_well_composed(grid));
    ASSERT_GT(grid.count(), 50u);
    const QuadMesh mesh = voxel_boundary(grid);
    // The boundary of a compact 3-manifold has twice its Euler characteristic.
    EXPECT_EQ(check_closed_manifold(mesh), 2 * voxel_topology(grid).euler);
    check_outward(grid, mesh);
  }
}

TEST(VoxelBoundary, CornersAreTheVerticesOfValenceOtherThanFour) {
  // The dissertation's corners (valence != 4) and the header's (faces of all three
  // directions) agree on well-composed sets.
  for (const unsigned seed : {3u, 9u}) {
    const VoxelGrid grid = noise_blob(24, seed, 6, 0.5);
    std::vector<std::uint8_t> corner;
    const QuadMesh mesh = voxel_boundary(grid, &corner);
    std::vector<int> valence(mesh.points.size(), 0);
    for (const auto& quad : mesh.quads)
      for (const Index v : quad) ++valence[v];
    std::size_t corners = 0;
    for (std::size_t v = 0; v < valence.size(); ++v) {
      EXPECT_EQ(corner[v] == 1, valence[v] != 4) << "vertex " << v << " of valence " << valence[v];
      corners += corner[v];
    }
    EXPECT_EQ(polycube_corners(grid), corners);
    EXPECT_GT(corners, 8u);
  }
}

// ---------------------------------------------------------------------------
// Homotopic morphology

namespace {

/// One homotopic erosion or dilation layer written with the public tests only: the
/// candidates at the start, scan order, a voxel flips when simple and well-composed
/// around it afterwards, blocked candidates retried until a pass flips nothing.
std::size_t reference_layer(VoxelGrid& grid, const VoxelBox& box, bool erosion) {
  std::vector<Triple> candidates;
  for (int z = std::max(box.lo[2], 0); z < std::min(box.hi[2], grid.dims[2]); ++z)
    for (int y = std::max(box.lo[1], 0); y < std::min(box.hi[1], grid.dims[1]); ++y)
      for (int x = std::max(box.lo[0], 0); x < std::min(box.hi[0], grid.dims[0]); ++x) {
        if (grid.at(x, y, z) != erosion) continue;
        bool other = false;
        for (int d = 0; d < 27; ++d)
          other = other || grid.at(x + d % 3 - 1, y + (d / 3) % 3 - 1, z + d / 9 - 1) != erosion;
        if (other) candidates.push_back({x, y, z});
      }
  std::size_t flipped = 0;
  for (std::size_t pass = 1; pass > 0;) {
    pass = 0;
    for (const Triple& c : candidates) {
      if (grid.at(c[0], c[1], c[2]) != erosion || !is_simple_voxel(grid, c[0], c[1], c[2])) continue;
      grid.set(c[0], c[1], c[2], !erosion);
      if (is_well_composed_near(grid, c[0], c[1], c[2]))
        ++pass;
      else
        grid.set(c[0], c[1], c[2], erosion);
    }
    flipped += pass;
  }
  return flipped;
}

}  // namespace

TEST(HomotopicMorphology, LayersMatchAReferenceBuiltFromThePublicTests) {
  std::mt19937 rng(17);
  std::size_t flips = 0;
  for (const unsigned seed : {3u, 5u, 8u}) {
    VoxelGrid grid = noise_blob(24, seed, 6, 0.5);
    VoxelGrid reference = grid;
    for (int step = 0; step < 12; ++step) {
      VoxelBox box;
      for (int a = 0; a < 3; ++a) {
        box.lo[a] = std::uniform_int_distribution<int>(-3, 14)(rng);
        box.hi[a] = box.lo[a] + std::uniform_int_distribution<int>(4, 70)(rng);
      }
      const bool erosion = step % 3 != 1;
      const std::size_t expected = reference_layer(reference, box, erosion);
      const std::size_t got = erosion ? homotopic_erode(grid, box) : homotopic_dilate(grid, box);
      ASSERT_EQ(got, expected) << "seed " << seed << " step " << step;
      ASSERT_EQ(grid.occupied, reference.occupied);
      flips += got;
    }
  }
  EXPECT_GT(flips, 1000u);
}

TEST(HomotopicMorphology, LayersMatchTheReferenceOnRowsLongerThanAWord) {
  // Boxes more than 62 voxels long take the multi-word path of the bit rows.
  VoxelGrid grid = noise_blob(Triple{150, 14, 12}, 4, 60, 0.3);
  ASSERT_GT(grid.count(), 2000u);
  VoxelGrid reference = grid;
  const std::vector<VoxelBox> boxes{{{-2, 0, 0}, {150, 14, 12}},
                                    {{30, 2, 1}, {140, 12, 11}},
                                    {{60, -3, -3}, {200, 20, 20}},
                                    {{0, 0, 0}, {129, 14, 12}}};
  std::size_t flips = 0;
  for (std::size_t b = 0; b < boxes.size() * 2; ++b) {
    const bool erosion = b % 2 == 0;
    const VoxelBox& box = boxes[b / 2];
    const std::size_t expected = reference_layer(reference, box, erosion);
    ASSERT_EQ(erosion ? homotopic_erode(grid, box) : homotopic_dilate(grid, box), expected) << "box " << b / 2;
    ASSERT_EQ(grid.occupied, reference.occupied);
    flips += expected;
  }
  EXPECT_GT(flips, 500u);
}

TEST(HomotopicMorphology, WindowsLoadTheSameFromPackedRows) {
  // optimize_polycube loads its windows from a bit-packed copy of the grid.
  std::mt19937 rng(23);
  VoxelGrid grid = make_grid(131, 9, 7);
  std::bernoulli_distribution occupied(0.5);
  for (std::size_t i = 0; i < grid.occupied.size(); ++i) grid.occupied[i] = occupied(rng);
  const voxel::PackedVoxels packed(grid);
  voxel::VoxelWindow from_grid, from_packed;
  for (int trial = 0; trial < 200; ++trial) {
    VoxelBox box;
    box.lo = {std::uniform_int_distribution<int>(-70, 140)(rng), std::uniform_int_distribution<int>(-3, 8)(rng),
              std::uniform_int_distribution<int>(-3, 6)(rng)};
    for (int a = 0; a < 3; ++a) box.hi[a] = box.lo[a] + std::uniform_int_distribution<int>(1, 140)(rng);
    const bool loaded = from_grid.load(grid, box);
    ASSERT_EQ(from_packed.load(packed, box), loaded);
    if (!loaded) continue;
    EXPECT_EQ(from_packed.origin(), from_grid.origin());
    EXPECT_EQ(from_packed.size(), from_grid.size());
    ASSERT_EQ(from_packed.loaded_rows(), from_grid.loaded_rows()) << "trial " << trial;
  }
}

TEST(HomotopicMorphology, ErosionPeelsACubeAndDilationRegrowsIt) {
  VoxelGrid grid = make_grid(9, 9, 9);
  fill(grid, {2, 2, 2}, {7, 7, 7});
  EXPECT_EQ(homotopic_erode(grid, whole(grid)), 125u - 27u);
  VoxelGrid core = make_grid(9, 9, 9);
  fill(core, {3, 3, 3}, {6, 6, 6});
  EXPECT_EQ(grid.occupied, core.occupied);
  EXPECT_EQ(homotopic_dilate(grid, whole(grid)), 125u - 27u);
  fill(core, {2, 2, 2}, {7, 7, 7});
  EXPECT_EQ(grid.occupied, core.occupied);
}

TEST(HomotopicMorphology, OnlyTheBoxChanges) {
  VoxelGrid grid = make_grid(10, 10, 10);
  fill(grid, {1, 1, 1}, {9, 9, 9});
  const VoxelGrid before = grid;
  const VoxelBox box{{0, 0, 0}, {5, 10, 10}};
  EXPECT_GT(homotopic_erode(grid, box), 0u);
  for (int z = 0; z < 10; ++z)
    for (int y = 0; y < 10; ++y)
      for (int x = 5; x < 10; ++x) EXPECT_EQ(grid.at(x, y, z), before.at(x, y, z));
  // Boxes reaching past the grid are clamped; an empty box changes nothing.
  EXPECT_GT(homotopic_dilate(grid, VoxelBox{{-5, -5, -5}, {20, 20, 20}}), 0u);
  const VoxelGrid dilated = grid;
  EXPECT_EQ(homotopic_erode(grid, VoxelBox{{3, 3, 3}, {3, 8, 8}}), 0u);
  EXPECT_EQ(grid.occupied, dilated.occupied);
}

TEST(HomotopicMorphology, OpeningRemovesAThinFinAndClosingFillsAThinGroove) {
  VoxelGrid grid = make_grid(12, 12, 12);
  fill(grid, {1, 1, 1}, {11, 11, 6});
  VoxelGrid slab = grid;
  fill(grid, {3, 5, 6}, {9, 6, 8});  // a fin one voxel thick on the top face
  EXPECT_GT(homotopic_open(grid, whole(grid), 1), 0u);
  EXPECT_EQ(grid.occupied, slab.occupied);

  fill(grid, {3, 5, 4}, {9, 6, 6}, false);  // a groove one voxel wide
  EXPECT_GT(homotopic_close(grid, whole(grid), 1), 0u);
  EXPECT_EQ(grid.occupied, slab.occupied);
}

TEST(HomotopicMorphology, OpeningNeverAddsAndClosingNeverRemoves) {
  const VoxelGrid blob = noise_blob(24, 21, 6, 0.5);
  for (const int layers : {1, 2, 3}) {
    VoxelGrid opened = blob, closed = blob;
    homotopic_open(opened, VoxelBox{{4, 4, 4}, {16, 18, 20}}, layers);
    homotopic_close(closed, VoxelBox{{4, 4, 4}, {16, 18, 20}}, layers);
    for (std::size_t i = 0; i < blob.occupied.size(); ++i) {
      EXPECT_LE(opened.occupied[i], blob.occupied[i]);
      EXPECT_GE(closed.occupied[i], blob.occupied[i]);
    }
    EXPECT_NE(opened.occupied, blob.occupied);
    EXPECT_NE(closed.occupied, blob.occupied);
  }
}

TEST(HomotopicMorphology, OpeningAndClosingKeepTopologyAndWellComposedness) {
  // Smooth blobs and a voxelized torus change (the plate may not: it is rectilinear).
  const std::vector<std::pair<VoxelGrid, bool>> cases{{noise_blob(24, 3, 6, 0.55), true},
                                                      {noise_blob(24, 5, 4, 0.45), true},
                                                      {noise_blob(24, 8, 8, 0.6), true},
                                                      {torus(20, 5.5, 2.5), true},
                                                      {genus_three_plate(), false}};
  for (const auto& [input, changes] : cases) {
    ASSERT_TRUE(is_well_composed(input));
    const VoxelTopology topology = voxel_topology(input);
    std::size_t flips = 0;
    for (const int layers : {1, 2, 3}) {
      VoxelGrid opened = input, closed = input;
      flips += homotopic_open(opened, whole(opened), layers);
      flips += homotopic_close(closed, whole(closed), layers);
      EXPECT_EQ(invariants(opened), invariants(input)) << "opening of " << layers;
      EXPECT_EQ(invariants(closed), invariants(input)) << "closing of " << layers;
      EXPECT_TRUE(is_well_composed(opened));
      EXPECT_TRUE(is_well_composed(closed));
    }
    if (changes) {
      EXPECT_GT(flips, 0u);
    }
    // Repeated erosions stop at a thin core of the same topology.
    VoxelGrid eroded = input;
    for (int i = 0; i < 12; ++i) homotopic_erode(eroded, whole(eroded));
    EXPECT_EQ(betti(voxel_topology(eroded)), betti(topology));
    EXPECT_TRUE(is_well_composed(eroded));
    EXPECT_LT(eroded.count(), input.count());
  }
}

TEST(HomotopicMorphology, PlainErosionBreaksAThinTorusAndHomotopicErosionDoesNot) {
  // A square ring, two voxels thick: one plain erosion (every voxel with an empty
  // 26-neighbour goes) removes all of it.
  VoxelGrid ring = make_grid(12, 12, 4);
  fill(ring, {1, 1, 1}, {11, 11, 3});
  fill(ring, {3, 3, 1}, {9, 9, 3}, false);
  ASSERT_EQ(betti(voxel_topology(ring)), (std::array<std::int64_t, 3>{1, 1, 0}));
  VoxelGrid plain = ring;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 12; ++y)
      for (int x = 0; x < 12; ++x) {
        bool interior = ring.at(x, y, z);
        for (int d = 0; d < 27 && interior; ++d) interior = ring.at(x + d % 3 - 1, y + (d / 3) % 3 - 1, z + d / 9 - 1);
        plain.set(x, y, z, interior);
      }
  EXPECT_NE(betti(voxel_topology(plain)), betti(voxel_topology(ring)));

  VoxelGrid homotopic = ring;
  EXPECT_GT(homotopic_erode(homotopic, whole(homotopic)), 0u);
  EXPECT_EQ(betti(voxel_topology(homotopic)), betti(voxel_topology(ring)));
  EXPECT_TRUE(is_well_composed(homotopic));
  VoxelGrid opened = ring;
  homotopic_open(opened, whole(opened), 2);
  EXPECT_EQ(invariants(opened), invariants(ring));
}

// ---------------------------------------------------------------------------
// Energy (4.1) and optimize_polycube

namespace {

/// Distance from each grid vertex (in voxel units) to the surface of the box of voxels
/// [lo, hi), measured in the grid's coordinates.
std::vector<double> distance_to_box(const VoxelGrid& grid, Triple lo, Triple hi) {
  std::vector<double> distance(grid.vertex_count());
  for (int z = 0; z <= grid.dims[2]; ++z)
    for (int y = 0; y <= grid.dims[1]; ++y)
      for (int x = 0; x <= grid.dims[0]; ++x) {
        const std::array<double, 3> p{double(x), double(y), double(z)};
        double outside = 0, inside = 1e9;
        for (int a = 0; a < 3; ++a) {
          const double below = lo[a] - p[a], above = p[a] - hi[a];
          const double gap = std::max({below, above, 0.0});
          outside += gap * gap;
          inside = std::min(inside, std::min(p[a] - lo[a], hi[a] - p[a]));
        }
        distance[grid.vertex_index(x, y, z)] = outside > 0 ? std::sqrt(outside) : std::max(inside, 0.0);
      }
  return distance;
}

}  // namespace

TEST(PolycubeEnergy, SumsCornersAndBoundaryDistances) {
  VoxelGrid grid = make_grid(6, 6, 6);
  fill(grid, {1, 1, 1}, {4, 5, 5});
  std::vector<double> distance(grid.vertex_count());
  for (std::size_t v = 0; v < distance.size(); ++v) distance[v] = 0.001 * static_cast<double>(v % 97);
  double boundary_sum = 0;
  for (int z = 0; z <= 6; ++z)
    for (int y = 0; y <= 6; ++y)
      for (int x = 0; x <= 6; ++x) {
        int occupied = 0;
        for (int c = 0; c < 8; ++c) occupied += grid.at(x - 1 + (c & 1), y - 1 + ((c >> 1) & 1), z - 1 + (c >> 2));
        if (occupied > 0 && occupied < 8) boundary_sum += distance[grid.vertex_index(x, y, z)];
      }
  const PolycubeEnergy energy = polycube_energy(grid, distance, 20);
  EXPECT_EQ(energy.corners, 8u);
  EXPECT_NEAR(energy.deviation, boundary_sum, 1e-12);
  EXPECT_NEAR(energy.total, 8 + 20 * boundary_sum, 1e-9);
  distance.pop_back();
  EXPECT_THROW(polycube_energy(grid, distance, 20), InputError);
  EXPECT_THROW(optimize_polycube(grid, distance), InputError);
}

TEST(OptimizePolycube, RemovesABumpTheDistanceFieldDoesNotWant) {
  VoxelGrid grid = make_grid(12, 12, 12);
  fill(grid, {2, 2, 2}, {10, 10, 10});
  VoxelGrid box = grid;
  grid.set(5, 6, 10, true);  // a bump on the top face
  const std::vector<double> distance = distance_to_box(grid, {2, 2, 2}, {10, 10, 10});
  const PolycubeOptimizationResult result = optimize_polycube(grid, distance);
  EXPECT_EQ(result.before.corners, 16u);
  EXPECT_DOUBLE_EQ(result.before.deviation, 4.0);  // the bump's four top vertices
  EXPECT_EQ(result.after.corners, 8u);
  // No boundary vertex off the box; the volume term counts the removed bump voxel at the
  // mean distance of its corners (four at 1, four at 0).
  EXPECT_DOUBLE_EQ(result.after.deviation, 0.5);
  EXPECT_EQ(grid.occupied, box.occupied);
  EXPECT_GE(result.openings, 1u);
  EXPECT_GE(result.sweeps, 6u);  // at least two sweeps at the radius that removed it, one at each other
}

TEST(OptimizePolycube, KeepsABumpTheDistanceFieldWantsWhenAlphaIsLarge) {
  // A 2 x 2 bump: without it the vertex in the middle of its base joins the boundary,
  // one voxel from the surface of box + bump. (A one-voxel bump always goes: removing
  // it takes boundary vertices away and adds none, so E_g cannot hold it.)
  VoxelGrid grid = make_grid(12, 12, 12);
  fill(grid, {2, 2, 2}, {10, 10, 10});
  VoxelGrid box = grid;
  fill(grid, {5, 5, 10}, {7, 7, 11});
  const VoxelGrid with_bump = grid;
  std::vector<double> distance = distance_to_box(grid, {2, 2, 2}, {10, 10, 10});
  const std::vector<double> to_bump = distance_to_box(grid, {5, 5, 10}, {7, 7, 11});
  for (std::size_t v = 0; v < distance.size(); ++v) distance[v] = std::min(distance[v], to_bump[v]);
  // The middle of the base (6, 6, 10) is inside box + bump, one voxel from its surface.
  distance[grid.vertex_index(6, 6, 10)] = 1.0;

  PolycubeOptimizationOptions options;
  options.alpha = 1000;
  const PolycubeOptimizationResult kept = optimize_polycube(grid, distance, options);
  EXPECT_EQ(grid.occupied, with_bump.occupied);
  EXPECT_EQ(kept.after.corners, 16u);
  EXPECT_EQ(kept.openings + kept.closings, 0u);

  options.alpha = 1;  // -8 corners + 1 * (1 + 0.5) deviation: now the bump goes
  const PolycubeOptimizationResult removed = optimize_polycube(grid, distance, options);
  EXPECT_EQ(grid.occupied, box.occupied);
  EXPECT_EQ(removed.after.corners, 8u);
  // 1 at the base's middle vertex, plus the volume term: four removed voxels, each with
  // that vertex (distance 1) among its eight corners and the others on the surface.
  EXPECT_DOUBLE_EQ(removed.after.deviation, 1.0 + 4 * (1.0 / 8));
}

TEST(OptimizePolycube, CoveredPointsKeepALegTheDistanceFieldDoesNotWant) {
  // A box with a leg two voxels thick and eight long; the distances are to the box alone,
  // so E_p wants the leg gone, and an opening takes it. With points of Q along the leg,
  // the guard refuses every opening that would leave one of them without a voxel within 3.
  VoxelGrid grid = make_grid(22, 12, 12);
  fill(grid, {2, 2, 2}, {10, 10, 10});
  const VoxelGrid box = grid;
  fill(grid, {10, 5, 5}, {18, 7, 7});
  const VoxelGrid with_leg = grid;
  const std::vector<double> distance = distance_to_box(grid, {2, 2, 2}, {10, 10, 10});
  const PolycubeOptimizationResult removed = optimize_polycube(grid, distance);
  EXPECT_EQ(grid.occupied, box.occupied);
  EXPECT_EQ(removed.refused_openings, 0u);

  std::vector<Vec3> leg;
  for (int x = 10; x < 18; ++x) leg.push_back(grid.origin + grid.size * Vec3(x + 0.5, 6.0, 6.0));
  grid = with_leg;
  const PolycubeOptimizationResult kept = optimize_polycube(grid, distance, {}, leg);
  EXPECT_GT(kept.refused_openings, 0u);
  EXPECT_EQ(betti(voxel_topology(grid)), betti(voxel_topology(with_leg)));
  for (const Vec3& p : leg) {
    const int x = static_cast<int>(std::floor((p.x() - grid.origin.x()) / grid.size));
    bool near = false;
    for (int dx = -3; dx <= 3; ++dx)
      for (int dy = -3; dy <= 3; ++dy)
        for (int dz = -3; dz <= 3; ++dz) near = near || grid.at(x + dx, 5 + dy, 5 + dz);
    EXPECT_TRUE(near) << x;
  }
  // The leg may lose up to 3 voxels at its end (the guard's radius), not more.
  EXPECT_TRUE(grid.at(14, 5, 5) || grid.at(14, 5, 6) || grid.at(14, 6, 5) || grid.at(14, 6, 6));
}

TEST(OptimizePolycube, KeepsTopologyAndWellComposednessAndLowersTheEnergy) {
  // Noisy solids: a torus and a genus-3 plate with random bumps and pits, against the
  // distance to the clean shape's boundary vertices.
  std::vector<std::pair<VoxelGrid, VoxelGrid>> cases;
  const VoxelGrid ring = torus(24, 6.5, 3.2), plate = genus_three_plate();
  for (const VoxelGrid& clean : {ring, plate}) {
    VoxelGrid noisy = clean;
    std::mt19937 rng(5);
    for (int i = 0; i < 60; ++i) {
      const int x = std::uniform_int_distribution<int>(1, clean.dims[0] - 2)(rng);
      const int y = std::uniform_int_distribution<int>(1, clean.dims[1] - 2)(rng);
      const int z = std::uniform_int_distribution<int>(1, clean.dims[2] - 2)(rng);
      // Flip only voxels that keep the topology and the manifold boundary.
      if (is_simple_voxel(noisy, x, y, z)) {
        noisy.set(x, y, z, !noisy.at(x, y, z));
        if (!is_well_composed_near(noisy, x, y, z)) noisy.set(x, y, z, !noisy.at(x, y, z));
      }
    }
    cases.push_back({clean, noisy});
  }
  for (auto& [clean, noisy] : cases) {
    ASSERT_TRUE(is_well_composed(clean));
    ASSERT_TRUE(is_well_composed(noisy));
    const auto topology = invariants(clean);
    ASSERT_EQ(invariants(noisy), topology);
    ASSERT_NE(noisy.occupied, clean.occupied);
    // Distance to the nearest boundary vertex of the clean shape.
    std::vector<std::uint8_t> on_surface(clean.vertex_count(), 0);
    std::vector<Triple> surface;
    for (int z = 0; z <= clean.dims[2]; ++z)
      for (int y = 0; y <= clean.dims[1]; ++y)
        for (int x = 0; x <= clean.dims[0]; ++x) {
          int occupied = 0;
          for (int c = 0; c < 8; ++c) occupied += clean.at(x - 1 + (c & 1), y - 1 + ((c >> 1) & 1), z - 1 + (c >> 2));
          if (occupied > 0 && occupied < 8) surface.push_back({x, y, z});
        }
    std::vector<double> distance(clean.vertex_count());
    for (int z = 0; z <= clean.dims[2]; ++z)
      for (int y = 0; y <= clean.dims[1]; ++y)
        for (int x = 0; x <= clean.dims[0]; ++x) {
          double best = 1e9;
          for (const Triple& s : surface)
            best = std::min(best, std::hypot(double(x - s[0]), double(y - s[1]), double(z - s[2])));
          distance[clean.vertex_index(x, y, z)] = best;
        }
    PolycubeOptimizationOptions options;
    options.max_window = 3;
    const VoxelGrid noisy_input = noisy;
    const PolycubeOptimizationResult result = optimize_polycube(noisy, distance, options);
    EXPECT_EQ(invariants(noisy), topology);
    EXPECT_TRUE(is_well_composed(noisy));
    EXPECT_GT(result.openings + result.closings, 0u);
    EXPECT_LT(result.after.total, result.before.total);
    const PolycubeEnergy recomputed = polycube_energy(noisy, distance, options.alpha, &noisy_input);
    EXPECT_EQ(recomputed.corners, result.after.corners);
    EXPECT_DOUBLE_EQ(recomputed.total, result.after.total);
    // Deterministic: the same input gives the same polycube.
    VoxelGrid rerun = noisy_input;
    const PolycubeOptimizationResult again = optimize_polycube(rerun, distance, options);
    EXPECT_EQ(rerun.occupied, noisy.occupied);
    EXPECT_EQ(again.openings, result.openings);
    EXPECT_EQ(again.sweeps, result.sweeps);
  }
}

TEST(OptimizePolycube, ResultDoesNotDependOnTheThreadCount) {
  VoxelGrid input = noise_blob(32, 13, 7, 0.5);
  std::vector<double> distance(input.vertex_count());
  for (std::size_t v = 0; v < distance.size(); ++v) distance[v] = 0.05 * static_cast<double>((v * 7919) % 13);
  VoxelGrid parallel = input, serial = input;
  PolycubeOptimizationOptions options;
  options.max_window = 3;
  options.alpha = 2;
  const PolycubeOptimizationResult parallel_result = optimize_polycube(parallel, distance, options);
  PolycubeOptimizationResult serial_result;
  {
    const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    serial_result = optimize_polycube(serial, distance, options);
  }
  EXPECT_GT(parallel_result.openings + parallel_result.closings, 10u);
  EXPECT_EQ(parallel.occupied, serial.occupied);
  EXPECT_EQ(parallel_result.openings, serial_result.openings);
  EXPECT_EQ(parallel_result.closings, serial_result.closings);
  EXPECT_EQ(parallel_result.sweeps, serial_result.sweeps);
  EXPECT_EQ(parallel_result.after.total, serial_result.after.total);
}

TEST(OptimizePolycube, RejectsBadOptions) {
  VoxelGrid grid = make_grid(3, 3, 3);
  grid.set(1, 1, 1, true);
  const std::vector<double> distance(grid.vertex_count(), 0.0);
  PolycubeOptimizationOptions options;
  options.max_window = 0;
  EXPECT_THROW(optimize_polycube(grid, distance, options), InputError);
  options.max_window = 2;
  options.alpha = -1;
  EXPECT_THROW(optimize_polycube(grid, distance, options), InputError);
  options.alpha = 20;
  options.threshold = std::nan("");
  EXPECT_THROW(optimize_polycube(grid, distance, options), InputError);
  std::vector<double> bad = distance;
  bad[5] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(optimize_polycube(grid, bad), InputError);
}

// ---------------------------------------------------------------------------
// merge_facet_planes

namespace {

std::size_t count_facet_planes(const VoxelGrid& grid, int axis) {
  std::size_t planes = 0;
  for (int w = 0; w <= grid.dims[axis]; ++w) {
    bool facet = false;
    for (int v = 0; v < grid.dims[(axis + 2) % 3] && !facet; ++v)
      for (int u = 0; u < grid.dims[(axis + 1) % 3] && !facet; ++u) {
        Triple above{}, below{};
        above[axis] = w, above[(axis + 1) % 3] = u, above[(axis + 2) % 3] = v;
        below = above;
        --below[axis];
        facet = grid.at(above[0], above[1], above[2]) != grid.at(below[0], below[1], below[2]);
      }
    planes += facet ? 1 : 0;
  }
  return planes;
}

// A 12 x 12 x 6 block with a step of `height` voxels on the half x >= 8.
VoxelGrid stepped_block(int height) {
  VoxelGrid grid = make_grid(16, 16, 14);
  fill(grid, {2, 2, 2}, {14, 14, 8});
  fill(grid, {8, 2, 8}, {14, 14, 8 + height});
  return grid;
}

}  // namespace

TEST(MergeFacetPlanes, AOneVoxelStepMovesOntoTheNeighbouringPlane) {
  VoxelGrid grid = stepped_block(1);
  const std::size_t voxels = grid.count();
  ASSERT_EQ(count_facet_planes(grid, 0), 3u);  // x = 2, 8 (the step's side), 14
  ASSERT_EQ(count_facet_planes(grid, 2), 3u);  // z = 2, 8, 9
  const PlaneMergeResult result = merge_facet_planes(grid, 2);
  EXPECT_EQ(result.planes_before, (std::array<std::size_t, 3>{3, 2, 3}));
  EXPECT_EQ(result.planes_after, (std::array<std::size_t, 3>{2, 2, 2}));
  for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(count_facet_planes(grid, axis), result.planes_after[axis]);
  EXPECT_GE(result.removed, 1u);
  // The step is either filled or planed off: one layer of 6 x 12 voxels.
  EXPECT_EQ(std::max(grid.count(), voxels) - std::min(grid.count(), voxels), 72u);
  EXPECT_TRUE(is_well_composed(grid));
  EXPECT_EQ(invariants(grid), invariants(stepped_block(1)));
}

TEST(MergeFacetPlanes, LeavesAStepTallerThanTheShift) {
  VoxelGrid grid = stepped_block(3);
  const VoxelGrid before = grid;
  const PlaneMergeResult result = merge_facet_planes(grid, 2);
  EXPECT_EQ(result.removed, 0u);
  EXPECT_EQ(result.flips, 0u);
  EXPECT_EQ(grid.occupied, before.occupied);
  // With a shift of 3 the step goes.
  EXPECT_EQ(merge_facet_planes(grid, 3).planes_after[2], 2u);
}

TEST(MergeFacetPlanes, ZeroShiftChangesNothing) {
  VoxelGrid grid = stepped_block(1);
  const VoxelGrid before = grid;
  const PlaneMergeResult result = merge_facet_planes(grid, 0);
  EXPECT_EQ(result.removed, 0u);
  EXPECT_EQ(result.planes_before, (std::array<std::size_t, 3>{3, 2, 3}));
  EXPECT_EQ(result.planes_after, result.planes_before);
  EXPECT_EQ(grid.occupied, before.occupied);
}

TEST(MergeFacetPlanes, KeepsTopologyAndWellComposednessAndNeverAddsAPlane) {
  std::vector<VoxelGrid> cases{noise_blob(28, 3, 6, 0.5), noise_blob({30, 22, 18}, 11, 9, 0.45), torus(24, 6.5, 3.2),
                               genus_three_plate()};
  std::size_t removed = 0;
  for (VoxelGrid& grid : cases) {
    ASSERT_TRUE(is_well_composed(grid));
    const auto topology = invariants(grid);
    std::array<std::size_t, 3> planes{};
    for (int axis = 0; axis < 3; ++axis) planes[axis] = count_facet_planes(grid, axis);
    const PlaneMergeResult result = merge_facet_planes(grid, 2);
    EXPECT_EQ(result.planes_before, planes);
    EXPECT_TRUE(is_well_composed(grid));
    EXPECT_EQ(invariants(grid), topology);
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(count_facet_planes(grid, axis), result.planes_after[axis]);
      EXPECT_LE(result.planes_after[axis], planes[axis]);
    }
    removed += result.removed;
  }
  EXPECT_GT(removed, 0u);  // the blobs' curved sides are staircases of planes
}

TEST(MergeFacetPlanes, ANarrowSlitStaysOpen) {
  // A block with a slit one voxel wide cut from the top across its whole depth: the slit's
  // walls are on planes x = 9 and x = 10, one apart. Moving either wall onto the other's
  // plane would fill the slit (glue the two halves, as it glued the hand's fingers): a
  // facet may only move where it arrives whole.
  VoxelGrid grid = make_grid(20, 12, 10);
  fill(grid, {2, 2, 2}, {18, 10, 8});
  fill(grid, {9, 2, 4}, {10, 10, 8}, false);
  const auto topology = invariants(grid);
  merge_facet_planes(grid, 2);
  for (int z = 4; z < 8; ++z)
    for (int y = 2; y < 10; ++y) EXPECT_FALSE(grid.at(9, y, z)) << y << ", " << z;
  EXPECT_EQ(invariants(grid), topology);
  EXPECT_TRUE(is_well_composed(grid));
}
