// merge_facet_planes(): fewer distinct facet planes on the polycube, by moving every facet
// of a plane onto a neighbouring plane that some other facet already uses.
//
// Why: the hex grid of chapter 5 (polycube_hex_grid) is the tensor product of the facet
// planes, and every slab between two planes takes at least one layer of hexes. The window
// optimisation of (4.1) removes bumps but not long one-voxel steps (a window sees only a
// part of the step), so a voxelized curved surface keeps a plane every voxel or two: the
// rocker arm kept 60 x-planes for 18k hexes asked and got 76k thin hexes. Moving a small
// facet by a voxel or two is a change of the same size as the window's (a voxel layer of
// the facet's area) but removes a whole plane.
//
// Each move flips the voxels between the facet and its target plane, layer by layer from
// the facet outward; every flip must be simple when it is made (so the topology is kept,
// as in §4.4.2's homotopic operations), and the whole plane's moves are undone unless the
// plane is gone, no new plane appeared and the voxels are still well-composed.
//
// Written by hand: it works on our voxel grid and its simple-voxel test.
#include "structmesh/polycube.hpp"
#include "structmesh/progress.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace structmesh {
namespace {

class PlaneMerger {
 public:
  explicit PlaneMerger(VoxelGrid& grid) : grid_(grid) {
    for (int axis = 0; axis < 3; ++axis) faces_[axis].assign(static_cast<std::size_t>(grid.dims[axis]) + 1, 0);
    for (int z = 0; z < grid.dims[2]; ++z)
      for (int y = 0; y < grid.dims[1]; ++y)
        for (int x = 0; x < grid.dims[0]; ++x)
          for (int axis = 0; axis < 3; ++axis) {
            std::array<int, 3> v{x, y, z};
            count_face(axis, v, +1);
          }
    // The faces at the upper end of each axis (voxel dims - 1 against outside) are never
    // facets: the grid keeps an empty border layer.
  }

  std::size_t planes(int axis) const {
    return static_cast<std::size_t>(
        std::count_if(faces_[axis].begin(), faces_[axis].end(), [](std::size_t n) { return n > 0; }));
  }
  std::size_t flips() const { return flips_; }
  const std::vector<std::size_t>& face_counts(int axis) const { return faces_[axis]; }

  // Tries to empty plane c of `axis`; returns whether it is gone (otherwise nothing changed).
  bool remove_plane(int axis, int c, int max_shift) {
    if (faces_[axis][static_cast<std::size_t>(c)] == 0) return false;
    const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
    const int nu = grid_.dims[u_axis], nv = grid_.dims[v_axis];
    // Orientation of each face of the plane: +1 solid below (at c - 1), -1 solid above, 0 none.
    std::vector<signed char> orientation(static_cast<std::size_t>(nu) * nv, 0);
    for (int v = 0; v < nv; ++v)
      for (int u = 0; u < nu; ++u) {
        const bool below = at(axis, c - 1, u, v), above = at(axis, c, u, v);
        if (below != above)
          orientation[static_cast<std::size_t>(u) + static_cast<std::size_t>(nu) * v] = below ? 1 : -1;
      }
    const std::array<std::vector<std::size_t>, 3> planes_before = faces_;
    journal_.clear();
    // Facets: 4-connected groups of faces with one orientation.
    std::vector<int> facet(orientation.size(), -1);
    std::vector<std::size_t> stack, members;
    int facets = 0;
    bool ok = true;
    for (std::size_t start = 0; start < orientation.size() && ok; ++start) {
      if (orientation[start] == 0 || facet[start] >= 0) continue;
      members.clear();
      stack.assign(1, start);
      facet[start] = facets;
      while (!stack.empty()) {
        const std::size_t f = stack.back();
        stack.pop_back();
        members.push_back(f);
        const int u = static_cast<int>(f % static_cast<std::size_t>(nu)),
                  v = static_cast<int>(f / static_cast<std::size_t>(nu));
        const std::array<std::array<int, 2>, 4> next{{{u - 1, v}, {u + 1, v}, {u, v - 1}, {u, v + 1}}};
        for (const auto& [a, b] : next) {
          if (a < 0 || b < 0 || a >= nu || b >= nv) continue;
          const std::size_t g = static_cast<std::size_t>(a) + static_cast<std::size_t>(nu) * b;
          if (facet[g] < 0 && orientation[g] == orientation[start]) facet[g] = facets, stack.push_back(g);
        }
      }
      ++facets;
      ok = move_facet(axis, c, members, orientation[start], max_shift, planes_before[axis]);
    }
    if (ok) ok = faces_[axis][static_cast<std::size_t>(c)] == 0 && no_new_plane(planes_before) && well_composed_after();
    if (!ok) undo();
    return ok;
  }

 private:
  // Voxel at coordinate w along `axis` and (u, v) along the next two axes.
  std::array<int, 3> voxel(int axis, int w, int u, int v) const {
    std::array<int, 3> p{};
    p[axis] = w;
    p[(axis + 1) % 3] = u;
    p[(axis + 2) % 3] = v;
    return p;
  }
  bool at(int axis, int w, int u, int v) const {
    const auto p = voxel(axis, w, u, v);
    return grid_.at(p[0], p[1], p[2]);
  }

  // Adds `sign` to the facet count of the face below voxel p along `axis` if it is a facet.
  void count_face(int axis, const std::array<int, 3>& p, int sign) {
    std::array<int, 3> q = p;
    --q[axis];
    if (grid_.at(p[0], p[1], p[2]) != grid_.at(q[0], q[1], q[2]))
      faces_[axis][static_cast<std::size_t>(p[axis])] += static_cast<std::size_t>(sign);
  }

  // Flips voxel p, keeping the facet counts of its six faces.
  void flip(const std::array<int, 3>& p) {
    for (int axis = 0; axis < 3; ++axis) {
      std::array<int, 3> q = p;
      ++q[axis];
      count_face(axis, p, -1);
      count_face(axis, q, -1);
    }
    grid_.set(p[0], p[1], p[2], !grid_.at(p[0], p[1], p[2]));
    for (int axis = 0; axis < 3; ++axis) {
      std::array<int, 3> q = p;
      ++q[axis];
      count_face(axis, p, +1);
      count_face(axis, q, +1);
    }
    journal_.push_back(p);
    ++flips_;
  }

  void undo() {
    std::vector<std::array<int, 3>> journal;
    journal.swap(journal_);
    for (auto it = journal.rbegin(); it != journal.rend(); ++it) flip(*it);
    flips_ -= 2 * journal.size();
    journal_.clear();
  }

  bool flippable(const std::array<int, 3>& p) const {
    // The outermost layer stays empty: the grid keeps its empty border.
    for (int a = 0; a < 3; ++a)
      if (p[a] <= 0 || p[a] >= grid_.dims[a] - 1) return false;
    return is_simple_voxel(grid_, p[0], p[1], p[2]);
  }

  // Moves one facet (its faces on plane c, `orientation` +1 with the solid below) to the
  // nearest plane within max_shift that already has facets, trying the nearer shifts first.
  bool move_facet(int axis, int c, const std::vector<std::size_t>& members, int orientation, int max_shift,
                  const std::vector<std::size_t>& planes_before) {
    const int nu = grid_.dims[(axis + 1) % 3];
    for (int distance = 1; distance <= max_shift; ++distance)
      for (const int d : {distance, -distance}) {
        const int target = c + d;
        if (target <= 0 || target >= grid_.dims[axis] || planes_before[static_cast<std::size_t>(target)] == 0) continue;
        // Voxels between c and the target: at c .. c + d - 1 going up, c + d .. c - 1 going
        // down, nearest the facet first. They turn solid when the facet moves away from
        // the solid side (up with the solid below), empty otherwise.
        const bool add = (d > 0) == (orientation > 0);
        // Only a clean translation: every voxel between the facet and the target, and the
        // one just beyond the target, must be in the state the facet leaves behind, so the
        // facet arrives whole on the target plane. A facet that would run into material on
        // the way fills a gap instead (it glued the hand's fingers together).
        std::vector<std::array<int, 3>> pending;
        bool clean = true;
        for (int layer = 0; layer <= distance && clean; ++layer) {
          const int w = d > 0 ? c + layer : c - 1 - layer;
          for (const std::size_t f : members) {
            const int u = static_cast<int>(f % static_cast<std::size_t>(nu)),
                      v = static_cast<int>(f / static_cast<std::size_t>(nu));
            const auto p = voxel(axis, w, u, v);
            if (grid_.at(p[0], p[1], p[2]) == add) {
              clean = false;
              break;
            }
            if (layer < distance) pending.push_back(p);
          }
        }
        if (!clean) continue;
        const std::size_t mark = journal_.size();
        // Passes over what is left: a flip that is not simple yet may be once its
        // neighbours have flipped.
        for (bool progress = true; progress && !pending.empty();) {
          progress = false;
          std::size_t kept = 0;
          for (const auto& p : pending) {
            if (grid_.at(p[0], p[1], p[2]) == add) continue;
            if (flippable(p)) {
              flip(p);
              progress = true;
            } else {
              pending[kept++] = p;
            }
          }
          pending.resize(kept);
        }
        if (pending.empty()) return true;
        while (journal_.size() > mark) {  // this shift failed: undo its flips only
          const auto p = journal_.back();
          journal_.pop_back();
          flip(p);
          journal_.pop_back();
          flips_ -= 2;
        }
      }
    return false;
  }

  bool no_new_plane(const std::array<std::vector<std::size_t>, 3>& before) const {
    for (int axis = 0; axis < 3; ++axis)
      for (std::size_t w = 0; w < before[axis].size(); ++w)
        if (faces_[axis][w] > 0 && before[axis][w] == 0) return false;
    return true;
  }

  bool well_composed_after() const {
    return std::all_of(journal_.begin(), journal_.end(),
                       [&](const auto& p) { return is_well_composed_near(grid_, p[0], p[1], p[2]); });
  }

  VoxelGrid& grid_;
  std::array<std::vector<std::size_t>, 3> faces_;  // per axis and lattice coordinate: facet faces
  std::vector<std::array<int, 3>> journal_;        // flips of the current plane, in order
  std::size_t flips_ = 0;
};

}  // namespace

PlaneMergeResult merge_facet_planes(VoxelGrid& grid, int max_shift, bool progress) {
  PlaneMergeResult result;
  if (grid.count() == 0) return result;
  PlaneMerger merger(grid);
  for (int axis = 0; axis < 3; ++axis) result.planes_before[axis] = merger.planes(axis);
  result.planes_after = result.planes_before;
  if (max_shift <= 0) return result;  // the planes counted, nothing moved
  // Rounds over the three axes, the planes with the fewest facet faces first (the cheapest
  // to move), until a round removes nothing.
  for (bool removed = true; removed;) {
    removed = false;
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<std::pair<std::size_t, int>> planes;
      const std::vector<std::size_t>& counts = merger.face_counts(axis);
      for (std::size_t w = 0; w < counts.size(); ++w)
        if (counts[w] > 0) planes.emplace_back(counts[w], static_cast<int>(w));
      std::sort(planes.begin(), planes.end());
      for (const auto& [faces, w] : planes)
        if (merger.remove_plane(axis, w, max_shift)) {
          removed = true;
          ++result.removed;
        }
    }
  }
  for (int axis = 0; axis < 3; ++axis) result.planes_after[axis] = merger.planes(axis);
  result.flips = merger.flips();
  if (progress)
    status("polycube: facet planes merged: " + std::to_string(result.removed) + " removed, x/y/z planes " +
           std::to_string(result.planes_before[0]) + "/" + std::to_string(result.planes_before[1]) + "/" +
           std::to_string(result.planes_before[2]) + " -> " + std::to_string(result.planes_after[0]) + "/" +
           std::to_string(result.planes_after[1]) + "/" + std::to_string(result.planes_after[2]));
  return result;
}

}  // namespace structmesh
