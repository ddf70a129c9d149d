// Internal: the box of voxels the homotopic operations of §4.4.2 work in, held as bit
// rows so that one erosion or dilation layer costs a few word operations per row plus
// one table look-up per candidate voxel. Used by homotopic_morphology.cpp (the public
// operations on any box) and optimize_polycube.cpp (thousands of small windows).
#pragma once

#include "structmesh/polycube.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace structmesh::voxel {

/// Remembers, per 26-neighbourhood, whether its centre may be removed and whether it may
/// be added (simple, and well-composed around it afterwards): a few thousand distinct
/// neighbourhoods make up nearly all look-ups on a voxelized surface.
class FlipCache {
 public:
  FlipCache();
  /// Whether the centre of `config` (a 27-bit configuration) may flip: simple, and no
  /// critical configuration around it after the flip.
  bool may_flip(std::uint32_t config);

 private:
  // A small table that stays in the L1 cache in front of a larger one; direct-mapped.
  static constexpr int kFrontBits = 11, kBackBits = 16;
  std::vector<std::uint32_t> front_, back_;  // config << 1 | answer; ~0 when empty
};

/// The voxels of a grid as bit rows (bit x of row (y, z)), so that a window loads a
/// row with a shift instead of a byte per voxel.
class PackedVoxels {
 public:
  explicit PackedVoxels(const VoxelGrid& grid);
  const std::array<int, 3>& dims() const { return dims_; }
  /// Voxels start .. start + 63 of row (y, z), any integers; 0 outside the grid.
  std::uint64_t bits(int start, int y, int z) const {
    if (y < 0 || z < 0 || y >= dims_[1] || z >= dims_[2] || start >= dims_[0] || start <= -64) return 0;
    const std::uint64_t* row =
        rows_.data() + (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims_[1]) * z) * words_;
    if (start < 0) return row[0] << -start;
    const int word = start >> 6, shift = start & 63;
    std::uint64_t bits = row[word] >> shift;
    if (shift != 0 && word + 1 < words_) bits |= row[word + 1] << (64 - shift);
    return bits;
  }
  void set(int x, int y, int z, bool value) {
    std::uint64_t& word =
        rows_[(static_cast<std::size_t>(y) + static_cast<std::size_t>(dims_[1]) * z) * words_ + (x >> 6)];
    const std::uint64_t bit = std::uint64_t{1} << (x & 63);
    word = value ? word | bit : word & ~bit;
  }

 private:
  std::array<int, 3> dims_{};
  int words_ = 0;
  std::vector<std::uint64_t> rows_;
};

/// A box of voxels that may flip and the layer of voxels around it that they see, as
/// rows along x of 64-bit words. Local voxel (i, j, k) is grid voxel origin + (i, j, k);
/// the box is local [1, n - 1) on each axis. Voxels outside the grid are empty.
class VoxelWindow {
 public:
  /// Reads `box` (clamped to the grid) and its surrounding layer; false if the clamped
  /// box is empty.
  bool load(const VoxelGrid& grid, const VoxelBox& box);
  /// The same from a packed copy of the grid.
  bool load(const PackedVoxels& packed, const VoxelBox& box);
  /// Writes the box's voxels that differ from the loaded ones (to `packed` too, if
  /// given); returns their count, and in `changed` (if given and the count is not 0)
  /// the grid box they span.
  std::size_t store(VoxelGrid& grid, VoxelBox* changed = nullptr, PackedVoxels* packed = nullptr) const;

  /// One homotopic erosion (dilation) layer: the candidates are the occupied (empty)
  /// voxels of the box with an empty (occupied) 26-neighbour at the start of the layer,
  /// and, when `allowed` is given (rows like row()), marked there; each flips in scan
  /// order if it may then, and the ones that may not are tried again in further passes
  /// until a pass flips nothing. Returns the number flipped.
  std::size_t erode(const std::uint64_t* allowed = nullptr);
  std::size_t dilate(const std::uint64_t* allowed = nullptr);
  /// `layers` erosions, then `layers` dilations that restore only voxels the erosions
  /// removed (so an opening never adds a voxel).
  std::size_t open(int layers);
  /// `layers` dilations, then `layers` erosions that remove only voxels the dilations
  /// added (so a closing never removes one).
  std::size_t close(int layers);

  /// Back to the loaded state.
  void reset() { rows_ = loaded_; }
  /// Whether some voxel differs from the loaded state.
  bool changed() const { return rows_ != loaded_; }

  const std::array<int, 3>& origin() const { return origin_; }
  const std::array<int, 3>& size() const { return size_; }
  int words() const { return words_; }
  /// Row (j, k): words() words, bit i of the row = local voxel (i, j, k).
  const std::uint64_t* row(int j, int k) const { return rows_.data() + row_offset(j, k); }
  const std::uint64_t* loaded_row(int j, int k) const { return loaded_.data() + row_offset(j, k); }
  /// All loaded rows: what the outcome of any operation in the window depends on.
  const std::vector<std::uint64_t>& loaded_rows() const { return loaded_; }

 private:
  /// Sets the window's extent for `box` clamped to a grid of `dims`; false if empty.
  bool place(const std::array<int, 3>& dims, const VoxelBox& box);
  std::size_t row_offset(int j, int k) const {
    return (static_cast<std::size_t>(j) + static_cast<std::size_t>(size_[1]) * k) * words_;
  }
  std::size_t layer(bool erosion, const std::uint64_t* allowed);
  template <bool kOneWord>
  std::size_t layer(bool erosion, const std::uint64_t* allowed);

  std::array<int, 3> origin_{}, size_{};
  int words_ = 0;
  std::vector<std::uint64_t> rows_, loaded_;
  std::vector<std::uint64_t> inside_;  // one row: the bits of the box, 1 .. size - 2
  std::vector<std::uint64_t> near_x_, near_xy_, candidates_, snapshot_;
  std::vector<std::array<int, 2>> lines_;  // rows (j, k) with candidates left
  FlipCache cache_;
};

}  // namespace structmesh::voxel
