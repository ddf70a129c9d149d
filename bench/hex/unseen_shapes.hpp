// Closed surfaces the polycube pipeline was never tuned on, for issue 6's "valid meshes on
// models you have never seen": made here from formulas (star-shaped radius functions over an
// icosphere, bent and twisted superellipsoids, a torus whose tube swells, smoothed unions of
// voxels of genus 2), most of them turned off the coordinate axes so that the principal-axes
// alignment has work to do. Nothing here was looked at while the pipeline's defaults were
// chosen; the shapes only reuse the tests' icosphere, torus and voxel-union builders.
#pragma once

#include "../../tests/guard/shapes.hpp"
#include "../../tests/polycube/shapes.hpp"
#include "structmesh/mesh.hpp"
#include "structmesh/tetmesh.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace structmesh::bench {

struct NamedShape {
  std::string name;
  std::string what;  // one line for the table
  TriMesh surface;
};

namespace unseen_detail {

/// A rotation off every coordinate axis (37 degrees about (1, 2, 3)).
inline Eigen::Matrix3d oblique() {
  return Eigen::AngleAxisd(37.0 * std::numbers::pi / 180.0, Vec3(1, 2, 3).normalized()).toRotationMatrix();
}

inline TriMesh rotated(TriMesh mesh) {
  const Eigen::Matrix3d r = oblique();
  for (Vec3& p : mesh.points) p = r * p;
  return mesh;
}

/// Radius of the superellipsoid |x/a|^p + |y/b|^p + |z/c|^p = 1 along unit direction d.
inline double superellipsoid_radius(const Vec3& d, const Vec3& semi_axes, double p) {
  const double s = std::pow(std::abs(d.x() / semi_axes.x()), p) + std::pow(std::abs(d.y() / semi_axes.y()), p) +
                   std::pow(std::abs(d.z() / semi_axes.z()), p);
  return std::pow(s, -1.0 / p);
}

/// Taubin's lambda|mu smoothing (umbrella operator): rounds a voxel union's steps without
/// shrinking it. Hand-written because it only shapes a benchmark input (CGAL's smoothing would
/// need a Surface_mesh and a heavy compile for that); the check in the benchmark rejects a
/// result that self-intersects.
inline void taubin_smooth(TriMesh& mesh, int iterations) {
  std::vector<std::vector<Index>> neighbours(mesh.points.size());
  for (const auto& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) {
      neighbours[t[i]].push_back(t[(i + 1) % 3]);
      neighbours[t[(i + 1) % 3]].push_back(t[i]);
    }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<Vec3> moved(mesh.points.size());
  for (int iteration = 0; iteration < 2 * iterations; ++iteration) {
    const double factor = iteration % 2 == 0 ? 0.5 : -0.53;
    for (std::size_t v = 0; v < mesh.points.size(); ++v) {
      Vec3 centroid = Vec3::Zero();
      for (const Index u : neighbours[v]) centroid += mesh.points[u];
      centroid /= static_cast<double>(neighbours[v].size());
      moved[v] = mesh.points[v] + factor * (centroid - mesh.points[v]);
    }
    mesh.points.swap(moved);
  }
}

/// The surface swept by turning `profile` (points (r, z), r >= 0) about the z axis in
/// `around` steps. An open profile must start and end on the axis (r = 0: poles); a closed
/// one (`closed`) stays off it and sweeps a solid torus. Profile corners stay sharp edges.
inline TriMesh revolve(const std::vector<std::pair<double, double>>& profile, int around, bool closed) {
  TriMesh mesh;
  std::vector<std::vector<Index>> rings;
  for (const auto& [r, z] : profile) {
    std::vector<Index> ring;
    const int copies = r == 0 ? 1 : around;
    for (int j = 0; j < copies; ++j) {
      const double a = 2 * std::numbers::pi * j / around;
      ring.push_back(static_cast<Index>(mesh.points.size()));
      mesh.points.emplace_back(r * std::cos(a), r * std::sin(a), z);
    }
    rings.push_back(std::move(ring));
  }
  const std::size_t bands = closed ? rings.size() : rings.size() - 1;
  for (std::size_t i = 0; i < bands; ++i) {
    const auto& a = rings[i];
    const auto& b = rings[(i + 1) % rings.size()];
    for (int j = 0; j < around; ++j) {
      const int k = (j + 1) % around;
      if (a.size() == 1) {
        mesh.triangles.push_back({a[0], b[j], b[k]});
      } else if (b.size() == 1) {
        mesh.triangles.push_back({a[j], b[0], a[k]});
      } else {
        mesh.triangles.push_back({a[j], b[j], b[k]});
        mesh.triangles.push_back({a[j], b[k], a[k]});
      }
    }
  }
  // Outward whichever way the profile runs.
  if (enclosed_volume(mesh) < 0)
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

/// The polyline through `corners`, each straight piece cut into pieces of about `step`.
inline std::vector<std::pair<double, double>> polyline(const std::vector<std::pair<double, double>>& corners,
                                                       double step, bool closed) {
  std::vector<std::pair<double, double>> points;
  const std::size_t pieces = closed ? corners.size() : corners.size() - 1;
  for (std::size_t i = 0; i < pieces; ++i) {
    const auto [r0, z0] = corners[i];
    const auto [r1, z1] = corners[(i + 1) % corners.size()];
    const int n = std::max(1, static_cast<int>(std::round(std::hypot(r1 - r0, z1 - z0) / step)));
    for (int k = 0; k < n; ++k) points.emplace_back(r0 + (r1 - r0) * k / n, z0 + (z1 - z0) * k / n);
  }
  if (!closed) points.push_back(corners.back());
  return points;
}

}  // namespace unseen_detail

/// The unseen shapes, 1k-10k vertices each, in a fixed order.
inline std::vector<NamedShape> unseen_shapes() {
  using namespace unseen_detail;
  std::vector<NamedShape> shapes;
  const auto add = [&](std::string name, std::string what, TriMesh surface) {
    shapes.push_back({std::move(name), std::move(what), std::move(surface)});
  };
  // Star-shaped radius functions over the icosphere (10,242 vertices).
  add("blob", "lumpy sphere, 1 + 0.3 sin sin sin, turned", rotated(test::icosphere(5, [](const Vec3& d) {
        return 1.0 + 0.3 * std::sin(4 * d.x() + 1.1) * std::sin(3 * d.y() + 0.2) * std::sin(4 * d.z() + 0.9);
      })));
  add("jack", "six rounded arms along the axes", test::icosphere(5, [](const Vec3& d) {
        const double m = std::max({std::abs(d.x()), std::abs(d.y()), std::abs(d.z())});
        return 0.45 + 0.8 * std::pow(m, 12);
      }));
  add("tetra_lobes", "four lobes towards a tetrahedron's corners (off the axes)", test::icosphere(5, [](const Vec3& d) {
        double lobe = 0;
        for (const Vec3& t : {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)})
          lobe = std::max(lobe, std::max(0.0, d.dot(t.normalized())));
        return 0.55 + 0.7 * std::pow(lobe, 6);
      }));
  add("urchin", "twelve spikes towards an icosahedron's corners", test::icosphere(5, [](const Vec3& d) {
        const double t = (1.0 + std::sqrt(5.0)) / 2.0;
        double spike = 0;
        for (const Vec3& c :
             {Vec3(0, 1, t), Vec3(0, -1, t), Vec3(1, t, 0), Vec3(-1, t, 0), Vec3(t, 0, 1), Vec3(-t, 0, 1)})
          spike = std::max(spike, std::abs(d.dot(c.normalized())));
        return 0.7 + 0.6 * std::pow(spike, 24);
      }));
  add("dumbbell", "two lobes and a waist 0.4 of their width",
      test::icosphere(5, [](const Vec3& d) { return 0.55 + 0.9 * std::pow(d.x(), 4); }));
  add("rounded_slab", "superellipsoid 1.6 x 0.9 x 0.5, exponent 6, turned",
      rotated(test::icosphere(5, [](const Vec3& d) { return superellipsoid_radius(d, Vec3(1.6, 0.9, 0.5), 6); })));
  {
    // A bar twisted by a quarter turn about its length.
    TriMesh bar = test::icosphere(5, [](const Vec3& d) { return superellipsoid_radius(d, Vec3(2.0, 0.5, 0.5), 6); });
    for (Vec3& p : bar.points) {
      const double angle = 0.25 * std::numbers::pi * p.x() / 2.0;
      const double y = p.y(), z = p.z();
      p.y() = std::cos(angle) * y - std::sin(angle) * z;
      p.z() = std::sin(angle) * y + std::cos(angle) * z;
    }
    add("twisted_bar", "bar 4 x 1 x 1 twisted by 90 degrees along its length", std::move(bar));
  }
  {
    // An ellipsoid bent into an arc of radius 2 (a banana).
    TriMesh banana =
        test::icosphere(5, [](const Vec3& d) { return superellipsoid_radius(d, Vec3(2.2, 0.55, 0.55), 2); });
    constexpr double kRadius = 2.0;
    for (Vec3& p : banana.points) {
      const double angle = p.x() / kRadius, r = kRadius - p.y();
      p = Vec3(r * std::sin(angle), kRadius - r * std::cos(angle), p.z());
    }
    add("banana", "ellipsoid 4.4 x 1.1 x 1.1 bent over 126 degrees", std::move(banana));
  }
  {
    // A torus whose tube swells from 0.25 to 0.65 around it, turned.
    constexpr int kAround = 160, kAcross = 48;
    TriMesh torus = test::torus(1.6, 1.0, kAround, kAcross);  // tube radius set below
    for (int i = 0; i < kAround; ++i)
      for (int j = 0; j < kAcross; ++j) {
        const double a = 2 * std::numbers::pi * i / kAround, b = 2 * std::numbers::pi * j / kAcross;
        const double tube = 0.45 + 0.2 * std::cos(a);
        torus.points[static_cast<std::size_t>(i * kAcross + j)] = Vec3(
            (1.6 + tube * std::cos(b)) * std::cos(a), (1.6 + tube * std::cos(b)) * std::sin(a), tube * std::sin(b));
      }
    add("swollen_torus", "torus, tube radius 0.25-0.65 around it, turned", rotated(std::move(torus)));
  }
  {
    // A tube of radius 0.45 around a trefoil knot (genus 1, winding through itself).
    constexpr int kAlong = 360, kAround = 24;
    constexpr double kTube = 0.45;
    const auto curve = [](double t) {
      return Vec3(std::sin(t) + 2 * std::sin(2 * t), std::cos(t) - 2 * std::cos(2 * t), -std::sin(3 * t));
    };
    TriMesh knot = test::torus(2.0, 1.0, kAlong, kAround);  // the grid; points set below
    for (int i = 0; i < kAlong; ++i) {
      const double t = 2 * std::numbers::pi * i / kAlong, dt = 1e-4;
      const Vec3 p = curve(t), tangent = (curve(t + dt) - curve(t - dt)).normalized();
      // A frame that turns with the curve: away from the centre of curvature, and the
      // binormal, in the torus grid's order (outward triangles).
      const Vec3 inward = curve(t + dt) - 2 * p + curve(t - dt);
      const Vec3 n = -(inward - inward.dot(tangent) * tangent).normalized(), b = n.cross(tangent);
      for (int j = 0; j < kAround; ++j) {
        const double a = 2 * std::numbers::pi * j / kAround;
        knot.points[static_cast<std::size_t>(i * kAround + j)] = p + kTube * (std::cos(a) * n + std::sin(a) * b);
      }
    }
    add("trefoil", "tube of radius 0.45 around a trefoil knot (genus 1)", std::move(knot));
  }
  {
    // Genus 2: a 5 x 3 x 2 block of voxels with two 1 x 1 holes through it, its steps
    // rounded by Taubin smoothing.
    std::vector<test::Cell> cells;
    for (int x = 0; x < 5; ++x)
      for (int y = 0; y < 3; ++y)
        for (int z = 0; z < 2; ++z)
          if (!(y == 1 && (x == 1 || x == 3))) cells.push_back({x, y, z});
    TriMesh pretzel = test::voxel_surface(cells, 4);
    taubin_smooth(pretzel, 40);
    add("pretzel", "genus 2: smoothed 5 x 3 x 2 voxel block with two holes, turned", rotated(std::move(pretzel)));
  }
  {
    // An L-shaped bracket with a hole through its foot: a CAD-like part, edges rounded.
    std::vector<test::Cell> cells;
    for (int x = 0; x < 5; ++x)
      for (int y = 0; y < 3; ++y)
        if (!(x == 3 && y == 1)) cells.push_back({x, y, 0});
    for (int z = 1; z < 5; ++z)
      for (int y = 0; y < 3; ++y) cells.push_back({0, y, z});
    TriMesh bracket = test::voxel_surface(cells, 4);
    taubin_smooth(bracket, 15);
    add("bracket", "L bracket 5 x 3 x 5 one voxel thick, hole in its foot (genus 1)", std::move(bracket));
  }
  // Machined parts: surfaces of revolution with sharp rims (CAD-like; default settings, no
  // --features), 96 steps around.
  constexpr double kStep = 2 * std::numbers::pi / 96;
  add("cylinder", "cylinder, radius 1, height 2, sharp rims",
      revolve(polyline({{0, 0}, {1, 0}, {1, 2}, {0, 2}}, kStep, false), 96, false));
  add("washer", "washer, radii 0.6 and 1.2, 0.5 thick, sharp rims (genus 1)",
      revolve(polyline({{0.6, 0}, {1.2, 0}, {1.2, 0.5}, {0.6, 0.5}}, kStep, true), 96, true));
  add("bolt", "bolt: head radius 1, 0.4 high, on a shaft of radius 0.4, 1.5 long; sharp, one rim concave",
      revolve(polyline({{0, 0}, {0.4, 0}, {0.4, 1.5}, {1, 1.5}, {1, 1.9}, {0, 1.9}}, kStep, false), 96, false));
  {
    std::vector<std::pair<double, double>> profile = polyline({{0, 0}, {1, 0}}, kStep, false);
    profile.pop_back();
    for (int k = 0; k <= 24; ++k) {
      const double a = 0.5 * std::numbers::pi * k / 24;
      profile.emplace_back(k == 24 ? 0.0 : std::cos(a), std::sin(a));
    }
    add("dome", "half ball, radius 1, sharp rim", revolve(profile, 96, false));
  }
  return shapes;
}

}  // namespace structmesh::bench
