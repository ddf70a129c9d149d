// libFuzzer target for read_stl: see fuzz_check.hpp for what is checked. The
// round trip uses ASCII STL: binary STL stores floats, so doubles would not
// come back unchanged.
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  structmesh::fuzz::check_reader(data, size, structmesh::read_stl, [](const structmesh::MeshBundle& mesh) {
    return write_stl(mesh, structmesh::Encoding::Ascii);
  });
  return 0;
}
