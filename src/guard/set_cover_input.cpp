// Shared checks of set-cover inputs, and covers_all().
#include "guard/set_cover_input.hpp"

#include "structmesh/error.hpp"
#include "structmesh/guard.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace structmesh {

namespace guard {

void require_coverable(const CompressedRows& sets, std::size_t element_count, const char* who) {
  std::vector<std::uint8_t> covered(element_count, 0);
  for (std::size_t c = 0; c < sets.row_count(); ++c)
    for (const Index e : sets.row(c)) {
      if (e >= element_count)
        throw InputError(std::string(who) + ": set " + std::to_string(c) + " lists element " + std::to_string(e) +
                         " of " + std::to_string(element_count));
      covered[e] = 1;
    }
  std::size_t missing = 0, first = 0;
  for (std::size_t e = element_count; e-- > 0;)
    if (covered[e] == 0) {
      ++missing;
      first = e;
    }
  if (missing > 0)
    throw InputError(std::string(who) + ": element " + std::to_string(first) + " is in no set (" +
                     std::to_string(missing) + " element" + (missing == 1 ? " is" : "s are") +
                     " not coverable): no choice of sets covers everything");
}

}  // namespace guard

bool covers_all(const CompressedRows& sets, std::size_t element_count, std::span<const Index> chosen) {
  std::vector<std::uint8_t> covered(element_count, 0);
  std::size_t count = 0;
  for (const Index c : chosen) {
    if (c >= sets.row_count()) return false;
    for (const Index e : sets.row(c))
      if (e < element_count && covered[e] == 0) {
        covered[e] = 1;
        ++count;
      }
  }
  return count == element_count;
}

}  // namespace structmesh
