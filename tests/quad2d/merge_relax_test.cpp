#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/quality.hpp"

#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cmath>
#include <map>

namespace structmesh {
namespace {

// Two unit squares side by side, each a structured n x n grid, with the separator
// x = 1 sampled once: a SampledPartition and the two paved parts built by hand.
struct TwoSquares {
  SampledPartition sampled;
  std::vector<PavedPart> parts;
  std::vector<std::vector<Index>> maps;
};

TwoSquares two_squares(int n) {
  TwoSquares s;
  const double h = 1.0 / n;
  std::map<std::pair<int, int>, Index> sample;  // (i, j) on the 2n x n lattice -> sample
  const auto sample_at = [&](int i, int j) {
    auto [it, added] = sample.try_emplace({i, j}, static_cast<Index>(s.sampled.points.size()));
    if (added) {
      s.sampled.points.emplace_back(i * h, j * h);
      const bool boundary = i == 0 || i == 2 * n || j == 0 || j == n;
      s.sampled.on_region_boundary.push_back(boundary ? 1 : 0);
      s.sampled.fixed.push_back(boundary ? 1 : 0);
    }
    return it->second;
  };
  for (int part = 0; part < 2; ++part) {
    const int i0 = part * n;
    std::vector<Index> loop;  // counter-clockwise around [i0, i0+n] x [0, n]
    for (int i = i0; i < i0 + n; ++i) loop.push_back(sample_at(i, 0));
    for (int j = 0; j < n; ++j) loop.push_back(sample_at(i0 + n, j));
    for (int i = i0 + n; i > i0; --i) loop.push_back(sample_at(i, n));
    for (int j = n; j > 0; --j) loop.push_back(sample_at(i0, j));
    s.sampled.part_loops.push_back({loop});
    PavedPart paved;
    std::map<std::pair<int, int>, Index> local;
    for (const Index g : loop) {
      const Vec2& p = s.sampled.points[g];
      local[{static_cast<int>(std::lround(p.x() / h)), static_cast<int>(std::lround(p.y() / h))}] =
          static_cast<Index>(paved.points.size());
      paved.points.push_back(p);
    }
    for (int j = 1; j < n; ++j)
      for (int i = i0 + 1; i < i0 + n; ++i) {
        local[{i, j}] = static_cast<Index>(paved.points.size());
        paved.points.emplace_back(i * h, j * h);
      }
    for (int j = 0; j < n; ++j)
      for (int i = i0; i < i0 + n; ++i)
        paved.quads.push_back({local[{i, j}], local[{i + 1, j}], local[{i + 1, j + 1}], local[{i, j + 1}]});
    s.parts.push_back(std::move(paved));
    s.maps.push_back(loop);
  }
  s.sampled.size = h;
  return s;
}

TEST(MergeParts, SharesSeparatorPointsAndConforms) {
  const TwoSquares s = two_squares(6);
  const MergedMesh merged = merge_parts(s.sampled, s.parts, s.maps);
  // (2n+1) x (n+1) lattice points, 2 n^2 quads, each point once.
  EXPECT_EQ(merged.mesh.points.size(), 13U * 7U);
  EXPECT_EQ(merged.mesh.quads.size(), 72U);
  const EdgeAdjacency edges = build_edges(merged.mesh);
  std::size_t boundary_edges = 0;
  for (std::size_t e = 0; e < edges.edges.size(); ++e) {
    const std::size_t uses = edges.edge_elements.row(e).size();
    ASSERT_TRUE(uses == 1 || uses == 2);
    boundary_edges += uses == 1;
  }
  EXPECT_EQ(boundary_edges, 2U * (12 + 6));
  EXPECT_EQ(std::count(merged.part_of_quad.begin(), merged.part_of_quad.end(), 1), 36);
  // The separator x = 1 minus its two ends on the boundary.
  EXPECT_EQ(std::count(merged.separator.begin(), merged.separator.end(), 1), 5);
  const QuadQuality quality = quad_quality(merged.mesh);
  EXPECT_EQ(quality.singular_vertices, 0U);
  EXPECT_DOUBLE_EQ(quality.scaled_jacobian_stats.min, 1.0);
}

TEST(MergeParts, RejectsMismatchedInput) {
  TwoSquares s = two_squares(2);
  std::vector<PavedPart> one(s.parts.begin(), s.parts.begin() + 1);
  EXPECT_THROW(merge_parts(s.sampled, one, s.maps), InputError);
  s.parts[0].quads[0][0] = 999;
  EXPECT_THROW(merge_parts(s.sampled, s.parts, s.maps), Error);
}

TEST(QuadMeshArea, IsTheRegionAreaAndTheSameBitsOnOneAndTwoThreads) {
  // A 400 x 300 grid of a 4 x 3 rectangle with its interior points moved inside
  // their cells: the quads tile the rectangle, so their areas sum to 12 whatever the
  // perturbation, and the parallel sum must not depend on the thread count.
  const int nx = 400, ny = 300;
  QuadMesh mesh;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const bool inside = i > 0 && i < nx && j > 0 && j < ny;
      const double dx = inside ? 0.3 * std::sin(1.7 * i + 0.3 * j) : 0.0;
      const double dy = inside ? 0.3 * std::cos(0.9 * i - 1.1 * j) : 0.0;
      mesh.points.emplace_back((i + dx) * 4.0 / nx, (j + dy) * 3.0 / ny, 0.0);
    }
  const auto at = [&](int i, int j) { return static_cast<Index>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) mesh.quads.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
  double one = 0, two = 0;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = quad_mesh_area(mesh);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = quad_mesh_area(mesh);
  }
  EXPECT_NEAR(one, 12.0, 1e-9);
  EXPECT_EQ(one, two);  // bit-identical, not merely close
}

// A deterministic perturbation of the interior points near the separator.
void perturb(MergedMesh& merged, double amount) {
  for (std::size_t i = 0; i < merged.mesh.points.size(); ++i) {
    if (merged.fixed[i]) continue;
    merged.mesh.points[i].x() += amount * std::sin(12.9898 * static_cast<double>(i));
    merged.mesh.points[i].y() += amount * std::cos(78.233 * static_cast<double>(i));
  }
}

TEST(RelaxNearSeparators, RestoresAPerturbedGridAndNeverMovesTheBoundary) {
  const TwoSquares s = two_squares(8);
  const MergedMesh exact = merge_parts(s.sampled, s.parts, s.maps);
  MergedMesh merged = exact;
  perturb(merged, 0.3 / 8);
  ASSERT_EQ(quad_quality(merged.mesh).inverted, 0U);
  double before = 0, after = 0;
  for (std::size_t i = 0; i < exact.mesh.points.size(); ++i)
    before = std::max(before, (merged.mesh.points[i] - exact.mesh.points[i]).norm());
  const RelaxStats stats = relax_near_separators(merged, {.rings = 8, .iterations = 200});
  for (std::size_t i = 0; i < exact.mesh.points.size(); ++i) {
    if (exact.fixed[i]) {
      EXPECT_EQ(merged.mesh.points[i], exact.mesh.points[i]);
    }
    after = std::max(after, (merged.mesh.points[i] - exact.mesh.points[i]).norm());
  }
  // Every interior point is within 8 rings of x = 1 on a 16 x 8 grid: all move, and
  // the Laplacian fixed point of a structured grid is the uniform grid.
  EXPECT_EQ(stats.moved_vertices, 15U * 7U);
  EXPECT_LT(after, 1e-3 * before);
  EXPECT_EQ(quad_quality(merged.mesh).inverted, 0U);
}

TEST(RelaxNearSeparators, MovesOnlyTheRingsAroundTheSeparator) {
  const TwoSquares s = two_squares(12);
  MergedMesh merged = merge_parts(s.sampled, s.parts, s.maps);
  perturb(merged, 0.2 / 12);
  const MergedMesh perturbed = merged;
  relax_near_separators(merged, {.rings = 2, .iterations = 50});
  for (std::size_t i = 0; i < merged.mesh.points.size(); ++i) {
    const double column = std::abs(perturbed.mesh.points[i].x() - 1.0) * 12;
    if (column > 3) {
      EXPECT_EQ(merged.mesh.points[i], perturbed.mesh.points[i]) << i;
    }
  }
}

TEST(RelaxNearSeparators, NeverInvertsAndIsIdenticalForOneAndTwoThreads) {
  const TwoSquares s = two_squares(10);
  MergedMesh one = merge_parts(s.sampled, s.parts, s.maps);
  perturb(one, 0.3 / 10);
  ASSERT_EQ(quad_quality(one.mesh).inverted, 0U);
  MergedMesh two = one;
  {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
    relax_near_separators(one);
  }
  {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
    relax_near_separators(two);
  }
  EXPECT_EQ(one.mesh.points, two.mesh.points);
  EXPECT_EQ(quad_quality(one.mesh).inverted, 0U);
}

TEST(RelaxNearSeparators, RejectsBadOptions) {
  const TwoSquares s = two_squares(2);
  MergedMesh merged = merge_parts(s.sampled, s.parts, s.maps);
  EXPECT_THROW(relax_near_separators(merged, {.rings = -1}), InputError);
  merged.fixed.pop_back();
  EXPECT_THROW(relax_near_separators(merged), InputError);
}

}  // namespace
}  // namespace structmesh
