// greedy_set_cover(): the greedy guarding of §2.2.2 (an O(log n) approximation,
// Chvátal 1979), made exact about ties and O(total size x log).
#include "guard/set_cover_input.hpp"
#include "structmesh/guard.hpp"

#include <cstdint>
#include <queue>
#include <utility>
#include <vector>

namespace structmesh {

std::vector<Index> greedy_set_cover(const CompressedRows& sets, std::size_t element_count) {
  guard::require_coverable(sets, element_count, "greedy_set_cover");
  const std::size_t set_count = sets.row_count();
  // Element -> sets (a set listing an element twice is recorded once: element e's sets
  // are items[offsets[e] .. end[e])), and the number of still uncovered elements of
  // each set, kept exact by decrementing through it.
  CompressedRows element_sets;
  element_sets.offsets.assign(element_count + 1, 0);
  for (const Index e : sets.items) ++element_sets.offsets[e + 1];
  for (std::size_t e = 0; e < element_count; ++e) element_sets.offsets[e + 1] += element_sets.offsets[e];
  std::vector<Index> end(element_sets.offsets.begin(), element_sets.offsets.end() - 1);
  element_sets.items.assign(sets.items.size(), 0);
  std::vector<Index> uncovered(set_count, 0);
  for (Index c = 0; c < set_count; ++c)
    for (const Index e : sets.row(c)) {
      // Sets are visited in order, so a repeated (c, e) would be the last entry of e.
      if (end[e] > element_sets.offsets[e] && element_sets.items[end[e] - 1] == c) continue;
      element_sets.items[end[e]++] = c;
      ++uncovered[c];
    }

  // Lazy priority queue: an entry's count is an upper bound of the set's current one
  // (counts only fall). A popped entry whose count is current is a true maximum, and
  // the order (count descending, index ascending) makes it the lowest-index one. Each
  // stale pop follows at least one decrement, so there are O(total size) pushes.
  using Entry = std::pair<Index, Index>;  // (count, set)
  const auto lower_priority = [](const Entry& x, const Entry& y) {
    return x.first != y.first ? x.first < y.first : x.second > y.second;
  };
  std::priority_queue<Entry, std::vector<Entry>, decltype(lower_priority)> queue(lower_priority);
  for (Index c = 0; c < set_count; ++c)
    if (uncovered[c] > 0) queue.emplace(uncovered[c], c);

  std::vector<std::uint8_t> covered(element_count, 0);
  std::size_t remaining = element_count;
  std::vector<Index> chosen;
  while (remaining > 0) {
    const auto [count, c] = queue.top();
    queue.pop();
    if (count != uncovered[c]) {
      if (uncovered[c] > 0) queue.emplace(uncovered[c], c);
      continue;
    }
    chosen.push_back(c);
    for (const Index e : sets.row(c)) {
      if (covered[e] != 0) continue;
      covered[e] = 1;
      --remaining;
      for (Index k = element_sets.offsets[e]; k < end[e]; ++k) --uncovered[element_sets.items[k]];
    }
  }
  return chosen;
}

}  // namespace structmesh
