// libFuzzer target for read_msh: any input must give a mesh or an InputError, never a
// crash, a sanitizer report or another exception.
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    structmesh::read_msh(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
  } catch (const structmesh::InputError&) {
  }
  return 0;
}
