#include "structmesh/error.hpp"

namespace structmesh {

std::string located_message(const std::string& file, std::uint64_t line, const std::string& message) {
  // Built with append() rather than operator+ chains: GCC 12 at -O3 raises a false
  // -Wrestrict on `std::string + const char*` (GCC bug 105329).
  std::string out;
  out.reserve(file.size() + message.size() + 24);
  out.append(file.empty() ? std::string_view("<input>") : std::string_view(file));
  if (line > 0) out.append(":").append(std::to_string(line));
  out.append(": ").append(message);
  return out;
}

}  // namespace structmesh
