// hex_boundary_quads(): the faces of a hex mesh used by one hex. build_faces() orients
// every face outward from its first hex, which for a boundary face is its only hex, so
// the quads come out outward as they are.
#include "structmesh/error.hpp"
#include "structmesh/hex.hpp"

#include <string>

namespace structmesh {

std::vector<std::array<Index, 4>> hex_boundary_quads(const HexMesh& mesh) {
  for (std::size_t h = 0; h < mesh.hexes.size(); ++h)
    for (const Index v : mesh.hexes[h])
      if (v >= mesh.points.size())
        throw InputError("hex_boundary_quads: hex " + std::to_string(h) + " refers to point " + std::to_string(v) +
                         " of " + std::to_string(mesh.points.size()));
  const FaceAdjacency<4> faces = build_faces(mesh);
  std::vector<std::array<Index, 4>> quads;
  for (std::size_t f = 0; f < faces.faces.size(); ++f)
    if (faces.face_cells[f][1] == kInvalidIndex) quads.push_back(faces.faces[f]);
  return quads;
}

}  // namespace structmesh
