#include "guard/shapes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"
#include "structmesh/io.hpp"
#include "structmesh/star.hpp"
#include "structmesh/tetmesh.hpp"
#include "test_data.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace structmesh {
namespace {

using test::Cell;
using test::voxel_surface;

// Union of unit cubes, each cut into the 6 Kuhn tets around its main diagonal (a
// conforming tetrahedralization of any union of grid cubes).
TetMesh kuhn_tets(const std::vector<Cell>& cells) {
  TetMesh mesh;
  std::map<Cell, Index> ids;
  const auto vertex = [&](int x, int y, int z) {
    const auto [it, inserted] = ids.emplace(Cell{x, y, z}, static_cast<Index>(mesh.points.size()));
    if (inserted) mesh.points.emplace_back(x, y, z);
    return it->second;
  };
  for (const Cell& c : cells) {
    const auto v = [&](int dx, int dy, int dz) { return vertex(c[0] + dx, c[1] + dy, c[2] + dz); };
    const Index o = v(0, 0, 0), d = v(1, 1, 1);
    const Index x = v(1, 0, 0), y = v(0, 1, 0), z = v(0, 0, 1);
    const Index xy = v(1, 1, 0), xz = v(1, 0, 1), yz = v(0, 1, 1);
    for (const auto& [a, b] :
         std::vector<std::pair<Index, Index>>{{x, xy}, {x, xz}, {y, xy}, {y, yz}, {z, xz}, {z, yz}})
      mesh.tets.push_back({o, a, b, d});
  }
  return mesh;
}

TetMesh solid_of(const std::vector<Cell>& cells, int subdivisions, double size) {
  TetmeshOptions options;
  options.size = size;
  return tetrahedralize(voxel_surface(cells, subdivisions), options).mesh;
}

std::vector<Vec3> guards_of(const TetMesh& solid) {
  std::vector<Vec3> guards;
  for (const Guard& guard : guard_surface(boundary_surface(solid)).guards) guards.push_back(guard.position);
  return guards;
}

// Independent check that every part is star-shaped from its guard, with exact
// constructions and without the kernel argument of star.hpp: for each vertex v of the
// part, the segment [guard, v] meets the part's boundary faces (faces not shared by two
// of its tets) at v at most. Also: the guard lies in a tet of the part.
// The check runs on the decomposition's points (result.points: relocation and smoothing
// move interior points).
void expect_star_shaped(const TetMesh& input, const StarResult& result) {
  TetMesh mesh = input;
  mesh.points = result.points;
  ASSERT_EQ(mesh.points.size(), input.points.size());
  using K = CGAL::Exact_predicates_exact_constructions_kernel;
  const auto point = [](const Vec3& p) { return K::Point_3(p.x(), p.y(), p.z()); };
  std::map<std::array<Index, 3>, std::vector<Index>> face_tets;
  for (Index t = 0; t < mesh.tets.size(); ++t)
    for (int i = 0; i < 4; ++i) {
      std::array<Index, 3> f{};
      int k = 0;
      for (int j = 0; j < 4; ++j)
        if (j != i) f[k++] = mesh.tets[t][j];
      std::sort(f.begin(), f.end());
      face_tets[f].push_back(t);
    }
  for (Index part = 0; part < result.parts.size(); ++part) {
    const K::Point_3 g = point(result.parts[part].guard);
    std::vector<std::array<Index, 3>> boundary;
    for (const auto& [face, tets] : face_tets) {
      int inside = 0;
      for (const Index t : tets) inside += result.tet_part[t] == part;
      if (inside == 1) boundary.push_back(face);
    }
    std::set<Index> vertices;
    bool holds_guard = false;
    for (Index t = 0; t < mesh.tets.size(); ++t) {
      if (result.tet_part[t] != part) continue;
      const auto& tet = mesh.tets[t];
      vertices.insert(tet.begin(), tet.end());
      holds_guard =
          holds_guard || CGAL::do_intersect(K::Tetrahedron_3(point(mesh.points[tet[0]]), point(mesh.points[tet[1]]),
                                                             point(mesh.points[tet[2]]), point(mesh.points[tet[3]])),
                                            g);
    }
    EXPECT_TRUE(holds_guard) << "part " << part << " does not contain its guard";
    for (const Index v : vertices) {
      const K::Point_3 pv = point(mesh.points[v]);
      if (pv == g) continue;
      const K::Segment_3 segment(g, pv);
      for (const auto& f : boundary) {
        const K::Triangle_3 triangle(point(mesh.points[f[0]]), point(mesh.points[f[1]]), point(mesh.points[f[2]]));
        const auto hit = CGAL::intersection(segment, triangle);
        if (!hit) continue;
        const K::Point_3* at = boost::get<K::Point_3>(&*hit);
        EXPECT_TRUE(at != nullptr && *at == pv) << "part " << part << ": vertex " << v << " is hidden from the guard";
      }
    }
  }
}

// A surface of the data set tetrahedralized at its mean edge length, as `structmesh star`
// does (the test fails if it is missing).
TetMesh data_solid(const std::string& name) {
  const std::filesystem::path path = test::data_dir() / "surfaces" / name;
  if (!std::filesystem::exists(path)) throw std::runtime_error(path.string() + " missing: set STRUCTMESH_DATA");
  const TriMesh surface = to_tri_mesh(read_mesh(path));
  TetmeshOptions options;
  options.size = mean_edge_length(surface);
  return tetrahedralize(surface, options).mesh;
}

// One pass over the tets, exact predicates: every face of a part's boundary has the
// part's guard strictly on the side of the tet's fourth vertex (the growth rule; a part
// where it holds is star-shaped from its guard). Returns the number of faces breaking it.
std::size_t faces_breaking_the_rule(const TetMesh& input, const StarResult& result) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  const auto point = [](const Vec3& p) { return K::Point_3(p.x(), p.y(), p.z()); };
  const auto neighbors = tet_neighbors(input);
  std::size_t breaking = 0;
  for (Index t = 0; t < input.tets.size(); ++t) {
    const Index part = result.tet_part[t];
    const K::Point_3 g = point(result.parts[part].guard);
    const auto& tet = input.tets[t];
    for (int i = 0; i < 4; ++i) {
      const Index n = neighbors[t][i];
      if (n != kInvalidIndex && result.tet_part[n] == part) continue;
      std::array<K::Point_3, 3> f;
      int k = 0;
      for (int j = 0; j < 4; ++j)
        if (j != i) f[k++] = point(result.points[tet[j]]);
      const CGAL::Orientation fourth = CGAL::orientation(f[0], f[1], f[2], point(result.points[tet[i]]));
      const CGAL::Orientation guard = CGAL::orientation(f[0], f[1], f[2], g);
      if (guard == CGAL::COPLANAR || guard != fourth) ++breaking;
    }
  }
  return breaking;
}

// Every tet in exactly one part (a valid id), every part non-empty and face-connected.
void expect_valid_partition(const TetMesh& mesh, const StarResult& result) {
  ASSERT_EQ(result.tet_part.size(), mesh.tets.size());
  const auto neighbors = tet_neighbors(mesh);
  std::vector<std::size_t> tets_in(result.parts.size(), 0);
  for (const Index part : result.tet_part) {
    ASSERT_LT(part, result.parts.size());
    ++tets_in[part];
  }
  std::size_t total = 0;
  for (Index part = 0; part < result.parts.size(); ++part) {
    EXPECT_GT(tets_in[part], 0u) << "part " << part << " is empty";
    EXPECT_EQ(result.parts[part].tets, tets_in[part]);
    total += result.parts[part].tets;
    // Breadth-first search inside the part from its first tet.
    std::vector<bool> seen(mesh.tets.size(), false);
    std::vector<Index> stack;
    for (Index t = 0; t < mesh.tets.size() && stack.empty(); ++t)
      if (result.tet_part[t] == part) stack.push_back(t), seen[t] = true;
    std::size_t reached = 0;
    while (!stack.empty()) {
      const Index t = stack.back();
      stack.pop_back();
      ++reached;
      for (const Index n : neighbors[t])
        if (n != kInvalidIndex && !seen[n] && result.tet_part[n] == part) seen[n] = true, stack.push_back(n);
    }
    EXPECT_EQ(reached, tets_in[part]) << "part " << part << " is not connected";
  }
  EXPECT_EQ(total, mesh.tets.size());
}

double total_volume(const TetMesh& mesh);

// Moving interior points (relocation, smoothing) keeps the boundary points, every tet's
// orientation and the total volume.
void expect_same_boundary_no_tet_flipped(const TetMesh& input, const StarResult& result) {
  TetMesh moved = input;
  moved.points = result.points;
  EXPECT_EQ(boundary_surface(input).points, boundary_surface(moved).points);
  for (std::size_t t = 0; t < input.tets.size(); ++t) {
    const auto volume = [&](const TetMesh& m) {
      const auto& q = m.tets[t];
      return (m.points[q[1]] - m.points[q[0]])
          .cross(m.points[q[2]] - m.points[q[0]])
          .dot(m.points[q[3]] - m.points[q[0]]);
    };
    EXPECT_GT(volume(input) * volume(moved), 0.0) << "tet " << t << " flipped or flattened";
  }
  EXPECT_NEAR(total_volume(moved), total_volume(input), 1e-9);
}

double total_volume(const TetMesh& mesh) {
  double volume = 0;
  for (const auto& t : mesh.tets) {
    const Vec3& a = mesh.points[t[0]];
    volume += std::abs((mesh.points[t[1]] - a).cross(mesh.points[t[2]] - a).dot(mesh.points[t[3]] - a)) / 6.0;
  }
  return volume;
}

TEST(TetNeighbors, KuhnBlockHasTheRightBoundaryAndSymmetry) {
  std::vector<Cell> cells;
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y)
      for (int z = 0; z < 2; ++z) cells.push_back({x, y, z});
  const TetMesh mesh = kuhn_tets(cells);
  const auto neighbors = tet_neighbors(mesh);
  std::size_t boundary = 0;
  for (Index t = 0; t < mesh.tets.size(); ++t)
    for (int i = 0; i < 4; ++i) {
      const Index n = neighbors[t][i];
      if (n == kInvalidIndex) {
        ++boundary;
        continue;
      }
      const auto& nb = neighbors[n];
      EXPECT_NE(std::find(nb.begin(), nb.end(), t), nb.end()) << "neighbour relation is not symmetric";
      // The neighbour does not use the vertex opposite the shared face.
      EXPECT_EQ(std::count(mesh.tets[n].begin(), mesh.tets[n].end(), mesh.tets[t][i]), 0);
    }
  EXPECT_EQ(boundary, 6u * 4u * 2u);  // 6 sides x 4 squares x 2 triangles
}

TEST(StarDecomposition, ConvexSolidIsOnePartFromOneGuard) {
  const TetMesh cube = solid_of({{0, 0, 0}}, 4, 0.2);
  const auto guards = guards_of(cube);
  ASSERT_EQ(guards.size(), 1u);
  for (const bool strict : {false, true}) {
    StarOptions options;
    options.strict = strict;
    const StarResult result = star_decomposition(cube, guards, options);
    EXPECT_EQ(result.parts.size(), 1u);
    expect_valid_partition(cube, result);
    expect_star_shaped(cube, result);
    EXPECT_TRUE(result.parts[0].star_shaped);
    EXPECT_DOUBLE_EQ(result.visible_fraction, 1.0);
    EXPECT_NEAR(result.parts[0].volume, 1.0, 1e-9);
  }
}

TEST(StarDecomposition, KuhnBlockFromAGenericInteriorGuard) {
  std::vector<Cell> cells;
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y)
      for (int z = 0; z < 3; ++z) cells.push_back({x, y, z});
  const TetMesh block = kuhn_tets(cells);
  const std::vector<Vec3> guard{{1.37, 1.52, 1.61}};
  StarOptions options;
  options.strict = true;
  const StarResult result = star_decomposition(block, guard, options);
  expect_valid_partition(block, result);
  expect_star_shaped(block, result);
  EXPECT_EQ(result.parts.size(), 1u) << "a convex block grows whole from one guard";
  EXPECT_EQ(result.moved_guards, 0u);
}

TEST(StarDecomposition, GuardOnAnEdgeIsMovedIntoATet) {
  const TetMesh block = kuhn_tets({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
  const std::vector<Vec3> guard{{1.0, 1.0, 0.5}};  // on the edge shared by the four cubes
  const StarResult result = star_decomposition(block, guard, {});
  EXPECT_EQ(result.moved_guards, 1u);
  EXPECT_FALSE(result.parts[0].added);
  expect_valid_partition(block, result);
  expect_star_shaped(block, result);
}

TEST(StarDecomposition, LAndUShapesSplitIntoOnePartPerGuard) {
  // Guards placed by hand where the known minimum needs them (guard_surface()'s own
  // tests check that it finds these minima): the L is star-shaped from a point of its
  // corner cube, the U from no point, but from one point in each bottom corner cube
  // (each sees its arm and the whole bottom bar).
  const std::vector<Cell> l_shape{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<Cell> u_shape{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {2, 1, 0}};
  const std::vector<Vec3> l_guards{{0.43, 0.52, 0.47}};
  const std::vector<Vec3> u_guards{{0.43, 0.52, 0.47}, {2.56, 0.48, 0.53}};
  for (const auto& [cells, guards] : {std::pair{l_shape, l_guards}, std::pair{u_shape, u_guards}}) {
    const TetMesh solid = solid_of(cells, 3, 0.25);
    StarOptions options;
    options.strict = true;
    const StarResult result = star_decomposition(solid, guards, options);
    expect_valid_partition(solid, result);
    expect_star_shaped(solid, result);
    EXPECT_EQ(result.parts.size(), guards.size()) << cells.size() << " cubes";
    EXPECT_DOUBLE_EQ(result.visible_fraction, 1.0);
    EXPECT_NEAR(total_volume(solid), double(cells.size()), 1e-9);
  }
}

TEST(StarDecomposition, StrictTorusPartsAreStarShaped) {
  const std::vector<Cell> ring = test::ring_cells();
  const TetMesh torus = solid_of(ring, 2, 0.35);
  const auto guards = guards_of(torus);
  StarOptions options;
  options.strict = true;
  const StarResult result = star_decomposition(torus, guards, options);
  expect_valid_partition(torus, result);
  expect_star_shaped(torus, result);
  expect_same_boundary_no_tet_flipped(torus, result);
  // A ring is not star-shaped, so at least 2 parts; the guards' parts are not dropped.
  EXPECT_GE(result.parts.size(), 2u);
  EXPECT_EQ(result.dropped_guards, 0u);
  for (const StarPart& part : result.parts) {
    EXPECT_TRUE(part.star_shaped);
    EXPECT_EQ(part.visible_vertices, part.vertices);
    TetMesh moved = torus;
    moved.points = result.points;
    EXPECT_EQ(kernel_violations(moved, result.tet_part, static_cast<Index>(&part - result.parts.data()), part.guard),
              0u);
  }
  EXPECT_DOUBLE_EQ(result.visible_fraction, 1.0);
}

TEST(StarDecomposition, StrictScrewdriverSeedsManyPartsInOneRound) {
  // The screwdriver of the data set at its mean edge (75k tets) with the five guards the
  // exact ILP chose for it once (fixed here: the skeleton is not repeatable). Its leftover
  // rounds seed several parts at once, and the repair of a later leftover moves points of
  // tets already in a part seeded earlier in the same round: the relocator read that
  // part's guard past the end of its list until 2026-12-05 (caught by the sanitizer
  // build's bounds checks, _GLIBCXX_ASSERTIONS).
  const TetMesh solid = data_solid("screwdriver.off");
  const std::vector<Vec3> guards = {{8.18970617890598e-05, 0.00039303782816527106, -0.0347693778557404},
                                    {-0.000605580337266727, -0.00029689466079487685, 0.04038220484594841},
                                    {-1.7480799867182395e-05, -0.00038033821575368237, 0.02185534852033241},
                                    {-0.0003683102701390497, -0.00023471744561961216, -0.005482731359515716},
                                    {0.006225498530894529, -0.0035623110859173642, -0.0386648889278702}};
  StarOptions options;
  options.strict = true;
  const StarResult result = star_decomposition(solid, guards, options);
  expect_valid_partition(solid, result);
  EXPECT_EQ(result.dropped_guards, 0u);
  std::size_t added = 0;
  for (const StarPart& part : result.parts) added += part.added;
  EXPECT_GT(added, 1u);
  EXPECT_GT(result.repaired_tets, 0u);
  for (Index part = 0; part < result.parts.size(); ++part)
    EXPECT_TRUE(result.parts[part].star_shaped) << "part " << part;
  EXPECT_EQ(faces_breaking_the_rule(solid, result), 0u);
  EXPECT_DOUBLE_EQ(result.visible_fraction, 1.0);
}

TEST(StarDecomposition, StrictRockerArmGrowsNoPartOverMovedPoints) {
  // The rocker arm of the data set at its mean edge (307k tets) with six guards the exact
  // ILP chose for it once (fixed here: the skeleton is not repeatable). A part seeded in a
  // leftover round queued its neighbours at once, the repair of a later leftover of the
  // same round moved their points, and the growth then took a queued tet whose face no
  // longer had the guard on its inner side: 269 of 270 parts were star-shaped until
  // 2026-12-05. The growth now checks a tet again when it leaves the queue.
  const TetMesh solid = data_solid("rocker-arm.obj");
  const std::vector<Vec3> guards = {{-0.010384185119778412, -0.064835892234098996, -0.0095212033955274066},
                                    {-0.024464311076412712, -0.071356912294896116, 0.17202410380813682},
                                    {0.013485156632160258, 0.080837948713105331, -0.36241518020708624},
                                    {0.012472568656966422, 0.18639271578198152, 0.36642817047406567},
                                    {-0.068799877210179938, 0.14378235434311831, 0.27397220760834279},
                                    {0.078151092303465994, 0.22262732748578773, 0.019311386462048136}};
  StarOptions options;
  options.strict = true;
  options.smoothing_iterations = 0;  // the failure came from the growth alone
  const StarResult result = star_decomposition(solid, guards, options);
  expect_valid_partition(solid, result);
  EXPECT_GT(result.parts.size(), 100u);
  for (Index part = 0; part < result.parts.size(); ++part)
    EXPECT_TRUE(result.parts[part].star_shaped) << "part " << part;
  EXPECT_EQ(faces_breaking_the_rule(solid, result), 0u);
}

TEST(StarDecomposition, SmoothingShrinksTheBordersAndKeepsPartsStarShaped) {
  const std::vector<Cell> ring = test::ring_cells();
  const TetMesh torus = solid_of(ring, 2, 0.3);
  const auto guards = guards_of(torus);
  StarOptions options;
  options.strict = true;
  options.smoothing_iterations = 10;
  const StarResult result = star_decomposition(torus, guards, options);
  EXPECT_GT(result.smoothed_vertices, 0u);
  EXPECT_LT(result.interface_area_after, result.interface_area_before);
  // The smoothed mesh: boundary points unchanged, no tet inverted or flat, parts star-shaped.
  TetMesh smoothed = torus;
  smoothed.points = result.points;
  expect_same_boundary_no_tet_flipped(torus, result);
  expect_valid_partition(smoothed, result);
  expect_star_shaped(smoothed, result);
  for (const StarPart& part : result.parts) EXPECT_TRUE(part.star_shaped);
}

TEST(StarDecomposition, WithoutGuardsEveryPartIsAddedAndStillStar) {
  const TetMesh l_solid = kuhn_tets({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  StarOptions options;
  options.strict = true;
  const StarResult result = star_decomposition(l_solid, {}, options);
  expect_valid_partition(l_solid, result);
  expect_star_shaped(l_solid, result);
  for (const StarPart& part : result.parts) EXPECT_TRUE(part.added);
  EXPECT_GE(result.growth_rounds, 1u);
}

TEST(StarDecomposition, KernelViolationsSeeANonStarPart) {
  // One part made of the whole U: the guard in one arm cannot see the other arm.
  const TetMesh u = kuhn_tets({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {2, 1, 0}});
  const std::vector<Index> all(u.tets.size(), 0);
  EXPECT_GT(kernel_violations(u, all, 0, Vec3(0.4, 1.6, 0.45)), 0u);
  EXPECT_GT(kernel_violations(u, all, 0, Vec3(1.4, 0.6, 0.45)), 0u);
  // A cube is star-shaped from any interior point, and from no outside one.
  const TetMesh cube = kuhn_tets({{0, 0, 0}});
  const std::vector<Index> one(cube.tets.size(), 0);
  EXPECT_EQ(kernel_violations(cube, one, 0, Vec3(0.3, 0.6, 0.45)), 0u);
  EXPECT_GT(kernel_violations(cube, one, 0, Vec3(1.3, 0.6, 0.45)), 0u);
}

TEST(StarDecomposition, RelaxedModeMergesSmallLeftoversAndReportsVisibility) {
  const std::vector<Cell> ring = test::ring_cells();
  const TetMesh torus = solid_of(ring, 2, 0.35);
  const auto guards = guards_of(torus);
  StarOptions strict, relaxed;
  strict.strict = true;
  relaxed.merge_max_tets = 1000000;  // every leftover that touches a part is merged
  relaxed.merge_max_violations = std::numeric_limits<std::size_t>::max();
  const StarResult a = star_decomposition(torus, guards, strict);
  const StarResult b = star_decomposition(torus, guards, relaxed);
  expect_valid_partition(torus, b);
  EXPECT_LE(b.parts.size(), a.parts.size());
  std::size_t vertices = 0, visible = 0;
  for (const StarPart& part : b.parts) {
    EXPECT_LE(part.visible_vertices, part.vertices);
    EXPECT_EQ(part.star_shaped, part.kernel_violations == 0);
    if (part.star_shaped) {
      EXPECT_EQ(part.visible_vertices, part.vertices);
    }
    vertices += part.vertices;
    visible += part.visible_vertices;
  }
  EXPECT_DOUBLE_EQ(b.visible_fraction, double(visible) / double(vertices));
  // Merging only what the vertex moves leave breaking the rule nowhere: every part is
  // star-shaped without --strict too.
  relaxed.merge_max_violations = 0;
  const StarResult c = star_decomposition(torus, guards, relaxed);
  expect_valid_partition(torus, c);
  for (const StarPart& part : c.parts) EXPECT_TRUE(part.star_shaped);
  EXPECT_DOUBLE_EQ(c.visible_fraction, 1.0);
}

TEST(StarDecomposition, BadInputIsRejected) {
  EXPECT_THROW(star_decomposition(TetMesh{}, {}, {}), InputError);
  TetMesh flat;
  flat.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  flat.tets = {{0, 1, 2, 3}};
  EXPECT_THROW(star_decomposition(flat, {}, {}), InputError);
  TetMesh out_of_range = kuhn_tets({{0, 0, 0}});
  out_of_range.tets[2][1] = 99;
  EXPECT_THROW(star_decomposition(out_of_range, {}, {}), InputError);
  // A copy of a tet on top of itself: three tets share its faces.
  TetMesh non_manifold = kuhn_tets({{0, 0, 0}, {1, 0, 0}});
  non_manifold.tets.push_back(non_manifold.tets[0]);
  EXPECT_THROW(star_decomposition(non_manifold, {}, {}), InputError);
  // An inverted tet: its apex mirrored through the shared face onto its neighbour's side.
  TetMesh inverted;
  inverted.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.2, 0.2, 0.5}};
  inverted.tets = {{0, 1, 2, 3}, {0, 1, 2, 4}};
  EXPECT_THROW(star_decomposition(inverted, {}, {}), InputError);
  // A guard outside the solid is dropped, not an error.
  const TetMesh cube = kuhn_tets({{0, 0, 0}});
  const std::vector<Vec3> outside{{5, 5, 5}};
  const StarResult result = star_decomposition(cube, outside, {});
  EXPECT_EQ(result.dropped_guards, 1u);
  expect_valid_partition(cube, result);
}

}  // namespace
}  // namespace structmesh
