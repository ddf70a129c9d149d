// mapped_mesh(): structured all-quad grid of a four-sided part (opposite sides with
// equal point counts), the cheap alternative to paving (pave()) for such parts.
// Transfinite interpolation of the sides (Gordon & Hall 1973) gives the
// initial grid; Winslow's elliptic smoothing (Winslow 1967; Thompson, Warsi & Mastin,
// "Numerical Grid Generation", 1985) removes its kinks; it makes the computational
// coordinates harmonic functions of the physical ones, a one-to-one map in the
// continuum (Rado's theorem), though the discrete grid can still fold next to a
// reentrant corner of a side. So the result is accepted only if every quad's scaled
// Jacobian (+z reference) reaches the threshold, if need be after the best grid is
// polished as a whole (polish_quads()); otherwise the caller paves.
#include "quad2d/mapped_mesh.hpp"
#include "quad2d/paving.hpp"
#include "quad2d/untangle_quads.hpp"

#include "structmesh/error.hpp"
#include "structmesh/quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>

namespace structmesh {

namespace mapped {

namespace {

/// Normalised arc length of the grid nodes first, first + step, ... (count nodes):
/// 0 at the first, 1 at the last. InputError when the side has zero length.
std::vector<double> arc_parameters(const StructuredGrid& grid, std::size_t first, std::size_t step, std::size_t count,
                                   const char* side) {
  std::vector<double> s(count, 0.0);
  for (std::size_t k = 1; k < count; ++k) {
    const std::size_t a = first + (k - 1) * step, b = a + step;
    s[k] = s[k - 1] + std::hypot(grid.x[b] - grid.x[a], grid.y[b] - grid.y[a]);
  }
  const double total = s.back();
  if (!(total > 0)) throw InputError(std::string("mapped_mesh: the ") + side + " side has zero length");
  for (double& v : s) v /= total;
  s.back() = 1.0;
  return s;
}

struct Box {
  double xmin, xmax, ymin, ymax;
};

/// The boundary nodes' bounding box grown by its diagonal: a node outside has run away.
Box escape_box(const StructuredGrid& grid) {
  Box b{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (std::size_t k = 0; k < grid.x.size(); ++k) {
    if (grid.loop_index[k] == kInvalidIndex) continue;
    b.xmin = std::min(b.xmin, grid.x[k]);
    b.xmax = std::max(b.xmax, grid.x[k]);
    b.ymin = std::min(b.ymin, grid.y[k]);
    b.ymax = std::max(b.ymax, grid.y[k]);
  }
  const double d = std::hypot(b.xmax - b.xmin, b.ymax - b.ymin);
  return {b.xmin - d, b.xmax + d, b.ymin - d, b.ymax + d};
}

// Successive over-relaxation of the Gauss-Seidel sweeps. The large grids of the Key at
// 2M quads (up to 316 x 136) still moved points by 4% of an edge per sweep after 150
// plain sweeps; with 1.8, 60 sweeps give a smoother grid (average scaled Jacobian
// 0.9918 instead of 0.9910 after 200 plain sweeps) in less than a third of the work.
// A sweep that diverges ends in the escape box and the next attempt takes over.
constexpr double kOverRelaxation = 1.8;

/// Over-relaxed Gauss-Seidel sweeps over the interior with `update(i, j, k, w, x, y) -> (x', y')`
/// (k = node(i, j), w = ni + 1); a node
/// that comes out non-finite or outside the escape box ends the sweeps as Diverged.
template <class Update>
Smoothing sweep(StructuredGrid& grid, int iterations, double tolerance, Update update) {
  if (grid.ni < 2 || grid.nj < 2) return Smoothing::Converged;
  const Box box = escape_box(grid);
  const std::size_t w = grid.ni + 1;
  double* x = grid.x.data();
  double* y = grid.y.data();
  for (int it = 0; it < iterations; ++it) {
    double largest = 0;
    for (std::size_t j = 1; j < grid.nj; ++j) {
      for (std::size_t i = 1, k = j * w + 1; i < grid.ni; ++i, ++k) {
        auto [nx, ny] = update(i, j, k, w, x, y);
        nx = x[k] + kOverRelaxation * (nx - x[k]);
        ny = y[k] + kOverRelaxation * (ny - y[k]);
        if (!(nx >= box.xmin && nx <= box.xmax && ny >= box.ymin && ny <= box.ymax)) return Smoothing::Diverged;
        largest = std::max(largest, std::max(std::abs(nx - x[k]), std::abs(ny - y[k])));
        x[k] = nx;
        y[k] = ny;
      }
    }
    if (largest < tolerance) return Smoothing::Converged;
  }
  return Smoothing::IterationLimit;
}

/// False when no grid on this loop can give every quad a scaled Jacobian of at least
/// `threshold`, whatever its interior points: a planar quad's scaled Jacobian is the
/// smallest sine of its corner angles, so each corner angle must lie in [a, pi - a]
/// with a = asin(threshold), and a loop point with k quads of the grid (1 at the four
/// corners, 2 elsewhere) splits its interior angle into k of them. Smoothing and the
/// polish move interior points only, so such a part would fail all of them: the check
/// spares their cost and changes no mesh (3 of the Gulf's parts in 1024, 1 of the Key's
/// in 64 at 2M quads).
bool corner_angles_can_reach(std::span<const Vec2> ring, const std::array<std::size_t, 4>& corners, double threshold) {
  if (!(threshold > 0)) return true;
  const double smallest = std::asin(std::min(threshold, 1.0)), largest = std::numbers::pi - smallest;
  constexpr double kSlack = 1e-9;  // radians: only a clear violation rules the grid out
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    // The interior angle of a counter-clockwise loop at point i (as the paver measures it).
    const double angle = paving::ccw_angle(ring[(i + 1) % n] - ring[i], ring[(i + n - 1) % n] - ring[i]);
    const double quads = std::find(corners.begin(), corners.end(), i) != corners.end() ? 1.0 : 2.0;
    if (angle < quads * smallest - kSlack || angle > quads * largest + kSlack) return false;
  }
  return true;
}

struct Point {
  double x, y;
};

/// A grid of more quads than this that misses the threshold after its first smoothing
/// goes straight to the polish: the other two smoothings (without control functions,
/// Laplacian) cost as much again each and did not rescue any such grid on the Gulf at
/// 20M quads in 40 parts, where four parts of 500k quads spent 1.7 s each on three
/// attempts before they were paved (a worst quad of 0.33, 0.33 and 0.24 after them,
/// at a bend of a side). Smaller grids keep all three (Table 3.4's parts).
constexpr std::size_t kRetryMaxQuads = 100000;

}  // namespace

StructuredGrid transfinite_grid(const Polygon2& boundary, const std::array<std::size_t, 4>& corners) {
  if (boundary.ring_count() == 0) throw InputError("mapped_mesh: the part has no boundary loop");
  if (boundary.ring_count() > 1)
    throw InputError("mapped_mesh: the part has " + std::to_string(boundary.hole_count()) +
                     " hole(s); a mapped mesh needs a single loop");
  const auto ring = boundary.ring(0);
  const std::size_t n = ring.size();
  if (n < 4) throw InputError("mapped_mesh: the loop has " + std::to_string(n) + " points; four corners need 4");
  if (!(corners[0] < corners[1] && corners[1] < corners[2] && corners[2] < corners[3]))
    throw InputError("mapped_mesh: the corners must be strictly increasing loop positions");
  if (corners[3] >= n)
    throw InputError("mapped_mesh: corner position " + std::to_string(corners[3]) + " is outside the loop of " +
                     std::to_string(n) + " points");
  const std::size_t ni = corners[1] - corners[0], nj = corners[2] - corners[1];
  if (corners[3] - corners[2] != ni || n - corners[3] + corners[0] != nj)
    throw InputError("mapped_mesh: opposite sides differ in segment count (" + std::to_string(ni) + " and " +
                     std::to_string(corners[3] - corners[2]) + ", " + std::to_string(nj) + " and " +
                     std::to_string(n - corners[3] + corners[0]) + ")");
  for (const Vec2& p : ring)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()))
      throw InputError("mapped_mesh: the loop has a non-finite point");
  if (!(signed_area(ring) > 0)) throw InputError("mapped_mesh: the loop (ring 0) must be counter-clockwise");
  const std::size_t nodes = (ni + 1) * (nj + 1);
  if (nodes >= kInvalidIndex) throw InputError("mapped_mesh: the grid has too many points");

  StructuredGrid g;
  g.ni = ni;
  g.nj = nj;
  g.x.assign(nodes, 0.0);
  g.y.assign(nodes, 0.0);
  g.loop_index.assign(nodes, kInvalidIndex);
  const auto set = [&](std::size_t i, std::size_t j, std::size_t loop) {
    const std::size_t k = g.node(i, j);
    g.loop_index[k] = static_cast<Index>(boundary.ring_offsets[0] + loop);
    g.x[k] = ring[loop].x();
    g.y[k] = ring[loop].y();
  };
  for (std::size_t i = 0; i <= ni; ++i) {
    set(i, 0, corners[0] + i);   // corners[0] -> corners[1]
    set(i, nj, corners[3] - i);  // corners[3] -> corners[2], run backwards
  }
  for (std::size_t j = 0; j <= nj; ++j) {
    set(ni, j, corners[1] + j);           // corners[1] -> corners[2]
    set(0, j, (corners[0] + n - j) % n);  // corners[0] -> corners[3] backwards, across the loop's start
  }

  const std::size_t step_i = 1, step_j = ni + 1;
  const std::vector<double> ub = arc_parameters(g, g.node(0, 0), step_i, ni + 1, "first");
  const std::vector<double> vr = arc_parameters(g, g.node(ni, 0), step_j, nj + 1, "second");
  const std::vector<double> ut = arc_parameters(g, g.node(0, nj), step_i, ni + 1, "third");
  const std::vector<double> vl = arc_parameters(g, g.node(0, 0), step_j, nj + 1, "fourth");
  const auto at = [&](std::size_t i, std::size_t j) { return Point{g.x[g.node(i, j)], g.y[g.node(i, j)]}; };
  const Point p00 = at(0, 0), p10 = at(ni, 0), p11 = at(ni, nj), p01 = at(0, nj);
  for (std::size_t j = 1; j < nj; ++j) {
    const Point l = at(0, j), r = at(ni, j);
    for (std::size_t i = 1; i < ni; ++i) {
      // (u, v) where the line from bottom to top parameter meets the one from left to
      // right parameter: with arc-length parameters that
      // differ between opposite sides, u varies with v and v with u.
      const double du = ut[i] - ub[i], dv = vr[j] - vl[j];
      const double u = (ub[i] + vl[j] * du) / (1 - du * dv);
      const double v = vl[j] + u * dv;
      const Point b = at(i, 0), t = at(i, nj);
      const auto blend = [&](double Point::*c) {
        return (1 - v) * b.*c + v * t.*c + (1 - u) * l.*c + u * r.*c -
               ((1 - u) * (1 - v) * p00.*c + u * (1 - v) * p10.*c + u * v * p11.*c + (1 - u) * v * p01.*c);
      };
      const std::size_t k = g.node(i, j);
      g.x[k] = blend(&Point::x);
      g.y[k] = blend(&Point::y);
    }
  }
  return g;
}

Smoothing winslow_smooth(StructuredGrid& grid, int iterations, double tolerance, bool control_functions) {
  const std::size_t ni = grid.ni, nj = grid.nj, w = ni + 1;
  // Thomas & Middlecoff (1980) control functions: phi on the two sides along i and psi
  // on the two along j, -(r_s . r_ss) / |r_s|^2 of the boundary spacing, interpolated
  // linearly across; with them a grid line spacing of the boundary carries into the
  // interior instead of being evened out.
  std::vector<double> phi(2 * (ni + 1), 0.0), psi(2 * (nj + 1), 0.0);
  const auto stretching = [&](std::size_t k, std::size_t step) {
    const double xs = 0.5 * (grid.x[k + step] - grid.x[k - step]), ys = 0.5 * (grid.y[k + step] - grid.y[k - step]);
    const double xss = grid.x[k + step] - 2 * grid.x[k] + grid.x[k - step];
    const double yss = grid.y[k + step] - 2 * grid.y[k] + grid.y[k - step];
    const double length2 = xs * xs + ys * ys;
    return length2 > 0 ? -(xs * xss + ys * yss) / length2 : 0.0;
  };
  if (control_functions) {
    for (std::size_t i = 1; i < ni; ++i) {
      phi[i] = stretching(grid.node(i, 0), 1);
      phi[ni + 1 + i] = stretching(grid.node(i, nj), 1);
    }
    for (std::size_t j = 1; j < nj; ++j) {
      psi[j] = stretching(grid.node(0, j), w);
      psi[nj + 1 + j] = stretching(grid.node(ni, j), w);
    }
  }
  const double di = 1.0 / static_cast<double>(ni), dj = 1.0 / static_cast<double>(nj);
  return sweep(
      grid, iterations, tolerance,
      [&](std::size_t i, std::size_t j, std::size_t k, std::size_t, const double* x, const double* y) {
        // alpha (r_xixi + phi r_xi) - 2 beta r_xieta + gamma (r_etaeta + psi r_eta) = 0 with
        // central differences on the unit (i, j) spacing (Thompson et al. 1985):
        // alpha = |r_eta|^2, beta = r_xi . r_eta, gamma = |r_xi|^2, solved for the centre node.
        const double xxi = 0.5 * (x[k + 1] - x[k - 1]), yxi = 0.5 * (y[k + 1] - y[k - 1]);
        const double xeta = 0.5 * (x[k + w] - x[k - w]), yeta = 0.5 * (y[k + w] - y[k - w]);
        const double alpha = xeta * xeta + yeta * yeta;
        const double beta = xxi * xeta + yxi * yeta;
        const double gamma = xxi * xxi + yxi * yxi;
        const double denominator = 2 * (alpha + gamma);
        const double v = static_cast<double>(j) * dj, u = static_cast<double>(i) * di;
        const double p = (1 - v) * phi[i] + v * phi[ni + 1 + i];
        const double q = (1 - u) * psi[j] + u * psi[nj + 1 + j];
        // 4 r_xieta, from the four diagonal neighbours.
        const double cx = x[k + w + 1] - x[k - w + 1] - x[k + w - 1] + x[k - w - 1];
        const double cy = y[k + w + 1] - y[k - w + 1] - y[k + w - 1] + y[k - w - 1];
        // A collapsed stencil (alpha + gamma = 0) gives NaN: sweep() reports Diverged.
        return Point{
            (alpha * (x[k + 1] + x[k - 1] + p * xxi) + gamma * (x[k + w] + x[k - w] + q * xeta) - 0.5 * beta * cx) /
                denominator,
            (alpha * (y[k + 1] + y[k - 1] + p * yxi) + gamma * (y[k + w] + y[k - w] + q * yeta) - 0.5 * beta * cy) /
                denominator};
      });
}

Smoothing laplace_smooth(StructuredGrid& grid, int iterations, double tolerance) {
  return sweep(grid, iterations, tolerance,
               [](std::size_t, std::size_t, std::size_t k, std::size_t w, const double* x, const double* y) {
                 return Point{0.25 * (x[k + 1] + x[k - 1] + x[k + w] + x[k - w]),
                              0.25 * (y[k + 1] + y[k - 1] + y[k + w] + y[k - w])};
               });
}

double min_scaled_jacobian(const StructuredGrid& grid) {
  const Vec3 up(0, 0, 1);
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < grid.nj; ++j) {
    for (std::size_t i = 0; i < grid.ni; ++i) {
      const std::array<std::size_t, 4> k{grid.node(i, j), grid.node(i + 1, j), grid.node(i + 1, j + 1),
                                         grid.node(i, j + 1)};
      std::array<Vec3, 4> c;
      for (int m = 0; m < 4; ++m) c[m] = Vec3(grid.x[k[m]], grid.y[k[m]], 0);
      const double sj = quad_scaled_jacobian(c, &up);
      if (std::isnan(sj)) return sj;
      smallest = std::min(smallest, sj);
    }
  }
  return smallest;
}

}  // namespace mapped

std::optional<PavedPart> mapped_mesh(const Polygon2& boundary, const std::array<std::size_t, 4>& corners,
                                     const MappedMeshOptions& options) {
  using namespace mapped;
  if (options.smoothing_iterations < 0) throw InputError("mapped_mesh: smoothing_iterations must be >= 0");
  if (std::isnan(options.min_scaled_jacobian)) throw InputError("mapped_mesh: min_scaled_jacobian is NaN");
  const StructuredGrid initial = transfinite_grid(boundary, corners);
  if (!corner_angles_can_reach(boundary.ring(0), corners, options.min_scaled_jacobian)) return std::nullopt;

  // Convergence: the largest move of a sweep below 1e-3 of the mean boundary edge
  // (invisible in the mesh and in its quality).
  const auto ring = boundary.ring(0);
  double perimeter = 0;
  for (std::size_t i = 0; i < ring.size(); ++i) perimeter += (ring[(i + 1) % ring.size()] - ring[i]).norm();
  const double tolerance = 1e-3 * perimeter / static_cast<double>(ring.size());

  // `!(q >= threshold)` also rejects a NaN quality.
  const auto accepted = [&](const StructuredGrid& g) { return min_scaled_jacobian(g) >= options.min_scaled_jacobian; };
  std::optional<StructuredGrid> chosen, best;
  if (options.smoothing_iterations == 0) {
    if (accepted(initial)) chosen = initial;
  } else {
    // Winslow with control functions keeps the boundary spacing; without them it is
    // the more robust harmonic map; Laplacian smoothing of the interpolated grid is the
    // last resort (it cannot diverge, being a mean of neighbours, but folds more easily
    // on concave sides). The first grid that passes is taken; failing that, the best.
    // A large grid gets the other attempts only if the first diverged (see
    // kRetryMaxQuads).
    double best_quality = -std::numeric_limits<double>::infinity();
    const bool large = initial.ni * initial.nj > kRetryMaxQuads;
    for (int attempt = 0; attempt < 3 && !chosen && !(large && best); ++attempt) {
      StructuredGrid g = initial;
      const Smoothing result = attempt < 2 ? winslow_smooth(g, options.smoothing_iterations, tolerance, attempt == 0)
                                           : laplace_smooth(g, options.smoothing_iterations, tolerance);
      if (result == Smoothing::Diverged) continue;
      const double quality = min_scaled_jacobian(g);
      if (quality >= options.min_scaled_jacobian) {
        chosen = std::move(g);
      } else if (quality > best_quality) {
        best_quality = quality;
        best = std::move(g);
      }
    }
  }
  if (!chosen && !best) return std::nullopt;

  const StructuredGrid& g = chosen ? *chosen : *best;
  PavedPart part;
  part.points = boundary.points;
  part.points.reserve(g.x.size());
  std::vector<Index> point(g.x.size());
  for (std::size_t k = 0; k < g.x.size(); ++k) {
    if (g.loop_index[k] != kInvalidIndex) {
      point[k] = g.loop_index[k];
    } else {
      point[k] = static_cast<Index>(part.points.size());
      part.points.emplace_back(g.x[k], g.y[k]);
    }
  }
  part.quads.reserve(g.ni * g.nj);
  for (std::size_t j = 0; j < g.nj; ++j)
    for (std::size_t i = 0; i < g.ni; ++i)
      part.quads.push_back(
          {point[g.node(i, j)], point[g.node(i + 1, j)], point[g.node(i + 1, j + 1)], point[g.node(i, j + 1)]});
  if (!chosen) {
    // No smoothing lifted every quad over the threshold: the best grid is polished as
    // a whole (the optimisation polar_mesh() applies to its blocks) and kept if it then
    // reaches the threshold with a mean of at least kRescuedBlocksMinMean.
    const double after = paving::polish_quads(part.points, part.quads, static_cast<Index>(ring.size()),
                                              perimeter / static_cast<double>(ring.size()), options.min_scaled_jacobian,
                                              paving::kBlockPolishEnergy);
    if (!(after >= options.min_scaled_jacobian) ||
        !(paving::mean_scaled_jacobian(part.points, part.quads) >= paving::kRescuedBlocksMinMean))
      return std::nullopt;
  }
  return part;
}

}  // namespace structmesh
