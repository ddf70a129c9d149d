// Collects Problems with a cap per kind; the caller keeps the complete counts.
// Also the tests and reports that more than one check_*() makes.
#pragma once

#include "structmesh/check.hpp"

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace structmesh::detail {

class ProblemLog {
 public:
  ProblemLog(std::vector<Problem>& out, std::size_t max_per_kind) : out_(out), max_per_kind_(max_per_kind) {}

  /// True while `kind` is under its cap: test it before building a costly message.
  bool wants(const std::string& kind) const {
    const auto it = counts_.find(kind);
    return it == counts_.end() || it->second < max_per_kind_;
  }

  void add(const std::string& kind, std::string message, std::uint32_t line = 0, std::int64_t element = -1) {
    std::size_t& count = counts_[kind];
    if (count >= max_per_kind_) return;
    ++count;
    out_.push_back({kind, std::move(message), line, element});
  }

 private:
  std::vector<Problem>& out_;
  std::size_t max_per_kind_;
  std::map<std::string, std::size_t> counts_;
};

/// Source line of element `i` when the reader recorded one, else 0.
inline std::uint32_t line_of(const std::vector<std::uint32_t>& lines, std::size_t i) {
  return i < lines.size() ? lines[i] : 0;
}

/// Reports each point with a NaN or infinite coordinate ("non-finite-point") and
/// returns how many there are: the checks stop when there are any, because no
/// measure of the cells means anything then.
inline std::size_t report_non_finite_points(const MeshBundle& mesh, ProblemLog& log) {
  std::size_t non_finite = 0;
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    if (mesh.points[v].allFinite()) continue;
    ++non_finite;
    if (log.wants("non-finite-point"))
      log.add("non-finite-point", "vertex " + std::to_string(v) + " has a NaN or infinite coordinate",
              line_of(mesh.lines.point_lines, v));
  }
  return non_finite;
}

/// True when a face or cell names one vertex twice.
inline bool repeats_vertex(std::span<const Index> v) {
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = i + 1; j < v.size(); ++j)
      if (v[i] == v[j]) return true;
  return false;
}

}  // namespace structmesh::detail
