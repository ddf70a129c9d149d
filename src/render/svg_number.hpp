// Compact SVG coordinates: values in hundredths of a pixel, written with at most two
// decimals (shared by region_svg and the partition pictures, so both files round alike).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

namespace structmesh::detail {

inline void append_hundredths(std::string& out, std::int64_t value) {
  if (value < 0) {
    out += '-';
    value = -value;
  }
  out += std::to_string(value / 100);
  const int fraction = static_cast<int>(value % 100);
  if (fraction != 0) {
    out += '.';
    out += static_cast<char>('0' + fraction / 10);
    if (fraction % 10 != 0) out += static_cast<char>('0' + fraction % 10);
  }
}

inline std::string pixels(double value) {
  std::string out;
  append_hundredths(out, std::llround(value * 100));
  return out;
}

}  // namespace structmesh::detail
