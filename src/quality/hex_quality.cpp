// Hex mesh quality of §5.3 (Table 5.2): scaled Jacobian (Verdict's 9 samples and
// the dissertation's 8 corners), dihedral angles, and N_h, the number of interior
// vertices with valence != 6 plus boundary vertices with boundary valence != 4.
#include "structmesh/quality.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace structmesh {

namespace {

// Per-hex summary of its 12 dihedral angles (degrees), merged afterwards in hex
// order with Chan et al.'s pairwise update, so the result does not depend on how
// TBB split the loop.
struct AngleSummary {
  std::size_t count = 0;
  double mean = 0, m2 = 0;  // m2 = sum of squared deviations from mean
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
};

AngleSummary summarize(const std::array<double, 12>& radians) {
  AngleSummary s;
  double sum = 0;
  std::array<double, 12> degrees{};
  for (std::size_t k = 0; k < radians.size(); ++k) {
    degrees[k] = radians[k] * (180.0 / std::numbers::pi);
    if (std::isnan(degrees[k])) continue;
    ++s.count;
    sum += degrees[k];
    s.min = std::min(s.min, degrees[k]);
    s.max = std::max(s.max, degrees[k]);
  }
  if (s.count == 0) return s;
  s.mean = sum / static_cast<double>(s.count);
  for (double d : degrees)
    if (!std::isnan(d)) s.m2 += (d - s.mean) * (d - s.mean);
  return s;
}

void merge(AngleSummary& total, const AngleSummary& part) {
  if (part.count == 0) return;
  const double n = static_cast<double>(total.count + part.count);
  const double delta = part.mean - total.mean;
  total.mean += delta * static_cast<double>(part.count) / n;
  total.m2 += part.m2 + delta * delta * static_cast<double>(total.count) * static_cast<double>(part.count) / n;
  total.count += part.count;
  total.min = std::min(total.min, part.min);
  total.max = std::max(total.max, part.max);
}

struct SingularCounts {
  std::size_t interior = 0, boundary = 0;
};

// N_h of Table 5.2. The boundary is the set of faces with exactly one hex (faces
// shared by three or more hexes are not boundary); a boundary vertex's valence is
// its number of boundary edges (4 on a smooth part of a structured surface), an
// interior vertex's its number of edges (6 inside a structured block).
SingularCounts count_singular_vertices(const HexMesh& mesh) {
  const std::size_t n = mesh.points.size();
  std::vector<char> used(n, 0), on_boundary(n, 0);
  for (const auto& h : mesh.hexes)
    for (Index v : h) used[v] = 1;

  const FaceAdjacency<4> faces = build_faces(mesh);
  std::vector<char> shared(faces.faces.size(), 0);
  for (Index f : faces.extra_faces) shared[f] = 1;
  std::vector<std::array<Index, 2>> boundary_edges;
  for (std::size_t f = 0; f < faces.faces.size(); ++f) {
    if (faces.face_cells[f][1] != kInvalidIndex || shared[f]) continue;
    const auto& face = faces.faces[f];
    for (int i = 0; i < 4; ++i) {
      const Index a = face[i], b = face[(i + 1) % 4];
      on_boundary[a] = 1;
      if (a != b) boundary_edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(boundary_edges.begin(), boundary_edges.end());
  boundary_edges.erase(std::unique(boundary_edges.begin(), boundary_edges.end()), boundary_edges.end());
  std::vector<Index> boundary_valence(n, 0);
  for (const auto& [a, b] : boundary_edges) {
    ++boundary_valence[a];
    ++boundary_valence[b];
  }

  const EdgeAdjacency edges = build_edges(mesh);
  std::vector<Index> valence(n, 0);
  for (const auto& [a, b] : edges.edges) {
    ++valence[a];
    ++valence[b];
  }

  SingularCounts counts;
  for (std::size_t v = 0; v < n; ++v) {
    if (!used[v]) continue;
    if (on_boundary[v])
      counts.boundary += boundary_valence[v] != 4 ? 1 : 0;
    else
      counts.interior += valence[v] != 6 ? 1 : 0;
  }
  return counts;
}

}  // namespace

HexQuality hex_quality(const HexMesh& mesh) {
  const std::size_t n = mesh.hexes.size();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  HexQuality quality;
  quality.scaled_jacobian.resize(n);
  quality.corner_scaled_jacobian.resize(n);
  std::vector<AngleSummary> angles(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 512), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      std::array<Vec3, 8> corners;
      for (int k = 0; k < 8; ++k) corners[k] = mesh.points[mesh.hexes[i][k]];
      const std::optional<double> sj = hex_scaled_jacobian(corners);
      quality.scaled_jacobian[i] = sj.value_or(kNaN);
      quality.corner_scaled_jacobian[i] = hex_corner_scaled_jacobian(corners).value_or(kNaN);
      if (sj) angles[i] = summarize(hex_dihedral_angles(corners));
    }
  });

  quality.scaled_jacobian_stats = statistics(quality.scaled_jacobian);
  quality.corner_scaled_jacobian_stats = statistics(quality.corner_scaled_jacobian);
  quality.scaled_jacobian_histogram = histogram(quality.scaled_jacobian, -1.0, 1.0, 20);
  for (double s : quality.scaled_jacobian) {
    if (std::isnan(s))
      ++quality.invalid;
    else if (s <= 0)
      ++quality.inverted;
  }

  AngleSummary total;
  for (const AngleSummary& a : angles) merge(total, a);
  if (total.count > 0)
    quality.dihedral_degrees = {total.count, total.min, total.max, total.mean,
                                std::sqrt(total.m2 / static_cast<double>(total.count))};

  const SingularCounts singular = count_singular_vertices(mesh);
  quality.singular_interior = singular.interior;
  quality.singular_boundary = singular.boundary;
  quality.singular_vertices = singular.interior + singular.boundary;
  return quality;
}

}  // namespace structmesh
