// Summary statistics and histograms of per-element measures (the avg / std / min
// columns of Tables 3.4 and 5.2).
#include "structmesh/error.hpp"
#include "structmesh/quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace structmesh {

Statistics statistics(const std::vector<double>& values) {
  Statistics s;
  double sum = 0;
  s.min = std::numeric_limits<double>::infinity();
  s.max = -std::numeric_limits<double>::infinity();
  for (double v : values) {
    if (std::isnan(v)) continue;
    ++s.count;
    sum += v;
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
  }
  if (s.count == 0) return Statistics{};
  s.mean = sum / static_cast<double>(s.count);
  // Two passes: the one-pass sum of squares loses every digit when all values are
  // close to 1, which is exactly the case for good meshes.
  double squares = 0;
  for (double v : values)
    if (!std::isnan(v)) squares += (v - s.mean) * (v - s.mean);
  s.stddev = std::sqrt(squares / static_cast<double>(s.count));
  return s;
}

std::vector<std::uint64_t> histogram(const std::vector<double>& values, double lo, double hi, int bins) {
  if (bins < 1 || !(lo < hi))
    throw InputError("histogram: need at least one bin and lo < hi (got " + std::to_string(bins) + " bins over [" +
                     std::to_string(lo) + ", " + std::to_string(hi) + "])");
  std::vector<std::uint64_t> counts(static_cast<std::size_t>(bins), 0);
  const double scale = bins / (hi - lo);
  for (double v : values) {
    if (std::isnan(v)) continue;
    const double position = std::floor((v - lo) * scale);
    const double clamped = std::clamp(position, 0.0, static_cast<double>(bins - 1));
    ++counts[static_cast<std::size_t>(clamped)];
  }
  return counts;
}

}  // namespace structmesh
