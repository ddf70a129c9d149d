#include "guard/shapes.hpp"
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <gtest/gtest.h>
#include <Eigen/Geometry>

namespace structmesh {
namespace {

using test::voxel_surface;

// Independent exact check: v is seen from p when the segment p-v meets no face that
// does not contain v (exact predicates, no tolerance).
bool exact_sees(const TriMesh& mesh, const Vec3& p, Index v) {
  using K = CGAL::Exact_predicates_exact_constructions_kernel;
  const auto point = [](const Vec3& x) { return K::Point_3(x.x(), x.y(), x.z()); };
  const K::Segment_3 segment(point(p), point(mesh.points[v]));
  for (const auto& t : mesh.triangles) {
    if (t[0] == v || t[1] == v || t[2] == v) continue;
    if (CGAL::do_intersect(segment,
                           K::Triangle_3(point(mesh.points[t[0]]), point(mesh.points[t[1]]), point(mesh.points[t[2]]))))
      return false;
  }
  return true;
}

void expect_every_face_seen_exactly(const TriMesh& mesh, const GuardResult& result) {
  ASSERT_EQ(result.face_guard.size(), mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Index g = result.face_guard[f];
    ASSERT_LT(g, result.guards.size()) << "face " << f << " has no guard";
    for (const Index v : mesh.triangles[f])
      EXPECT_TRUE(exact_sees(mesh, result.guards[g].position, v)) << "face " << f << " vertex " << v;
  }
}

TEST(VoxelSurface, ClosedOutwardWithTheCellVolume) {
  const TriMesh u = voxel_surface({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {2, 1, 0}}, 2);
  EXPECT_NEAR(enclosed_volume(u), 5.0, 1e-12);
}

TEST(GuardSurface, ConvexCubeNeedsOneGuard) {
  const TriMesh cube = voxel_surface({{0, 0, 0}}, 6);
  for (const GuardMethod method : {GuardMethod::Greedy, GuardMethod::Ilp}) {
    GuardOptions options;
    options.method = method;
    const GuardResult result = guard_surface(cube, options);
    EXPECT_EQ(result.guards.size(), 1u);
    EXPECT_EQ(result.uncovered_faces, 0u);
    expect_every_face_seen_exactly(cube, result);
  }
}

TEST(GuardSurface, LShapeIsStarShapedAndNeedsOne) {
  // An L of three cubes (a 2D L extruded by one): the corner cube sees everything.
  const TriMesh l_shape = voxel_surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 4);
  const GuardResult result = guard_surface(l_shape);
  EXPECT_EQ(result.uncovered_faces, 0u);
  EXPECT_EQ(result.guards.size(), 1u);
  EXPECT_TRUE(result.optimal);
  expect_every_face_seen_exactly(l_shape, result);
}

TEST(GuardSurface, KernelRoundsReplaceTwoGuardsByOneInTheirFacesKernel) {
  // The L of LShapeIsStarShaped with two given candidates near the tips of its arms: each
  // misses the far end of the other arm (the segment passes outside the reflex edge), so
  // over them alone the cover needs both. The faces only they see have the corner cube as
  // the kernel of their inner half-spaces: the kernel round's point there sees everything.
  const TriMesh l_shape = voxel_surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 4);
  for (const GuardMethod method : {GuardMethod::Ilp, GuardMethod::Pilp}) {
    GuardOptions options;
    options.method = method;
    options.candidates = {Vec3(1.8, 0.5, 0.5), Vec3(0.5, 1.8, 0.5)};
    options.refine_seconds = 0;
    const GuardResult without = guard_surface(l_shape, options);
    EXPECT_EQ(without.uncovered_faces, 0u);
    EXPECT_EQ(without.kernel_candidates, 0u);
    ASSERT_EQ(without.guards.size(), 2u);

    options.refine_seconds = 30;
    const GuardResult result = guard_surface(l_shape, options);
    EXPECT_EQ(result.uncovered_faces, 0u);
    EXPECT_EQ(result.guards_before_refinement, 2u);
    EXPECT_GT(result.kernel_candidates, 0u);
    ASSERT_EQ(result.guards.size(), 1u);
    EXPECT_EQ(result.refinement_rounds, 1u);
    const Vec3& guard = result.guards[0].position;
    EXPECT_TRUE((guard.array() >= 0).all() && (guard.array() <= 1).all()) << guard.transpose();
    expect_every_face_seen_exactly(l_shape, result);
    if (method == GuardMethod::Ilp) {
      EXPECT_TRUE(result.optimal);
      EXPECT_TRUE(result.refined_optimal);
    }
    // The greedy cover over the same candidates (kernel ones included) takes the kernel
    // point as well: it sees every face.
    EXPECT_EQ(result.greedy_guards, 1u);
    EXPECT_EQ(result.greedy_guards_before_refinement, 2u);
  }
}

TEST(GuardSurface, KernelRoundsWorkFarFromTheOriginAndAtAnyScale) {
  // The same L in millimetres, 5 km from the origin (UTM-like coordinates): the LPs see
  // the same kernel.
  TriMesh l_shape = voxel_surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 4);
  const Vec3 offset(5.0e6, -4.0e6, 3.0e5);
  constexpr double kScale = 1000;
  for (Vec3& p : l_shape.points) p = offset + kScale * p;
  GuardOptions options;
  options.candidates = {offset + kScale * Vec3(1.8, 0.5, 0.5), offset + kScale * Vec3(0.5, 1.8, 0.5)};
  options.refine_seconds = 30;
  const GuardResult result = guard_surface(l_shape, options);
  EXPECT_EQ(result.uncovered_faces, 0u);
  EXPECT_EQ(result.guards_before_refinement, 2u);
  ASSERT_EQ(result.guards.size(), 1u);
  const Vec3 local = (result.guards[0].position - offset) / kScale;
  EXPECT_TRUE((local.array() >= 0).all() && (local.array() <= 1).all()) << local.transpose();
  expect_every_face_seen_exactly(l_shape, result);
}

TEST(GuardSurface, UShapeNeedsTwoAndIlpIsNoWorseThanGreedy) {
  // A U of seven cubes, prongs three long: no point sees the tops of both prongs.
  const TriMesh u_shape =
      voxel_surface({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 2, 0}, {2, 1, 0}, {2, 2, 0}}, 3);
  const GuardResult result = guard_surface(u_shape);
  EXPECT_EQ(result.uncovered_faces, 0u);
  EXPECT_EQ(result.guards.size(), 2u);
  EXPECT_TRUE(result.optimal);
  EXPECT_LE(result.guards.size(), result.greedy_guards);
  expect_every_face_seen_exactly(u_shape, result);
  // The two guards' face sets meet: one edge in the guard graph.
  EXPECT_EQ(result.graph.size(), 1u);
}

TEST(GuardSurface, ExtraCandidatesCoverWhatTheGivenOnesMissInRounds) {
  // The U of UShapeNeedsTwo with one given candidate, inside the left prong's top cube:
  // it cannot see the right prong. The extra candidates near the unseen faces' vertices
  // must cover them, added in rounds: fewer than one point per such vertex (all at once,
  // each would get three).
  const TriMesh u_shape =
      voxel_surface({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 2, 0}, {2, 1, 0}, {2, 2, 0}}, 3);
  const Vec3 given(0.5, 2.5, 0.5);
  const VisibilityOracle oracle(u_shape);
  const CompressedRows seen_from_given = visible_faces(oracle, u_shape, std::span<const Vec3>(&given, 1));
  std::vector<std::uint8_t> seen(u_shape.triangles.size(), 0), open(u_shape.points.size(), 0);
  for (const Index f : seen_from_given.items) seen[f] = 1;
  std::size_t open_vertices = 0;
  for (std::size_t f = 0; f < u_shape.triangles.size(); ++f)
    if (!seen[f])
      for (const Index v : u_shape.triangles[f]) open_vertices += open[v] == 0, open[v] = 1;
  ASSERT_GT(open_vertices, 50u);

  GuardOptions options;
  options.candidates = {given};
  const GuardResult result = guard_surface(u_shape, options);
  EXPECT_EQ(result.uncovered_faces, 0u);
  expect_every_face_seen_exactly(u_shape, result);
  EXPECT_EQ(result.candidates, 1 + result.added_candidates);
  EXPECT_GT(result.added_candidates, 0u);
  EXPECT_LT(result.added_candidates, open_vertices);
  EXPECT_TRUE(result.optimal);
  EXPECT_EQ(result.guards.size(), 2u);
}

TEST(GuardSurface, ProgressiveIlpCoversEveryFaceThroughItsLevels) {
  // A ring of 12 cubes (a torus of genus 1) at 1,152 vertices, with levels of 300, 600
  // and 900 vertices before the input, so every level runs.
  const TriMesh torus = voxel_surface(test::ring_cells(), 4);
  GuardOptions options;
  options.method = GuardMethod::Pilp;
  options.pilp_coarsest_vertices = 300;
  options.pilp_level_step = 300;
  const GuardResult pilp = guard_surface(torus, options);
  EXPECT_EQ(pilp.uncovered_faces, 0u);
  expect_every_face_seen_exactly(torus, pilp);
  ASSERT_GE(pilp.levels.size(), 2u);
  EXPECT_LE(pilp.levels.front().vertices, 400u);
  EXPECT_EQ(pilp.levels.back().vertices, torus.points.size());
  for (std::size_t i = 1; i < pilp.levels.size(); ++i) EXPECT_GT(pilp.levels[i].vertices, pilp.levels[i - 1].vertices);
  for (const PilpLevel& level : pilp.levels) {
    EXPECT_EQ(level.guards, level.kept + level.added);
    EXPECT_LE(level.universe, level.faces);
  }
  EXPECT_EQ(pilp.guards_before_refinement + pilp.pilp_pruned + pilp.pilp_exchanges, pilp.levels.back().guards);
  // The kernel rounds after it only lower the count, by what their exchanges saved.
  EXPECT_EQ(pilp.guards.size() + pilp.refinement_exchanges, pilp.guards_before_refinement);
  EXPECT_FALSE(pilp.optimal);  // PILP proves nothing about the whole
  // Against the exact optimum on the same candidates (before the kernel rounds, which
  // add candidates of their own): no better, and at most greedy.
  options.method = GuardMethod::Ilp;
  options.candidates = pilp.candidate_points;
  const GuardResult ilp = guard_surface(torus, options);
  ASSERT_TRUE(ilp.optimal);
  EXPECT_EQ(ilp.candidates, pilp.candidates);
  EXPECT_GE(pilp.guards_before_refinement, ilp.guards_before_refinement);
  EXPECT_LE(pilp.guards_before_refinement, pilp.greedy_guards_before_refinement + 1);
  EXPECT_LE(ilp.guards.size(), ilp.guards_before_refinement);
  EXPECT_LE(pilp.guards.size(), pilp.guards_before_refinement);
}

TEST(GuardSurface, SelfIntersectingSurfaceOnlyWhenAllowed) {
  // Two unit cubes overlapping by half along each axis: closed, manifold, outward, but
  // their surfaces cross.
  TriMesh both = voxel_surface({{0, 0, 0}}, 2);
  const TriMesh second = voxel_surface({{0, 0, 0}}, 2);
  const auto offset = static_cast<Index>(both.points.size());
  for (const Vec3& p : second.points) both.points.push_back(p + Vec3(0.5, 0.5, 0.5));
  for (const auto& t : second.triangles) both.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  try {
    guard_surface(both);
    FAIL() << "a self-intersecting surface was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("self-intersecting"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--repair"), std::string::npos) << e.what();
  }
  GuardOptions options;
  options.allow_self_intersections = true;
  const GuardResult result = guard_surface(both, options);
  EXPECT_GT(result.self_intersections, 0u);
  EXPECT_GE(result.guards.size(), 1u);
  for (std::size_t f = 0; f < both.triangles.size(); ++f)
    if (result.face_guard[f] != kInvalidIndex) {
      const auto& faces = result.guards[result.face_guard[f]].faces;
      EXPECT_TRUE(std::binary_search(faces.begin(), faces.end(), static_cast<Index>(f)));
    }
}

TEST(GuardSurface, BadSurfacesAreRejectedWithTheReason) {
  TriMesh open = voxel_surface({{0, 0, 0}}, 2);
  open.triangles.pop_back();
  try {
    guard_surface(open);
    FAIL() << "an open surface was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("open"), std::string::npos) << e.what();
  }
  TriMesh inward = voxel_surface({{0, 0, 0}}, 2);
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  try {
    guard_surface(inward);
    FAIL() << "an inward surface was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("inward"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace structmesh
