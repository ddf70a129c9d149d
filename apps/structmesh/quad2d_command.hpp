// Shared by the threaded (cmd_quad2d.cpp) and MPI (quad2d_mpi.cpp) paths of
// `structmesh quad2d`.
#pragma once

#include "cli.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/render.hpp"

#include <string>
#include <vector>

namespace structmesh::cli {

struct Quad2dSettings {
  std::string source;
  std::size_t segments = 0;
  std::string polygon;
  std::string method = "cvtgp";
  double size = 0;
  std::size_t quads = 0;
  Quad2dOptions options;
  std::vector<std::string> outputs;
  std::vector<std::string> merged_outputs;  ///< MPI: whole mesh gathered on rank 0
  bool lonlat_output = false;
  std::string view;
  int picture_width = 1600;
};

/// InputError unless every output is .vtu, .pvtu, .msh, .mesh or .png.
void check_outputs(const std::vector<std::string>& outputs);

/// Writes the whole mesh (with cell data part and scaled_jacobian) to each output;
/// a .pvtu gets one piece "<stem>_0.vtu" beside it.
void write_outputs(const std::vector<std::string>& outputs, const QuadMesh& mesh,
                   const std::vector<std::int32_t>& part_of_quad, const std::vector<double>& scaled_jacobian,
                   const QuadPictureOptions& picture);

/// True when this process was started by mpirun (OpenMPI or a PMI launcher).
bool launched_by_mpirun();

/// The distributed quad2d: parts assigned to ranks by predicted work, paved per
/// rank, relaxed with halo exchanges, written as one .pvtu piece per rank (and
/// merged on rank 0 for --merged and non-.pvtu outputs). Returns the exit code.
int run_quad2d_mpi(const Quad2dSettings& settings, const Quad2dOptions& options, const Polygon2& region,
                   const QuadPictureOptions& picture, const GlobalOptions& global);

}  // namespace structmesh::cli
