// Hand-built tessellations for the part geometry, metrics and output tests: faces
// given as counter-clockwise polygons in input coordinates, vertices merged by
// exact coordinates, twins matched by vertex pairs, region vertices found by exact
// coordinates. The normalised frame is an affine image of the input (identity by default).
#pragma once

#include "partition2d/partition_internal.hpp"

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

namespace structmesh::partition2d::testing {

using Face = std::vector<Vec2>;

/// normalised = (input * metric_scale - center) / cell; the maps invert it.
struct TestFrame {
  double metric_scale = 1;
  Vec2 center = Vec2::Zero();
  double cell = 1;

  Vec2 to_normalised(const Vec2& input) const { return (input * metric_scale - center) / cell; }
  CoordinateMaps maps() const {
    const TestFrame frame = *this;
    return {[frame](const Vec2& n) -> Vec2 { return n * frame.cell + frame.center; },
            [frame](const Vec2& m) -> Vec2 { return m / frame.metric_scale; }};
  }
};

inline Polygon2 make_region(const std::vector<std::vector<Vec2>>& rings) {
  Polygon2 region;
  for (const auto& ring : rings) region.add_ring(ring);
  return region;
}

inline Tessellation make_tessellation(const std::vector<Face>& faces, const Polygon2& region,
                                      const TestFrame& frame = {}) {
  Tessellation t;
  std::map<std::pair<double, double>, Index> vertex_id;
  std::map<std::pair<double, double>, std::int64_t> region_point;
  for (std::size_t i = 0; i < region.points.size(); ++i)
    region_point[{region.points[i].x(), region.points[i].y()}] = static_cast<std::int64_t>(i);
  std::vector<Vec2> input_points;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (const Vec2& p : faces[f]) {
      const auto [it, inserted] = vertex_id.try_emplace({p.x(), p.y()}, static_cast<Index>(input_points.size()));
      if (inserted) {
        input_points.push_back(p);
        t.vertices.push_back(frame.to_normalised(p));
        const auto r = region_point.find({p.x(), p.y()});
        t.input_vertex.push_back(r == region_point.end() ? -1 : r->second);
      }
      t.face_vertices.push_back(it->second);
    }
    t.face_offsets.push_back(static_cast<Index>(t.face_vertices.size()));
    t.face_cell.push_back(static_cast<Index>(f));
  }
  t.cell_count = faces.size();
  std::map<std::pair<Index, Index>, Index> half_edge;
  for (Index f = 0; f < t.face_count(); ++f)
    for (Index h = t.face_offsets[f]; h < t.face_offsets[f + 1]; ++h)
      half_edge[{t.face_vertices[h], t.face_vertices[t.next(h, f)]}] = h;
  t.twin.assign(t.face_vertices.size(), kInvalidIndex);
  t.boundary_ring.assign(t.face_vertices.size(), -1);
  for (const auto& [key, h] : half_edge) {
    const auto twin = half_edge.find({key.second, key.first});
    if (twin != half_edge.end()) {
      t.twin[h] = twin->second;
      continue;
    }
    // The region ring whose segment holds both ends (exact for the dyadic test coordinates).
    const Vec2 &a = input_points[key.first], &b = input_points[key.second];
    for (std::size_t r = 0; r < region.ring_count() && t.boundary_ring[h] < 0; ++r) {
      const auto ring = region.ring(r);
      for (std::size_t i = 0; i < ring.size(); ++i) {
        const Vec2 &p = ring[i], &q = ring[(i + 1) % ring.size()];
        const auto on = [&](const Vec2& x) {
          const Vec2 d = q - p, e = x - p;
          return d.x() * e.y() - d.y() * e.x() == 0 && e.dot(d) >= 0 && e.dot(d) <= d.dot(d);
        };
        if (on(a) && on(b)) t.boundary_ring[h] = static_cast<std::int32_t>(r);
      }
    }
  }
  return t;
}

/// Square faces of an n x m grid of cells of size `size` from `origin`, row by row
/// (face index = j * n + i for column i, row j); cells listed in `skip` are left out.
inline std::vector<Face> grid_faces(int n, int m, const Vec2& origin, double size,
                                    const std::vector<std::pair<int, int>>& skip = {}) {
  std::vector<Face> faces;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      if (std::find(skip.begin(), skip.end(), std::pair{i, j}) != skip.end()) continue;
      const Vec2 p = origin + size * Vec2(i, j);
      faces.push_back({p, p + Vec2(size, 0), p + Vec2(size, size), p + Vec2(0, size)});
    }
  return faces;
}

inline Polygon2 unit_square() { return make_region({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}); }

/// The unit square as a 4x4 grid, labelled into its four quadrants
/// (0 lower left, 1 lower right, 2 upper left, 3 upper right).
inline std::vector<std::int32_t> quadrant_labels() {
  std::vector<std::int32_t> labels;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) labels.push_back((i >= 2 ? 1 : 0) + (j >= 2 ? 2 : 0));
  return labels;
}

/// [0,5]^2 with the hole [2,3]^2 as 24 unit squares; part 1 is the ring of cells
/// around the hole, part 0 the outer ring of cells.
struct HoleFixture {
  Polygon2 region = make_region({{{0, 0}, {5, 0}, {5, 5}, {0, 5}}, {{2, 2}, {2, 3}, {3, 3}, {3, 2}}});
  std::vector<Face> faces = grid_faces(5, 5, {0, 0}, 1, {{2, 2}});
  std::vector<std::int32_t> labels;
  HoleFixture() {
    for (const Face& f : faces) {
      const Vec2 c = 0.25 * (f[0] + f[1] + f[2] + f[3]);
      labels.push_back(c.x() > 1 && c.x() < 4 && c.y() > 1 && c.y() < 4 ? 1 : 0);
    }
  }
};

inline Partition build(const Tessellation& t, const std::vector<std::int32_t>& labels, std::size_t parts,
                       const Polygon2& region, const TestFrame& frame = {}) {
  Partition partition;
  build_part_geometry(t, labels, parts, region, frame.maps(), partition);
  return partition;
}

}  // namespace structmesh::partition2d::testing
