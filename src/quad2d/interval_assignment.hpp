// Interval assignment: segment counts for the boundary edges of all parts at once,
// so that every part has an even number of boundary points and every four-sided
// part has equal counts on opposite sides (then it can be meshed as a structured
// grid, without interior singular vertices; see mapped_mesh()).
#pragma once

#include "structmesh/mesh.hpp"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace structmesh::quad2d {

struct IntervalProblem {
  std::vector<double> ideal;   ///< per edge: length / size
  std::vector<Index> minimum;  ///< per edge: the smallest allowed count (>= 1)
  /// Per edge: a count fixed in advance (kInvalidIndex or an empty vector: free).
  std::vector<Index> fixed;
  /// Per part: its edges (each once per loop it bounds); the counts must sum to an even number.
  std::vector<std::vector<Index>> part_edges;
  /// Per part_edges entry: the partition part it belongs to (entries of one part may
  /// repeat); empty: entry i is part i. Groups the entries for the clustered solve.
  std::vector<std::size_t> part_ids;
  struct FourSided {
    std::size_t part = 0;
    std::array<std::vector<Index>, 4> sides;  ///< edges of each side, in loop order
  };
  std::vector<FourSided> four_sided;  ///< parts to make mappable where possible
  /// Parts with n >= 3 corners to cut into n blocks around a centre (polar_mesh()):
  /// side i (corner i to i+1) must have r_{i-1} + r_{i+1} segments, r_i >= 1 the
  /// segments of the chord from side i's split point to the centre.
  struct Polar {
    std::size_t part = 0;
    std::vector<std::vector<Index>> sides;  ///< edges of each side, in loop order
    std::vector<double> chord_ideal;        ///< per chord: its length / size
    double reward = 1.5;  ///< objective reward when its counts hold (a grid's is 2: no singular point)
  };
  std::vector<Polar> polar;
  /// (four_sided index, polar index) pairs of the same part, of which at most one may
  /// be rewarded (z_f + y_q <= 1).
  std::vector<std::pair<std::size_t, std::size_t>> exclusive;
};

struct IntervalSolution {
  bool solved = false;                             ///< false: the caller falls back to rounding + parity repair
  std::vector<Index> counts;                       ///< per edge
  std::vector<std::uint8_t> mapped;                ///< per four_sided entry: opposite sides match
  std::vector<std::uint8_t> polar;                 ///< per polar entry: the block counts hold
  std::vector<std::vector<Index>> chord_segments;  ///< per polar entry: r_i
};

/// Minimises the summed relative deviation |n_e - ideal_e| / max(1, ideal_e) minus a
/// reward for every four-sided part whose opposite sides match and every polar part
/// whose block counts hold, subject to the even
/// parity of every part (an MILP solved by COIN-OR CBC with a node limit, so the
/// answer does not depend on the machine's speed).
///
/// When the whole problem has no integer solution within the node limit (plain branch
/// and bound found none from about 200 parts on: the Key at 2M quads in 256 or 1024
/// parts got no structured block at all) and it has more than 24 parts, it is solved
/// in clusters of up to 24 neighbouring parts (breadth-first over parts sharing edges,
/// from the lowest part id), one after the other, each with the edges that earlier
/// clusters decided fixed. A cluster without a solution keeps the rounded counts and no
/// block, and the parity of its parts is left to the caller (`solved` is still true).
IntervalSolution solve_interval_assignment(const IntervalProblem& problem);

/// The clustered solve above with clusters of up to `cluster_parts` parts (exposed for
/// tests). InputError for zero.
IntervalSolution solve_interval_assignment_in_clusters(const IntervalProblem& problem, std::size_t cluster_parts);

}  // namespace structmesh::quad2d
