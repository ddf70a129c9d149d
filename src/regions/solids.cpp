// Built-in solids (solids.hpp): closed surfaces made from formulas. Hand-written because
// they are inputs, not algorithms: an icosphere displaced by a radius function, a voxel
// union, a torus grid and a surface of revolution are a few loops each, and the one
// smoothing step used (Taubin's, to round a voxel union's steps) would otherwise pull in a
// CGAL Surface_mesh for a 20-line umbrella operator.
#include "structmesh/solids.hpp"

#include "structmesh/error.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <tuple>

namespace structmesh {

TriMesh icosphere(int subdivisions, const std::function<double(const Vec3&)>& radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriMesh mesh;
  for (const auto& p : std::vector<Vec3>{{-1, t, 0},
                                         {1, t, 0},
                                         {-1, -t, 0},
                                         {1, -t, 0},
                                         {0, -1, t},
                                         {0, 1, t},
                                         {0, -1, -t},
                                         {0, 1, -t},
                                         {t, 0, -1},
                                         {t, 0, 1},
                                         {-t, 0, -1},
                                         {-t, 0, 1}})
    mesh.points.push_back(p.normalized());
  mesh.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<Index, Index>, Index> middle;
    const auto mid = [&](Index a, Index b) {
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = middle.emplace(key, static_cast<Index>(mesh.points.size()));
      if (inserted) mesh.points.push_back((mesh.points[a] + mesh.points[b]).normalized());
      return it->second;
    };
    std::vector<std::array<Index, 3>> next;
    for (const auto& [a, b, c] : mesh.triangles) {
      const Index ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.push_back({a, ab, ca});
      next.push_back({b, bc, ab});
      next.push_back({c, ca, bc});
      next.push_back({ab, bc, ca});
    }
    mesh.triangles = std::move(next);
  }
  for (Vec3& p : mesh.points) p *= radius(p);
  return mesh;
}

TriMesh voxel_union_surface(std::span<const std::array<int, 3>> cells, int subdivisions) {
  using Cell = std::array<int, 3>;
  const int n = subdivisions;
  const std::set<Cell> filled(cells.begin(), cells.end());
  TriMesh mesh;
  std::map<Cell, Index> ids;  // positions in units of 1 / n
  const auto vertex = [&](const Cell& c) {
    const auto [it, inserted] = ids.emplace(c, static_cast<Index>(mesh.points.size()));
    if (inserted) mesh.points.emplace_back(double(c[0]) / n, double(c[1]) / n, double(c[2]) / n);
    return it->second;
  };
  for (const Cell& cell : filled)
    for (int axis = 0; axis < 3; ++axis)
      for (const int side : {-1, 1}) {
        Cell neighbour = cell;
        neighbour[axis] += side;
        if (filled.count(neighbour) != 0) continue;
        // e_u x e_w = e_axis: corners base, +u, +u+w, +w face +axis.
        const int u = (axis + 1) % 3, w = (axis + 2) % 3;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) {
            Cell base{cell[0] * n, cell[1] * n, cell[2] * n};
            if (side > 0) base[axis] += n;
            base[u] += i;
            base[w] += j;
            Cell c1 = base, c2 = base, c3 = base;
            c1[u] += 1;
            c2[u] += 1;
            c2[w] += 1;
            c3[w] += 1;
            std::array<Index, 4> q{vertex(base), vertex(c1), vertex(c2), vertex(c3)};
            if (side < 0) std::swap(q[1], q[3]);
            mesh.triangles.push_back({q[0], q[1], q[2]});
            mesh.triangles.push_back({q[0], q[2], q[3]});
          }
      }
  return mesh;
}

TriMesh torus_surface(double big, double small, int u, int v) {
  TriMesh mesh;
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      const double a = 2 * std::numbers::pi * i / u, b = 2 * std::numbers::pi * j / v;
      mesh.points.emplace_back((big + small * std::cos(b)) * std::cos(a), (big + small * std::cos(b)) * std::sin(a),
                               small * std::sin(b));
    }
  const auto id = [&](int i, int j) { return static_cast<Index>(((i + u) % u) * v + (j + v) % v); };
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return mesh;
}

TriMesh surface_of_revolution(std::span<const std::pair<double, double>> profile, int around, bool closed) {
  if (profile.size() < 3 || around < 3)
    throw InputError("surface_of_revolution: a profile of at least 3 points and 3 steps around");
  if (!closed && (profile.front().first != 0 || profile.back().first != 0))
    throw InputError("surface_of_revolution: an open profile starts and ends on the axis (r = 0)");
  TriMesh mesh;
  std::vector<std::vector<Index>> rings;
  for (std::size_t i = 0; i < profile.size(); ++i) {
    const auto [r, z] = profile[i];
    // Only an open profile's two ends may lie on the axis: a point there in between would
    // pinch the surface to a point.
    const bool end = !closed && (i == 0 || i + 1 == profile.size());
    if (r < 0 || (r == 0 && !end))
      throw InputError("surface_of_revolution: profile point " + std::to_string(i) + " has radius " +
                       std::to_string(r) + ", off the half-plane r > 0");
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
      const auto k = static_cast<std::size_t>((j + 1) % around), jj = static_cast<std::size_t>(j);
      if (a.size() == 1)
        mesh.triangles.push_back({a[0], b[jj], b[k]});
      else if (b.size() == 1)
        mesh.triangles.push_back({a[jj], b[0], a[k]});
      else {
        mesh.triangles.push_back({a[jj], b[jj], b[k]});
        mesh.triangles.push_back({a[jj], b[k], a[k]});
      }
    }
  }
  // Outward whichever way the profile runs.
  if (enclosed_volume(mesh) < 0)
    for (auto& triangle : mesh.triangles) std::swap(triangle[1], triangle[2]);
  return mesh;
}

void taubin_smooth(TriMesh& mesh, int iterations) {
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
      if (neighbours[v].empty()) {
        moved[v] = mesh.points[v];
        continue;
      }
      Vec3 centroid = Vec3::Zero();
      for (const Index u : neighbours[v]) centroid += mesh.points[u];
      centroid /= static_cast<double>(neighbours[v].size());
      moved[v] = mesh.points[v] + factor * (centroid - mesh.points[v]);
    }
    mesh.points.swap(moved);
  }
}

namespace {

/// Turned 37 degrees about (1, 2, 3), off every coordinate axis, so that a polycube's
/// principal-axes alignment has work to do.
TriMesh turned(TriMesh mesh) {
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(37.0 * std::numbers::pi / 180.0, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (Vec3& p : mesh.points) p = r * p;
  return mesh;
}

/// Radius of the superellipsoid |x/a|^p + |y/b|^p + |z/c|^p = 1 along unit direction d.
double superellipsoid_radius(const Vec3& d, const Vec3& semi_axes, double p) {
  const double s = std::pow(std::abs(d.x() / semi_axes.x()), p) + std::pow(std::abs(d.y() / semi_axes.y()), p) +
                   std::pow(std::abs(d.z() / semi_axes.z()), p);
  return std::pow(s, -1.0 / p);
}

/// The polyline through `corners`, each straight piece cut into pieces of about `step`.
std::vector<std::pair<double, double>> polyline(const std::vector<std::pair<double, double>>& corners, double step,
                                                bool closed) {
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

// Machined parts: 96 steps around, profile pieces of about the same length.
constexpr int kAround = 96;
constexpr double kStep = 2 * std::numbers::pi / kAround;

TriMesh twisted_bar() {
  // A bar 4 x 1 x 1 twisted by a quarter turn about its length.
  TriMesh bar = icosphere(5, [](const Vec3& d) { return superellipsoid_radius(d, Vec3(2.0, 0.5, 0.5), 6); });
  for (Vec3& p : bar.points) {
    const double angle = 0.25 * std::numbers::pi * p.x() / 2.0;
    const double y = p.y(), z = p.z();
    p.y() = std::cos(angle) * y - std::sin(angle) * z;
    p.z() = std::sin(angle) * y + std::cos(angle) * z;
  }
  return bar;
}

TriMesh banana() {
  // An ellipsoid bent into an arc of radius 2.
  TriMesh banana = icosphere(5, [](const Vec3& d) { return superellipsoid_radius(d, Vec3(2.2, 0.55, 0.55), 2); });
  constexpr double kRadius = 2.0;
  for (Vec3& p : banana.points) {
    const double angle = p.x() / kRadius, r = kRadius - p.y();
    p = Vec3(r * std::sin(angle), kRadius - r * std::cos(angle), p.z());
  }
  return banana;
}

TriMesh swollen_torus() {
  // A torus whose tube swells from 0.25 to 0.65 around it.
  constexpr int kAroundTorus = 160, kAcross = 48;
  TriMesh torus = torus_surface(1.6, 1.0, kAroundTorus, kAcross);  // tube radius set below
  for (int i = 0; i < kAroundTorus; ++i)
    for (int j = 0; j < kAcross; ++j) {
      const double a = 2 * std::numbers::pi * i / kAroundTorus, b = 2 * std::numbers::pi * j / kAcross;
      const double tube = 0.45 + 0.2 * std::cos(a);
      torus.points[static_cast<std::size_t>(i * kAcross + j)] =
          Vec3((1.6 + tube * std::cos(b)) * std::cos(a), (1.6 + tube * std::cos(b)) * std::sin(a), tube * std::sin(b));
    }
  return turned(std::move(torus));
}

TriMesh trefoil() {
  // A tube of radius 0.45 around a trefoil knot, on the torus grid's connectivity.
  constexpr int kAlong = 360, kAroundTube = 24;
  constexpr double kTube = 0.45;
  const auto curve = [](double t) {
    return Vec3(std::sin(t) + 2 * std::sin(2 * t), std::cos(t) - 2 * std::cos(2 * t), -std::sin(3 * t));
  };
  TriMesh knot = torus_surface(2.0, 1.0, kAlong, kAroundTube);  // the grid; points set below
  for (int i = 0; i < kAlong; ++i) {
    const double t = 2 * std::numbers::pi * i / kAlong, dt = 1e-4;
    const Vec3 p = curve(t), tangent = (curve(t + dt) - curve(t - dt)).normalized();
    // A frame that turns with the curve: away from the centre of curvature, and the
    // binormal, in the torus grid's order (outward triangles).
    const Vec3 inward = curve(t + dt) - 2 * p + curve(t - dt);
    const Vec3 n = -(inward - inward.dot(tangent) * tangent).normalized(), b = n.cross(tangent);
    for (int j = 0; j < kAroundTube; ++j) {
      const double a = 2 * std::numbers::pi * j / kAroundTube;
      knot.points[static_cast<std::size_t>(i * kAroundTube + j)] = p + kTube * (std::cos(a) * n + std::sin(a) * b);
    }
  }
  return knot;
}

TriMesh pretzel() {
  // Genus 2: a 5 x 3 x 2 block of voxels with two 1 x 1 holes through it, its steps rounded.
  std::vector<std::array<int, 3>> cells;
  for (int x = 0; x < 5; ++x)
    for (int y = 0; y < 3; ++y)
      for (int z = 0; z < 2; ++z)
        if (!(y == 1 && (x == 1 || x == 3))) cells.push_back({x, y, z});
  TriMesh surface = voxel_union_surface(cells, 4);
  taubin_smooth(surface, 40);
  return turned(std::move(surface));
}

TriMesh bracket() {
  // An L bracket one voxel thick with a hole through its foot, edges rounded.
  std::vector<std::array<int, 3>> cells;
  for (int x = 0; x < 5; ++x)
    for (int y = 0; y < 3; ++y)
      if (!(x == 3 && y == 1)) cells.push_back({x, y, 0});
  for (int z = 1; z < 5; ++z)
    for (int y = 0; y < 3; ++y) cells.push_back({0, y, z});
  TriMesh surface = voxel_union_surface(cells, 4);
  taubin_smooth(surface, 15);
  return surface;
}

TriMesh dome() {
  std::vector<std::pair<double, double>> profile = polyline({{0, 0}, {1, 0}}, kStep, false);
  profile.pop_back();
  for (int k = 0; k <= 24; ++k) {
    const double a = 0.5 * std::numbers::pi * k / 24;
    profile.emplace_back(k == 24 ? 0.0 : std::cos(a), std::sin(a));
  }
  return surface_of_revolution(profile, kAround, false);
}

TriMesh revolved(const std::vector<std::pair<double, double>>& corners, bool closed) {
  return surface_of_revolution(polyline(corners, kStep, closed), kAround, closed);
}

struct Entry {
  BuiltinSolid solid;
  TriMesh (*make)();
};

const std::vector<Entry>& entries() {
  static const std::vector<Entry> table = {
      {{"blob", "lumpy sphere, radius 1 + 0.3 sin sin sin, turned off the axes", 0},
       [] {
         return turned(icosphere(5, [](const Vec3& d) {
           return 1.0 + 0.3 * std::sin(4 * d.x() + 1.1) * std::sin(3 * d.y() + 0.2) * std::sin(4 * d.z() + 0.9);
         }));
       }},
      {{"jack", "six rounded arms along the axes", 0},
       [] {
         return icosphere(5, [](const Vec3& d) {
           const double m = std::max({std::abs(d.x()), std::abs(d.y()), std::abs(d.z())});
           return 0.45 + 0.8 * std::pow(m, 12);
         });
       }},
      {{"tetra_lobes", "four lobes towards a tetrahedron's corners (between the axes)", 0},
       [] {
         return icosphere(5, [](const Vec3& d) {
           double lobe = 0;
           for (const Vec3& t : {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)})
             lobe = std::max(lobe, std::max(0.0, d.dot(t.normalized())));
           return 0.55 + 0.7 * std::pow(lobe, 6);
         });
       }},
      {{"urchin", "twelve spikes towards an icosahedron's corners", 0},
       [] {
         return icosphere(5, [](const Vec3& d) {
           const double t = (1.0 + std::sqrt(5.0)) / 2.0;
           double spike = 0;
           for (const Vec3& c :
                {Vec3(0, 1, t), Vec3(0, -1, t), Vec3(1, t, 0), Vec3(-1, t, 0), Vec3(t, 0, 1), Vec3(-t, 0, 1)})
             spike = std::max(spike, std::abs(d.dot(c.normalized())));
           return 0.7 + 0.6 * std::pow(spike, 24);
         });
       }},
      {{"dumbbell", "two lobes and a waist 0.4 of their width", 0},
       [] { return icosphere(5, [](const Vec3& d) { return 0.55 + 0.9 * std::pow(d.x(), 4); }); }},
      {{"rounded_slab", "superellipsoid 1.6 x 0.9 x 0.5 (semi-axes), exponent 6, turned off the axes", 0},
       [] {
         return turned(icosphere(5, [](const Vec3& d) { return superellipsoid_radius(d, Vec3(1.6, 0.9, 0.5), 6); }));
       }},
      {{"twisted_bar", "bar 4 x 1 x 1 twisted by 90 degrees along its length", 0}, twisted_bar},
      {{"banana", "ellipsoid 4.4 x 1.1 x 1.1 bent over 126 degrees", 0}, banana},
      {{"swollen_torus", "torus whose tube radius goes 0.25-0.65 around it, turned off the axes", 1}, swollen_torus},
      {{"trefoil", "tube of radius 0.45 around a trefoil knot", 1}, trefoil},
      {{"pretzel", "smoothed 5 x 3 x 2 voxel block with two holes, turned off the axes", 2}, pretzel},
      {{"bracket", "L bracket 5 x 3 x 5, one voxel thick, a hole in its foot, edges rounded", 1}, bracket},
      {{"cylinder", "cylinder, radius 1, height 2, sharp rims", 0},
       [] {
         return revolved({{0, 0}, {1, 0}, {1, 2}, {0, 2}}, false);
       }},
      {{"washer", "washer, radii 0.6 and 1.2, 0.5 thick, sharp rims", 1},
       [] {
         return revolved({{0.6, 0}, {1.2, 0}, {1.2, 0.5}, {0.6, 0.5}}, true);
       }},
      {{"bolt", "head of radius 1, 0.4 high, on a shaft of radius 0.4, 1.5 long; sharp rims, one concave", 0},
       [] {
         return revolved({{0, 0}, {0.4, 0}, {0.4, 1.5}, {1, 1.5}, {1, 1.9}, {0, 1.9}}, false);
       }},
      {{"dome", "half ball of radius 1, sharp rim", 0}, dome},
  };
  return table;
}

}  // namespace

std::span<const BuiltinSolid> builtin_solids() {
  static const std::vector<BuiltinSolid> solids = [] {
    std::vector<BuiltinSolid> list;
    for (const Entry& entry : entries()) list.push_back(entry.solid);
    return list;
  }();
  return solids;
}

TriMesh make_builtin_solid(std::string_view name) {
  for (const Entry& entry : entries())
    if (entry.solid.name == name) return entry.make();
  std::string choices;
  for (const Entry& entry : entries()) choices += (choices.empty() ? "" : ", ") + std::string(entry.solid.name);
  throw InputError("no built-in solid named '" + std::string(name) + "' (choices: " + choices + ")");
}

}  // namespace structmesh
