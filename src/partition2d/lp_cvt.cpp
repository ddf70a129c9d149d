// L_p-CVT energy (3.12), its exact gradient (design/partition2d.md §1.7, §2.3), the
// initial grid of sites and the L-BFGS optimisation (§2.5). Frame `axes` (R = I).
#include "mesh/lbfgs_parameters.hpp"
#include "partition2d/restricted_voronoi_impl.hpp"

#include "structmesh/error.hpp"
#include "structmesh/progress.hpp"

#include <LBFGS.h>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

namespace structmesh::partition2d {

namespace {

// Complete homogeneous symmetric polynomials h_m(a, b, c) for m = p - 1 and m = p
// (§2.3), by h_n(x_1..x_k) = x_k h_{n-1}(x_1..x_k) + h_n(x_1..x_{k-1}).
struct Homogeneous {
  double below = 0;  ///< h_{p-1}
  double top = 0;    ///< h_p
};
Homogeneous homogeneous(double a, double b, double c, int p) {
  double h1 = 1, h2 = 1, h3 = 1, previous = 1;  // degree 0
  for (int n = 1; n <= p; ++n) {
    previous = h3;
    h1 *= c;
    h2 = b * h2 + h1;
    h3 = a * h3 + h2;
  }
  return {previous, h3};
}

// x^p for even p.
double power(double x, int p) {
  const double square = x * x;
  double r = square;
  for (int k = 2; k < p; k += 2) r *= square;
  return r;
}

// Gauss-Legendre rule on [-1, 1] with p/2 + 1 points, exact to degree p + 1, the
// degree of the bisector integrand (§2.3: 5 points for p = 8). Nodes by Newton's
// method on the Legendre polynomial from Chebyshev guesses.
struct GaussRule {
  std::vector<double> nodes, weights;
};
GaussRule gauss_legendre(int points) {
  constexpr double kPi = 3.14159265358979323846;
  GaussRule rule;
  for (int i = 0; i < points; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (points + 0.5));
    double derivative = 1;
    for (int iteration = 0; iteration < 100; ++iteration) {
      // P_n(x) and P_n'(x) by the three-term recurrence.
      double p0 = 1, p1 = x;
      for (int n = 2; n <= points; ++n) {
        const double p2 = ((2 * n - 1) * x * p1 - (n - 1) * p0) / n;
        p0 = p1;
        p1 = p2;
      }
      derivative = points * (x * p1 - p0) / (x * x - 1);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    rule.nodes.push_back(x);
    rule.weights.push_back(2 / ((1 - x * x) * derivative * derivative));
  }
  return rule;
}

struct Contribution {
  Index site;
  double energy, gx, gy;
};

// Energy and gradient of one piece of cell c (eq. 3.12 and §1.7).
Contribution piece_contribution(const rvd::PieceView& piece, std::span<const Vec2> sites, int p, bool gradient,
                                const GaussRule& gauss) {
  const Vec2& xc = sites[piece.site];
  const std::size_t m = piece.positions.size();
  Contribution out{piece.site, 0, 0, 0};
  // Fan from the first vertex: int_T U^m dy = 2|T| h_m(U_1, U_2, U_3) / ((m+1)(m+2)).
  const Vec2 u0 = piece.positions[0] - xc;
  const double energy_factor = 1.0 / ((p + 1.0) * (p + 2.0));
  const double gradient_factor = 1.0 / (p * (p + 1.0));
  for (std::size_t k = 1; k + 1 < m; ++k) {
    const Vec2 u1 = piece.positions[k] - xc, u2 = piece.positions[k + 1] - xc;
    const Vec2 e1 = u1 - u0, e2 = u2 - u0;
    const double twice_area = e1.x() * e2.y() - e1.y() * e2.x();
    const Homogeneous hx = homogeneous(u0.x(), u1.x(), u2.x(), p);
    const Homogeneous hy = homogeneous(u0.y(), u1.y(), u2.y(), p);
    out.energy += twice_area * energy_factor * (hx.top + hy.top);
    if (gradient) {
      // Interior term: -p int (y - x_c)_k^{p-1} dy.
      out.gx -= p * twice_area * gradient_factor * hx.below;
      out.gy -= p * twice_area * gradient_factor * hy.below;
    }
  }
  if (!gradient || p == 2) return out;  // p = 2: f_c = f_l on the bisector, the edge term vanishes
  // Bisector term of §1.7: int_{Γ_cl} (f_c - f_l)(y - x_c) / |x_l - x_c| ds.
  for (std::size_t k = 0; k < m; ++k) {
    const rvd::EdgeTag& tag = piece.tags[k];
    if (!tag.on_bisector()) continue;
    const Vec2& xl = sites[tag.neighbor];
    const Vec2& q0 = piece.positions[k];
    const Vec2& q1 = piece.positions[k + 1 == m ? 0 : k + 1];
    const Vec2 mid = 0.5 * (q0 + q1), half = 0.5 * (q1 - q0);
    const double scale = half.norm() / (xl - xc).norm();
    for (std::size_t g = 0; g < gauss.nodes.size(); ++g) {
      const Vec2 y = mid + gauss.nodes[g] * half;
      const Vec2 uc = y - xc, ul = y - xl;
      const double jump = power(uc.x(), p) + power(uc.y(), p) - power(ul.x(), p) - power(ul.y(), p);
      out.gx += gauss.weights[g] * scale * jump * uc.x();
      out.gy += gauss.weights[g] * scale * jump * uc.y();
    }
  }
  return out;
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Grid points of spacing h (offset by half a spacing from the bounding box corner)
// that lie in a domain triangle, each once, in row-major order.
std::vector<Vec2> grid_points_inside(const DomainMesh& domain, const Vec2& origin, double h, std::size_t columns,
                                     std::size_t rows) {
  std::vector<std::uint8_t> inside(columns * rows, 0);
  for (const auto& tri : domain.triangles) {
    const Vec2 &a = domain.points[tri[0]], &b = domain.points[tri[1]], &c = domain.points[tri[2]];
    const Vec2 low = a.cwiseMin(b).cwiseMin(c), high = a.cwiseMax(b).cwiseMax(c);
    const auto first = [&](double v, double o) { return std::max(0.0, std::ceil((v - o) / h - 0.5)); };
    const auto last = [&](double v, double o) { return std::floor((v - o) / h - 0.5); };
    const double i0 = first(low.x(), origin.x()), i1 = std::min<double>(last(high.x(), origin.x()), columns - 1.0);
    const double j0 = first(low.y(), origin.y()), j1 = std::min<double>(last(high.y(), origin.y()), rows - 1.0);
    for (double j = j0; j <= j1; ++j) {
      for (double i = i0; i <= i1; ++i) {
        const Vec2 q = origin + h * Vec2(i + 0.5, j + 0.5);
        const auto cross = [](const Vec2& u, const Vec2& v, const Vec2& w) {
          return (v - u).x() * (w - u).y() - (v - u).y() * (w - u).x();
        };
        if (cross(a, b, q) >= 0 && cross(b, c, q) >= 0 && cross(c, a, q) >= 0) {
          inside[static_cast<std::size_t>(j) * columns + static_cast<std::size_t>(i)] = 1;
        }
      }
    }
  }
  std::vector<Vec2> points;
  for (std::size_t j = 0; j < rows; ++j) {
    for (std::size_t i = 0; i < columns; ++i) {
      if (inside[j * columns + i] != 0) points.push_back(origin + h * Vec2(i + 0.5, j + 0.5));
    }
  }
  return points;
}

}  // namespace

double lp_energy(const DomainMesh& domain, std::span<const Vec2> sites, int p, std::vector<double>* gradient,
                 std::size_t* empty_cells) {
  if (p < 2 || p % 2 != 0) throw InputError("L_p-CVT: p must be even and at least 2, got " + std::to_string(p));
  const rvd::Engine engine(domain, sites);
  std::vector<std::vector<Contribution>> blocks(engine.block_count());
  const bool want_gradient = gradient != nullptr;
  const GaussRule gauss = gauss_legendre(p / 2 + 1);
  engine.for_each_piece([&](std::size_t block, const rvd::PieceView& piece) {
    blocks[block].push_back(piece_contribution(piece, sites, p, want_gradient, gauss));
  });
  // Summed in block order, never with floating-point joins across threads, so the
  // result does not depend on the thread count (§2.3).
  std::vector<double> energy(sites.size(), 0.0);
  std::vector<std::uint8_t> occupied(sites.size(), 0);
  if (want_gradient) gradient->assign(2 * sites.size(), 0.0);
  for (const auto& block : blocks) {
    for (const Contribution& c : block) {
      energy[c.site] += c.energy;
      occupied[c.site] = 1;
      if (want_gradient) {
        (*gradient)[2 * c.site] += c.gx;
        (*gradient)[2 * c.site + 1] += c.gy;
      }
    }
  }
  double total = 0;
  for (const double e : energy) total += e;
  if (empty_cells != nullptr) *empty_cells = static_cast<std::size_t>(std::count(occupied.begin(), occupied.end(), 0));
  return total;
}

std::vector<Vec2> initial_grid_sites(const DomainMesh& domain, std::size_t count, std::uint64_t seed) {
  if (count == 0) throw InputError("initial sites: the count must be positive");
  if (domain.triangles.empty() || !(domain.area > 0)) throw InputError("initial sites: empty domain");
  Vec2 low = domain.points[0], high = domain.points[0];
  for (const Vec2& q : domain.points) low = low.cwiseMin(q), high = high.cwiseMax(q);
  // A spacing of sqrt(area / count) puts about `count` points inside; a few secant
  // corrections absorb the boundary effect.
  double h = std::sqrt(domain.area / static_cast<double>(count));
  std::vector<Vec2> best;
  double best_h = h;
  const auto miss = [&](std::size_t found) {
    return std::abs(static_cast<double>(found) - static_cast<double>(count));
  };
  for (int attempt = 0; attempt < 8; ++attempt) {
    const Vec2 extent = high - low;
    const auto columns = static_cast<std::size_t>(std::floor(extent.x() / h)) + 1;
    const auto rows = static_cast<std::size_t>(std::floor(extent.y() / h)) + 1;
    const Vec2 origin = 0.5 * (low + high) - 0.5 * h * Vec2(static_cast<double>(columns), static_cast<double>(rows));
    std::vector<Vec2> points = grid_points_inside(domain, origin, h, columns, rows);
    const std::size_t found = points.size();
    if (best.empty() || miss(found) < miss(best.size())) best = std::move(points), best_h = h;
    if (miss(found) <= std::max(1.0, 0.01 * static_cast<double>(count))) break;
    h *= std::sqrt(std::max<double>(static_cast<double>(found), 1.0) / static_cast<double>(count));
  }
  if (best.empty()) throw InputError("initial sites: no grid point inside the domain");
  // §2.2 step 4: a perfect grid is co-circular everywhere; jitter by 1e-6 of the
  // spacing, deterministically from (seed, index).
  const double amplitude = 1e-6 * best_h;
  for (std::size_t i = 0; i < best.size(); ++i) {
    const std::uint64_t r = splitmix64(seed * 0x100000001b3ULL ^ splitmix64(i));
    const double jx = static_cast<double>(r & 0xffffffffULL) / 4294967296.0 - 0.5;
    const double jy = static_cast<double>(r >> 32) / 4294967296.0 - 0.5;
    best[i] += amplitude * Vec2(jx, jy);
  }
  return best;
}

LpCvtResult optimise_lp_cvt(const DomainMesh& domain, std::vector<Vec2> sites, const LpCvtOptions& options) {
  const std::size_t n = sites.size();
  if (n == 0) throw InputError("L_p-CVT: no sites");
  LpCvtResult result;
  Eigen::VectorXd x(2 * n);
  for (std::size_t i = 0; i < n; ++i) x[2 * i] = sites[i].x(), x[2 * i + 1] = sites[i].y();

  std::optional<Progress> progress;
  if (options.progress) progress.emplace("L_p-CVT iterations", static_cast<std::uint64_t>(options.max_iterations));
  // L-BFGS may leave x at a failed trial point, so the functor keeps the best point.
  double best_energy = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_x = x;
  std::size_t best_empty = 0;
  int improvements = 0;
  std::vector<Vec2> trial(n);
  std::vector<double> g;
  const auto energy = [&](const Eigen::VectorXd& point, Eigen::VectorXd& grad) {
    for (std::size_t i = 0; i < n; ++i) trial[i] = Vec2(point[2 * i], point[2 * i + 1]);
    std::size_t empty = 0;
    const double f = lp_energy(domain, trial, options.p, &g, &empty);
    grad = Eigen::Map<const Eigen::VectorXd>(g.data(), static_cast<Eigen::Index>(g.size()));
    if (f < best_energy) best_energy = f, best_x = point, best_empty = empty, ++improvements;
    return f;
  };
  Eigen::VectorXd initial_gradient(2 * n);
  result.energy_initial = energy(x, initial_gradient);

  LBFGSpp::LBFGSParam<double> param =
      detail::lbfgs_parameters(options.gradient_tolerance, options.max_iterations, true);
  param.past = 3;
  param.delta = 1e-8;
  LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchBacktracking> solver(param);
  double fx = 0;
  // The solver's first evaluation is the starting point, already evaluated above.
  // Progress: the solver has no callback; every accepted step decreases F, so the
  // number of improvements of the best point tracks the iterations.
  bool first_call = true;
  const auto counted = [&](const Eigen::VectorXd& point, Eigen::VectorXd& grad) {
    if (std::exchange(first_call, false) && point == best_x) {
      grad = initial_gradient;
      return result.energy_initial;
    }
    const double f = energy(point, grad);
    if (progress) progress->set(static_cast<std::uint64_t>(std::max(improvements - 1, 0)));
    return f;
  };
  try {
    result.iterations = options.max_iterations > 0 ? solver.minimize(counted, x, fx) : 0;
    result.stop_reason = result.iterations >= options.max_iterations ? "max iterations" : "converged";
  } catch (const std::runtime_error&) {
    // Maximum line-search steps or a step too small: the best point is kept. The
    // solver's count is lost with the throw; every accepted step decreased F, so the
    // number of improvements (minus the starting point) stands in for it.
    result.stop_reason = "line search stopped";
    result.iterations = improvements - 1;
  }
  if (progress) progress->finish();
  for (std::size_t i = 0; i < n; ++i) sites[i] = Vec2(best_x[2 * i], best_x[2 * i + 1]);
  result.sites = std::move(sites);
  result.energy_final = best_energy;
  result.empty_cells = best_empty;
  return result;
}

}  // namespace structmesh::partition2d
