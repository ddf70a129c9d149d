// libFuzzer target for read_obj: see fuzz_check.hpp for what is checked.
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  structmesh::fuzz::check_reader(data, size, structmesh::read_obj, structmesh::write_obj);
  return 0;
}
