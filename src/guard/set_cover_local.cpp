// improve_set_cover(): a local search on a finished set cover (beyond the dissertation,
// which stops at its last PILP level): a large-neighbourhood search whose neighbourhoods
// are small exact ILPs. Written here because CBC has no notion of "improve this cover
// locally"; the sub-problems go to ilp_set_cover() (reductions + CBC).
//
// In the guards' terms (sets = candidates, elements = faces): a guard and the
// group_size - 1 guards sharing most faces with it; the faces only the group sees are
// covered exactly over every candidate that sees one of them, and when that needs fewer
// guards they replace the group. A smaller cover of a group's own faces keeps the whole
// a cover, and a group of k finds what its sub-groups would.
#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace structmesh {

std::size_t improve_set_cover(const CompressedRows& rows, std::size_t faces, std::vector<Index>& guards,
                              std::size_t group_size, double time_limit, double total_seconds) {
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  for (const Index g : guards)
    if (g >= rows.row_count())
      throw InputError("improve_set_cover: set " + std::to_string(g) + " of the cover is not among the " +
                       std::to_string(rows.row_count()) + " sets");
  for (const Index f : rows.items)
    if (f >= faces)
      throw InputError("improve_set_cover: element " + std::to_string(f) + " is not below the element count " +
                       std::to_string(faces));
  std::vector<std::uint32_t> coverage(faces, 0);
  for (const Index g : guards)
    for (const Index f : rows.row(g)) ++coverage[f];
  for (const Index f : rows.items)
    if (coverage[f] == 0)
      throw InputError("improve_set_cover: element " + std::to_string(f) +
                       " is in some set but in none of the cover's");
  if (group_size < 2 || guards.size() < 2) return 0;
  // The face -> candidates transpose, to find the candidates that matter to a group.
  std::vector<Index> face_offsets(faces + 1, 0), face_candidates(rows.items.size());
  for (const Index f : rows.items) ++face_offsets[f + 1];
  for (std::size_t f = 0; f < faces; ++f) face_offsets[f + 1] += face_offsets[f];
  {
    std::vector<Index> next(face_offsets.begin(), face_offsets.end() - 1);
    for (std::size_t c = 0; c < rows.row_count(); ++c)
      for (const Index f : rows.row(c)) face_candidates[next[f]++] = static_cast<Index>(c);
  }
  std::vector<std::uint32_t> in_group(faces, 0);
  std::vector<Index> element(faces, kInvalidIndex), candidate_slot(rows.row_count(), kInvalidIndex);
  std::vector<Index> group, exclusive, relevant;
  std::size_t saved = 0;
  for (bool improved = true; improved;) {
    improved = false;
    for (std::size_t i = 0; i < guards.size() && !improved; ++i) {
      if (elapsed() >= total_seconds) return saved;
      // The group: guard i and the guards sharing most faces with it.
      for (const Index f : rows.row(guards[i])) in_group[f] = 1;
      std::vector<std::pair<std::size_t, Index>> by_overlap;
      for (std::size_t j = 0; j < guards.size(); ++j)
        if (j != i) {
          const auto row = rows.row(guards[j]);
          const auto shared = static_cast<std::size_t>(
              std::count_if(row.begin(), row.end(), [&](Index f) { return in_group[f] != 0; }));
          by_overlap.emplace_back(shared, static_cast<Index>(j));
        }
      for (const Index f : rows.row(guards[i])) in_group[f] = 0;
      const std::size_t others = std::min(group_size - 1, by_overlap.size());
      std::partial_sort(
          by_overlap.begin(), by_overlap.begin() + static_cast<std::ptrdiff_t>(others), by_overlap.end(),
          [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
      group.assign(1, static_cast<Index>(i));
      for (std::size_t k = 0; k < others; ++k) group.push_back(by_overlap[k].second);
      // Faces no guard outside the group sees.
      exclusive.clear();
      for (const Index member : group)
        for (const Index f : rows.row(guards[member])) ++in_group[f];
      for (const Index member : group)
        for (const Index f : rows.row(guards[member]))
          if (in_group[f] > 0) {
            if (coverage[f] == in_group[f]) exclusive.push_back(f);
            in_group[f] = 0;
          }
      for (std::size_t e = 0; e < exclusive.size(); ++e) element[exclusive[e]] = static_cast<Index>(e);
      relevant.clear();
      for (const Index f : exclusive)
        for (Index k = face_offsets[f]; k < face_offsets[f + 1]; ++k)
          if (candidate_slot[face_candidates[k]] == kInvalidIndex) {
            candidate_slot[face_candidates[k]] = static_cast<Index>(relevant.size());
            relevant.push_back(face_candidates[k]);
          }
      CompressedRows sub;
      for (const Index c : relevant) {
        for (const Index f : rows.row(c))
          if (element[f] != kInvalidIndex) sub.items.push_back(element[f]);
        sub.offsets.push_back(static_cast<Index>(sub.items.size()));
      }
      for (const Index f : exclusive) element[f] = kInvalidIndex;
      for (const Index c : relevant) candidate_slot[c] = kInvalidIndex;
      // No exclusive face: the others see all of the group's faces and it just goes.
      const std::vector<Index> chosen =
          exclusive.empty()
              ? std::vector<Index>{}
              : ilp_set_cover(sub, exclusive.size(), std::min(time_limit, std::max(0.01, total_seconds - elapsed())))
                    .chosen;
      if (chosen.size() >= group.size()) continue;
      // Replace the group by the ILP's guards.
      for (const Index member : group)
        for (const Index f : rows.row(guards[member])) --coverage[f];
      std::vector<Index> next_guards;
      std::vector<std::uint8_t> leaves(guards.size(), 0);
      for (const Index member : group) leaves[member] = 1;
      for (std::size_t j = 0; j < guards.size(); ++j)
        if (!leaves[j]) next_guards.push_back(guards[j]);
      for (const Index c : chosen) {
        next_guards.push_back(relevant[c]);
        for (const Index f : rows.row(relevant[c])) ++coverage[f];
      }
      saved += group.size() - chosen.size();
      guards = std::move(next_guards);
      improved = true;
    }
  }
  return saved;
}

}  // namespace structmesh
