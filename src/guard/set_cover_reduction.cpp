// reduce_set_cover(): the reductions the progressive ILP applies before each solve
// (§2.2.3, rules 1-3, plus duplicate rows), repeated until none applies. Guard
// instances collapse under them: neighbouring faces are mostly seen by the same
// candidates, so most rows are duplicates or supersets of a few (RECIPES.md: a
// 38k-face tube went from 38,496 rows to 392).
//
// Rows are elements (faces), columns are sets (candidates), as in ILP (2.3).
//
// Cost per round: O(nnz + rows log rows) to compact the lists, apply rule 1 and sort
// rows by hash for duplicates. Dominance compares a row s only with the rows that
// share s's rarest column (any superset of s must contain it), after a 64-bit
// signature filter, so it costs O(sum over s of |rows of s's rarest column| x |s|);
// the same on the transpose for columns. That is quadratic on adversarial instances but close to
// linear on guard instances, where duplicates are gone before dominance is tried.
// Rounds end when nothing changes (a handful in practice).
#include "guard/set_cover_input.hpp"
#include "structmesh/guard.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace structmesh {

namespace {

using Lists = std::vector<std::vector<Index>>;

std::uint64_t bit_of(Index i) {
  // A multiplicative hash spreads consecutive ids over the 64 bits.
  return std::uint64_t{1} << ((static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull) >> 58);
}

std::uint64_t signature(const std::vector<Index>& list) {
  std::uint64_t s = 0;
  for (const Index i : list) s |= bit_of(i);
  return s;
}

/// Drops dead entries from every live list.
void compact(Lists& lists, const std::vector<std::uint8_t>& alive, const std::vector<std::uint8_t>& entry_alive) {
  for (std::size_t i = 0; i < lists.size(); ++i) {
    if (alive[i] == 0) {
      lists[i].clear();
      continue;
    }
    std::erase_if(lists[i], [&](Index j) { return entry_alive[j] == 0; });
  }
}

enum class Remove { Superset, Subset };

/// For every pair of live lists with one a subset of the other, removes the superset
/// (rows: rule 2) or the subset (columns: rule 3); of two equal lists the higher index
/// goes. `other` is the transpose: every superset of list s contains s's rarest entry,
/// so only the lists sharing it are compared. Removing along chains is safe because
/// "subset of" is transitive: whatever a removed list would have removed, the list
/// that removed it (or the end of that chain, which stays) removes too.
bool remove_dominated(const Lists& lists, const Lists& other, std::vector<std::uint8_t>& alive, Remove which) {
  std::vector<std::uint64_t> sig(lists.size(), 0);
  std::vector<Index> order;
  for (Index i = 0; i < lists.size(); ++i)
    if (alive[i] != 0 && !lists[i].empty()) {
      sig[i] = signature(lists[i]);
      order.push_back(i);
    }
  // Small lists first: as subsets they remove the most.
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return lists[a].size() < lists[b].size(); });
  bool changed = false;
  for (const Index s : order) {
    if (alive[s] == 0) continue;
    const auto& small = lists[s];
    Index rarest = small.front();
    for (const Index j : small)
      if (other[j].size() < other[rarest].size()) rarest = j;
    for (const Index r : other[rarest]) {
      if (r == s || alive[r] == 0) continue;
      const auto& big = lists[r];
      if (big.size() < small.size() || (sig[s] & ~sig[r]) != 0) continue;
      const Index removed = which == Remove::Superset ? r : s;
      if (big.size() == small.size() && removed != std::max(r, s)) continue;
      if (!std::includes(big.begin(), big.end(), small.begin(), small.end())) continue;
      alive[removed] = 0;
      changed = true;
      if (removed == s) break;
    }
  }
  return changed;
}

}  // namespace

SetCoverReduction reduce_set_cover(const CompressedRows& sets, std::size_t element_count) {
  guard::require_coverable(sets, element_count, "reduce_set_cover");
  SetCoverReduction result;
  const std::size_t column_count = sets.row_count();
  result.rows_before = element_count;
  result.columns_before = column_count;

  Lists column_rows(column_count), row_columns(element_count);
  for (Index c = 0; c < column_count; ++c) {
    const auto row = sets.row(c);
    column_rows[c].assign(row.begin(), row.end());
    std::sort(column_rows[c].begin(), column_rows[c].end());
    column_rows[c].erase(std::unique(column_rows[c].begin(), column_rows[c].end()), column_rows[c].end());
    for (const Index e : column_rows[c]) row_columns[e].push_back(c);  // ascending: c increases
  }
  std::vector<std::uint8_t> row_alive(element_count, 1), column_alive(column_count, 1), forced(column_count, 0);

  bool changed = true;
  while (changed) {
    changed = false;
    ++result.rounds;

    // Rule 1 (essential column): a row in one column forces it; the rows it covers
    // are satisfied and leave with it.
    for (Index r = 0; r < element_count; ++r)
      if (row_alive[r] != 0 && row_columns[r].size() == 1) forced[row_columns[r][0]] = 1;
    for (Index c = 0; c < column_count; ++c) {
      if (forced[c] == 0 || column_alive[c] == 0) continue;
      column_alive[c] = 0;
      for (const Index r : column_rows[c]) row_alive[r] = 0;
      changed = true;
    }
    compact(row_columns, row_alive, column_alive);
    compact(column_rows, column_alive, row_alive);

    // Duplicate rows: sort live rows by (hash, list), so that lists are compared only
    // on equal hashes, and keep the lowest index of each run of equal lists.
    {
      std::vector<Index> order;
      std::vector<std::uint64_t> hash(element_count, 0);
      for (Index r = 0; r < element_count; ++r)
        if (row_alive[r] != 0) {
          order.push_back(r);
          std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a over the column ids
          for (const Index c : row_columns[r]) h = (h ^ c) * 0x100000001b3ull;
          hash[r] = h;
        }
      std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) {
        return hash[a] != hash[b] ? hash[a] < hash[b] : row_columns[a] < row_columns[b];
      });
      for (std::size_t k = 1; k < order.size(); ++k)
        if (row_columns[order[k]] == row_columns[order[k - 1]]) {
          row_alive[std::max(order[k], order[k - 1])] = 0;
          changed = true;
          // Keep the run's lowest index at position k for the next comparison.
          order[k] = std::min(order[k], order[k - 1]);
        }
    }
    compact(column_rows, column_alive, row_alive);

    // Rule 2 (row dominance): covering a row covers every row whose columns are a
    // superset of its columns.
    if (remove_dominated(row_columns, column_rows, row_alive, Remove::Superset)) changed = true;
    compact(column_rows, column_alive, row_alive);

    // Rule 3 (column dominance): a column whose rows are a subset of another's can be
    // swapped for it in any cover. A column with no live rows left is useless.
    for (Index c = 0; c < column_count; ++c)
      if (column_alive[c] != 0 && column_rows[c].empty()) {
        column_alive[c] = 0;
        changed = true;
      }
    if (remove_dominated(column_rows, row_columns, column_alive, Remove::Subset)) changed = true;
    compact(row_columns, row_alive, column_alive);
    compact(column_rows, column_alive, row_alive);
  }

  for (Index c = 0; c < column_count; ++c)
    if (forced[c] != 0) result.forced.push_back(c);
  std::vector<Index> position(element_count, kInvalidIndex);
  for (Index r = 0; r < element_count; ++r)
    if (row_alive[r] != 0) {
      position[r] = static_cast<Index>(result.kept_rows.size());
      result.kept_rows.push_back(r);
    }
  for (Index c = 0; c < column_count; ++c) {
    if (column_alive[c] == 0) continue;
    result.kept_columns.push_back(c);
    for (const Index r : column_rows[c]) result.reduced_sets.items.push_back(position[r]);
    result.reduced_sets.offsets.push_back(static_cast<Index>(result.reduced_sets.items.size()));
  }
  result.rows_after = result.kept_rows.size();
  result.columns_after = result.kept_columns.size();
  return result;
}

}  // namespace structmesh
