// VoxelWindow and FlipCache (voxel_window.hpp): the bit-row engine behind the homotopic
// erosions and dilations of §4.4.2.
//
// A layer of an erosion finds its candidates for all rows at once: a voxel has an empty
// 26-neighbour when its row, or one of the eight rows around it, has an empty voxel at
// x - 1, x or x + 1, so the candidates are the occupied bits of the row AND the OR of
// the nine rows' "empty within one along x" masks, done separably (x, then y, then z).
// The candidates then flip one by one in scan order, each after the simple point and
// well-composedness tests on its current 3x3x3 neighbourhood (simple_voxel.cpp,
// well_composed.cpp), which the cache answers for repeated neighbourhoods.
#include "voxel_window.hpp"

#include "voxel_neighbourhood.hpp"

#include <algorithm>
#include <bit>

namespace structmesh::voxel {

FlipCache::FlipCache()
    : front_(std::size_t{1} << kFrontBits, ~std::uint32_t{0}), back_(std::size_t{1} << kBackBits, ~std::uint32_t{0}) {}

bool FlipCache::may_flip(std::uint32_t config) {
  // The centre's bit says which way it flips; an entry is config << 1 | answer.
  const std::uint32_t hash = config * 0x9E3779B1u;
  std::uint32_t& front = front_[hash >> (32 - kFrontBits)];
  if ((front >> 1) == config) return (front & 1u) != 0;
  std::uint32_t& back = back_[hash >> (32 - kBackBits)];
  if ((back >> 1) != config) {
    const bool answer = is_simple_configuration(config) && is_well_composed_configuration(config ^ kCentre);
    back = (config << 1) | (answer ? 1u : 0u);
  }
  front = back;
  return (back & 1u) != 0;
}

PackedVoxels::PackedVoxels(const VoxelGrid& grid) : dims_(grid.dims), words_((std::max(grid.dims[0], 0) + 63) / 64) {
  rows_.assign(static_cast<std::size_t>(std::max(grid.dims[1], 0)) * std::max(grid.dims[2], 0) * words_, 0);
  for (int z = 0; z < grid.dims[2]; ++z)
    for (int y = 0; y < grid.dims[1]; ++y) {
      const std::uint8_t* grid_row = grid.occupied.data() + grid.index(0, y, z);
      std::uint64_t* row =
          rows_.data() + (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims_[1]) * z) * words_;
      for (int x = 0; x < grid.dims[0]; ++x) row[x >> 6] |= static_cast<std::uint64_t>(grid_row[x] != 0) << (x & 63);
    }
}

bool VoxelWindow::place(const std::array<int, 3>& dims, const VoxelBox& box) {
  for (int a = 0; a < 3; ++a) {
    const int lo = std::max(box.lo[a], 0), hi = std::min(box.hi[a], dims[a]);
    if (hi <= lo) return false;
    origin_[a] = lo - 1;
    size_[a] = hi - lo + 2;
  }
  words_ = (size_[0] + 63) / 64;
  inside_.assign(words_, 0);
  for (int i = 1; i < size_[0] - 1; ++i) inside_[i >> 6] |= std::uint64_t{1} << (i & 63);
  return true;
}

bool VoxelWindow::load(const VoxelGrid& grid, const VoxelBox& box) {
  if (!place(grid.dims, box)) return false;
  rows_.assign(static_cast<std::size_t>(size_[1]) * size_[2] * words_, 0);
  for (int k = 0; k < size_[2]; ++k)
    for (int j = 0; j < size_[1]; ++j) {
      const int gy = origin_[1] + j, gz = origin_[2] + k;
      if (gy < 0 || gy >= grid.dims[1] || gz < 0 || gz >= grid.dims[2]) continue;
      const std::uint8_t* grid_row = grid.occupied.data() + grid.index(0, gy, gz);
      std::uint64_t* row = rows_.data() + row_offset(j, k);
      const int first = std::max(0, -origin_[0]), last = std::min(size_[0], grid.dims[0] - origin_[0]);
      for (int i = first; i < last; ++i)
        row[i >> 6] |= static_cast<std::uint64_t>(grid_row[origin_[0] + i] != 0) << (i & 63);
    }
  loaded_ = rows_;
  return true;
}

bool VoxelWindow::load(const PackedVoxels& packed, const VoxelBox& box) {
  if (!place(packed.dims(), box)) return false;
  rows_.resize(static_cast<std::size_t>(size_[1]) * size_[2] * words_);
  const int tail = size_[0] & 63;  // bits of the last word that are in the window (0: all)
  for (int k = 0; k < size_[2]; ++k)
    for (int j = 0; j < size_[1]; ++j) {
      std::uint64_t* row = rows_.data() + row_offset(j, k);
      for (int w = 0; w < words_; ++w) row[w] = packed.bits(origin_[0] + 64 * w, origin_[1] + j, origin_[2] + k);
      if (tail != 0) row[words_ - 1] &= (std::uint64_t{1} << tail) - 1;
    }
  loaded_ = rows_;
  return true;
}

std::size_t VoxelWindow::store(VoxelGrid& grid, VoxelBox* changed, PackedVoxels* packed) const {
  std::size_t count = 0;
  std::array<int, 3> lo{size_[0], size_[1], size_[2]}, hi{0, 0, 0};
  for (int k = 1; k < size_[2] - 1; ++k)
    for (int j = 1; j < size_[1] - 1; ++j)
      for (int w = 0; w < words_; ++w) {
        const std::size_t at = row_offset(j, k) + w;
        for (std::uint64_t diff = rows_[at] ^ loaded_[at]; diff != 0; diff &= diff - 1) {
          const int i = w * 64 + std::countr_zero(diff);
          const bool value = (rows_[at] >> (i & 63)) & 1;
          grid.set(origin_[0] + i, origin_[1] + j, origin_[2] + k, value);
          if (packed) packed->set(origin_[0] + i, origin_[1] + j, origin_[2] + k, value);
          lo = {std::min(lo[0], i), std::min(lo[1], j), std::min(lo[2], k)};
          hi = {std::max(hi[0], i + 1), std::max(hi[1], j + 1), std::max(hi[2], k + 1)};
          ++count;
        }
      }
  if (changed && count > 0)
    for (int a = 0; a < 3; ++a) {
      changed->lo[a] = origin_[a] + lo[a];
      changed->hi[a] = origin_[a] + hi[a];
    }
  return count;
}

template <bool kOneWord>
std::size_t VoxelWindow::layer(bool erosion, const std::uint64_t* allowed) {
  // kOneWord: the rows fit in one word (boxes up to 62 voxels long, which takes
  // optimize_polycube's windows up to radius 15), and the loops over words go.
  const int nj = size_[1], nk = size_[2], nw = kOneWord ? 1 : words_;
  const std::size_t row_count = static_cast<std::size_t>(nj) * nk;
  const std::uint64_t flip_mask = erosion ? ~std::uint64_t{0} : 0;  // XOR: the state that makes a candidate
  // Voxels of the other state (the ones that make a candidate) within one along x ...
  near_x_.resize(rows_.size());
  for (std::size_t r = 0; r < row_count; ++r) {
    const std::uint64_t* row = rows_.data() + r * nw;
    std::uint64_t* out = near_x_.data() + r * nw;
    for (int w = 0; w < nw; ++w) {
      const std::uint64_t here = row[w] ^ flip_mask;
      const std::uint64_t below = w > 0 ? row[w - 1] ^ flip_mask : 0;
      const std::uint64_t above = w + 1 < nw ? row[w + 1] ^ flip_mask : 0;
      out[w] = here | (here << 1) | (below >> 63) | (here >> 1) | (above << 63);
    }
  }
  // ... within one along x and y ...
  near_xy_.resize(rows_.size());
  for (int k = 0; k < nk; ++k)
    for (int j = 1; j < nj - 1; ++j)
      for (int w = 0; w < nw; ++w)
        near_xy_[row_offset(j, k) + w] =
            near_x_[row_offset(j - 1, k) + w] | near_x_[row_offset(j, k) + w] | near_x_[row_offset(j + 1, k) + w];
  // ... and within one along all three: the candidates of this layer, and the rows
  // that have some.
  candidates_.assign(rows_.size(), 0);
  lines_.clear();
  for (int k = 1; k < nk - 1; ++k)
    for (int j = 1; j < nj - 1; ++j) {
      std::uint64_t any = 0;
      for (int w = 0; w < nw; ++w) {
        const std::size_t at = row_offset(j, k) + w;
        const std::uint64_t near =
            near_xy_[row_offset(j, k - 1) + w] | near_xy_[at] | near_xy_[row_offset(j, k + 1) + w];
        candidates_[at] = ~(rows_[at] ^ flip_mask) & near & inside_[w] & (allowed ? allowed[at] : ~std::uint64_t{0});
        any |= candidates_[at];
      }
      if (any != 0) lines_.push_back({j, k});
    }
  // Scan order; a candidate that may not flip yet (typically because a neighbour that
  // leaves later in the same layer would leave a critical configuration behind it) is
  // tried again in another pass, until a pass flips nothing.
  std::size_t flipped = 0;
  for (std::size_t pass_flipped = 1; pass_flipped > 0;) {
    pass_flipped = 0;
    std::size_t kept = 0;  // lines that still have candidates, compacted in place
    for (const auto& [j, k] : lines_) {
      std::uint64_t* candidates = candidates_.data() + row_offset(j, k);
      std::uint64_t* row = rows_.data() + row_offset(j, k);
      std::array<const std::uint64_t*, 9> around;  // rows (j + dy - 1, k + dz - 1) at dy + 3 * dz
      for (int t = 0; t < 9; ++t) around[t] = rows_.data() + row_offset(j + t % 3 - 1, k + t / 3 - 1);
      std::uint64_t left = 0;
      for (int w = 0; w < nw; ++w) {
        for (std::uint64_t bits = candidates[w]; bits != 0; bits &= bits - 1) {
          const int bit = std::countr_zero(bits);
          // The 27-bit neighbourhood: bits i - 1 .. i + 1 of the nine rows.
          const int first = w * 64 + bit - 1, word = first >> 6, shift = first & 63;
          std::uint32_t config = 0;
          for (int t = 0; t < 9; ++t) {
            std::uint64_t three = around[t][word] >> shift;
            if (!kOneWord && shift > 61 && word + 1 < nw) three |= around[t][word + 1] << (64 - shift);
            config |= static_cast<std::uint32_t>(three & 7u) << (3 * t);
          }
          if (cache_.may_flip(config)) {
            row[w] ^= std::uint64_t{1} << bit;
            candidates[w] &= ~(std::uint64_t{1} << bit);
            ++pass_flipped;
          }
        }
        left |= candidates[w];
      }
      if (left != 0) lines_[kept++] = {j, k};
    }
    lines_.resize(kept);
    flipped += pass_flipped;
  }
  return flipped;
}

std::size_t VoxelWindow::layer(bool erosion, const std::uint64_t* allowed) {
  return words_ == 1 ? layer<true>(erosion, allowed) : layer<false>(erosion, allowed);
}

std::size_t VoxelWindow::erode(const std::uint64_t* allowed) { return layer(true, allowed); }
std::size_t VoxelWindow::dilate(const std::uint64_t* allowed) { return layer(false, allowed); }

std::size_t VoxelWindow::open(int layers) {
  snapshot_ = rows_;
  std::size_t flipped = 0;
  for (int l = 0; l < layers; ++l) flipped += erode();
  for (int l = 0; l < layers; ++l) flipped += dilate(snapshot_.data());
  return flipped;
}

std::size_t VoxelWindow::close(int layers) {
  snapshot_.resize(rows_.size());
  std::transform(rows_.begin(), rows_.end(), snapshot_.begin(), [](std::uint64_t w) { return ~w; });
  std::size_t flipped = 0;
  for (int l = 0; l < layers; ++l) flipped += dilate();
  for (int l = 0; l < layers; ++l) flipped += erode(snapshot_.data());
  return flipped;
}

}  // namespace structmesh::voxel
