// assign_parts(): parts to processes by predicted work, longest first onto the
// least loaded process (Graham's LPT rule, within 4/3 of the best makespan). Used
// for the MPI ranks and for the speedup predicted from measured per-part times
// (Fig. 3.9(b) of the dissertation).
#include "structmesh/error.hpp"
#include "structmesh/quad2d.hpp"

#include <algorithm>
#include <numeric>

namespace structmesh {

std::vector<std::int32_t> assign_parts(std::span<const double> work, std::size_t processes) {
  if (processes == 0) throw InputError("assign_parts: at least one process is needed");
  std::vector<std::size_t> order(work.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return work[a] > work[b]; });
  std::vector<double> load(processes, 0);
  std::vector<std::int32_t> owner(work.size(), 0);
  for (const std::size_t part : order) {
    // The least loaded process; ties go to the lowest rank (deterministic).
    const std::size_t process = static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
    owner[part] = static_cast<std::int32_t>(process);
    load[process] += work[part];
  }
  return owner;
}

double predicted_speedup(std::span<const double> work, std::size_t processes) {
  const std::vector<std::int32_t> owner = assign_parts(work, processes);
  std::vector<double> load(processes, 0);
  for (std::size_t p = 0; p < work.size(); ++p) load[static_cast<std::size_t>(owner[p])] += work[p];
  const double total = std::accumulate(work.begin(), work.end(), 0.0);
  const double longest = *std::max_element(load.begin(), load.end());
  return longest > 0 ? total / longest : 1.0;
}

}  // namespace structmesh
