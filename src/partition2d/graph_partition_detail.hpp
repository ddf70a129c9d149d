// Pieces of partition_cell_graph shared by graph_partition.cpp, exact_bisection.cpp
// and their tests (design §2.7, §2.8).
#pragma once

#include "partition2d/partition_internal.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace structmesh::partition2d::detail {

/// One bisection of a node group (design §2.7): the nodes currently labelled
/// `label0` are split into a side keeping `label0` and a side taking `label1`.
/// Every other node keeps its label; its separators and corners still count in J.
struct BisectionProblem {
  std::vector<Index> nodes;  ///< the group, ascending
  std::int32_t label0 = 0, label1 = 1;
  double lo0 = 0, hi0 = 0;  ///< area band of side 0, eq. (3.1)
  double lo1 = 0, hi1 = 0;  ///< area band of side 1
  double lambda = 0;        ///< J = L_S + lambda * D_theta
  bool boundary_corners = true;
};

/// Eq. (3.1) per bisection: side i gets k_i of the k parts of a group of area W, so
/// its target is W k_i / k and its band target * (1 -/+ tolerance), widened to half
/// the largest node's area so that a band always contains an attainable sum.
BisectionProblem make_bisection(const CellGraph& graph, std::vector<Index> nodes, std::int32_t label0,
                                std::int32_t label1, std::size_t k0, std::size_t k1, double tolerance, double lambda,
                                bool boundary_corners);

/// Per-bisection tolerance: the recursion has depth d = ceil(log2 k); with
/// (1 + t)^d = sqrt(1 + imbalance) a part that stays in every band ends in the
/// k-way band [A/sqrt(1+e), A sqrt(1+e)] (so max/min <= 1 + e).
double bisection_tolerance(std::size_t parts, double imbalance);

/// L_S (3.3): total length of arcs between different labels.
double separator_length(const CellGraph& graph, std::span<const std::int32_t> labels);
/// D_theta (3.7) as corner_cost counts it, plus the boundary corners when asked.
double angle_cost(const CellGraph& graph, std::span<const std::int32_t> labels, bool boundary_corners);
/// J = L_S + lambda D_theta.
double objective(const CellGraph& graph, std::span<const std::int32_t> labels, double lambda, bool boundary_corners);

/// The first bisection exactly as the RecursiveGp engine runs it on the whole graph
/// (METIS 2-way with targets k0/k, k1/k, refinement of J, repair): labels 0 / 1.
std::vector<std::int32_t> gp_first_bisection(const CellGraph& graph, const GraphPartitionOptions& options);
/// The problem that first bisection solves (labels 0 / 1, every node in the group).
BisectionProblem first_bisection_problem(const CellGraph& graph, const GraphPartitionOptions& options);

struct ExactBisectionResult {
  double objective = 0;  ///< the MILP's J of the group (without separators to other groups)
  double bound = 0;      ///< best bound on it
  bool proven = false;   ///< optimal and connected
  std::size_t connectivity_cuts = 0;
  std::size_t solves = 0;
};

/// Design §2.8: MILP of the bisection (linearised L_S + lambda D_theta, balance,
/// lazy connectivity cuts (3.9)/(3.10)) solved with CBC within `seconds`. Writes the
/// sides into `labels` (nodes of the group only). Error when no feasible bisection
/// is found in time.
ExactBisectionResult exact_bisection(const CellGraph& graph, std::span<std::int32_t> labels,
                                     const BisectionProblem& problem, double seconds);

}  // namespace structmesh::partition2d::detail
