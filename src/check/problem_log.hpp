// Collects Problems with a cap per kind; the caller keeps the complete counts.
#pragma once

#include "structmesh/check.hpp"

#include <cstdint>
#include <map>
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

}  // namespace structmesh::detail
