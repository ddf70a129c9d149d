// libFuzzer target for read_ply: see fuzz_check.hpp for what is checked. The
// round trip alternates between the two encodings by input size.
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const structmesh::Encoding encoding = size % 2 == 0 ? structmesh::Encoding::Binary : structmesh::Encoding::Ascii;
  structmesh::fuzz::check_reader(data, size, structmesh::read_ply,
                                 [encoding](const structmesh::MeshBundle& mesh) { return write_ply(mesh, encoding); });
  return 0;
}
