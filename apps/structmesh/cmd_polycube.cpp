// structmesh polycube SURFACE -o polycube.obj: the polycube domain of chapter 4 (the
// first half of hex meshing), to inspect or to use elsewhere.
#include "cli.hpp"
#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/polycube.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/render.hpp"

#include <Eigen/Geometry>

#include <filesystem>
#include <memory>

namespace structmesh::cli {

namespace {

nlohmann::json topology_json(const VoxelTopology& t) {
  return {{"components", t.components}, {"handles", t.handles}, {"voids", t.voids}, {"euler", t.euler}};
}

// The polycube's quads split into triangles, each labelled by its axis (0 +X ... 5 -Z).
TriMesh labelled_triangles(const QuadMesh& quads, std::vector<std::int32_t>& labels) {
  TriMesh mesh{quads.points, {}};
  labels.clear();
  for (const auto& q : quads.quads) {
    const Vec3 normal = (quads.points[q[2]] - quads.points[q[0]]).cross(quads.points[q[3]] - quads.points[q[1]]);
    const auto label = static_cast<std::int32_t>(nearest_axis_label(normal));
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
    labels.insert(labels.end(), {label, label});
  }
  return mesh;
}

}  // namespace

Action add_polycube_command(CLI::App& command, const GlobalOptions& global) {
  struct Settings {
    std::string input, deformed;
    std::vector<std::string> outputs;
    PolycubeOptions options;
    bool no_align = false;
  };
  auto settings = std::make_shared<Settings>();
  command.add_option("SURFACE", settings->input, "Closed, outward-oriented triangle surface (.obj .off .ply .stl)")
      ->required();
  command
      .add_option("-o,--output", settings->outputs,
                  "The polycube surface (quads; faces labelled by axis 0..5 = +X -X +Y -Y +Z -Z): .obj .ply .off .vtu "
                  ".mesh, or a picture .png; repeatable")
      ->required();
  command.add_option("--deformed", settings->deformed,
                     "Also write the pseudo-polycube Q (the deformed input, §4.3) to this surface file");
  command
      .add_option("--alpha", settings->options.optimization.alpha,
                  "Weight of the deviation E_g in E_c + alpha E_g (4.1)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command
      .add_option("--max-window", settings->options.optimization.max_window,
                  "Largest radius of the moving window of the optimisation (down to 1; 0: no optimisation)")
      ->capture_default_str()
      ->check(CLI::Range(0, 20));
  command
      .add_option("--merge-planes", settings->options.merge_planes_within,
                  "Move facets by up to this many voxels onto planes other facets use, so fewer distinct planes "
                  "remain (0: off)")
      ->capture_default_str()
      ->check(CLI::Range(0, 10));
  command.add_option("--voxel-size", settings->options.voxel_size, "Voxel edge (0: the Morse resolution of §4.4.1)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command
      .add_option("--max-resolution", settings->options.max_resolution,
                  "At most this many voxels along the longest side")
      ->capture_default_str()
      ->check(CLI::Range(4, 2000));
  command.add_option("--iterations", settings->options.deformation.max_iterations, "Pre-deformation rounds (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  command.add_flag("--no-align", settings->no_align, "Skip the principal-axes pre-alignment");

  return [&global, settings]() {
    for (const std::string& output : settings->outputs) {
      if (std::filesystem::path(output).extension() == ".png") continue;
      const FileFormat format = format_from_path(output);
      if (format != FileFormat::Obj && format != FileFormat::Ply && format != FileFormat::Off &&
          format != FileFormat::Vtu && format != FileFormat::Medit)
        throw InputError(output + ": polycube writes .obj .ply .off .vtu .mesh or .png");
    }
    const MeshBundle bundle = read_mesh(settings->input);
    if (!bundle.quads.empty() || !bundle.tets.empty() || !bundle.hexes.empty())
      throw InputError(settings->input + ": polycube needs a triangle surface; the file holds other elements");
    PolycubeOptions options = settings->options;
    options.align = !settings->no_align;
    options.progress = !global.quiet;
    PolycubeResult result;
    try {
      result = build_polycube(TriMesh{bundle.points, bundle.triangles}, options);
    } catch (const InputError& e) {
      throw InputError(settings->input + ": " + e.what());
    }

    std::vector<std::int32_t> labels;
    const TriMesh triangles = labelled_triangles(result.surface, labels);
    for (const std::string& output : settings->outputs) {
      if (std::filesystem::path(output).extension() == ".png") {
        std::vector<Vec3> corners;
        for (std::size_t p = 0; p < result.surface.points.size(); ++p)
          if (result.corner[p]) corners.push_back(result.surface.points[p]);
        write_file_atomic(output, surface_png(triangles, labels, corners));
        continue;
      }
      MeshBundle out;
      out.points = result.surface.points;
      out.quads = result.surface.quads;
      for (std::size_t k = 0; k < labels.size(); k += 2) out.quad_labels.push_back(labels[k]);
      WriteOptions write;
      write.cell_data.push_back({"axis", {}, out.quad_labels});
      DataArray corner{"corner", {}, {}};
      for (const std::uint8_t c : result.corner) corner.i32.push_back(c);
      write.point_data.push_back(std::move(corner));
      write_mesh(output, out, write);
    }
    if (!settings->deformed.empty()) write_mesh(settings->deformed, to_bundle(result.pseudo.surface));

    const PolycubeOptimizationResult& opt = result.optimization;
    say(global, "polycube: " + std::to_string(result.voxels.count()) + " voxels of size " +
                    std::to_string(result.voxels.size) + ", " + std::to_string(opt.after.corners) + " corners (" +
                    std::to_string(opt.before.corners) + " before optimisation), " +
                    std::to_string(result.final.handles) + " handles, as the input");
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& [name, seconds] : result.stage_seconds) stages[name] = seconds;
    const Eigen::Matrix3d& r = result.alignment.rotation;
    write_json_report(
        global,
        {{"input", settings->input},
         {"vertices", bundle.points.size()},
         {"alignment",
          {{"rotation", {r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2)}},
           {"centre", {result.alignment.centre.x(), result.alignment.centre.y(), result.alignment.centre.z()}}}},
         {"pseudo_polycube",
          {{"iterations", result.pseudo.iterations},
           {"input_deviation_degrees", result.pseudo.input_deviation_degrees},
           {"deviation_degrees", result.pseudo.deviation_degrees},
           {"charts", result.pseudo.charts},
           {"wedges", result.pseudo.wedges}}},
         {"morse_voxel_size", result.morse.size},
         {"critical_levels",
          {result.morse.levels[0].size(), result.morse.levels[1].size(), result.morse.levels[2].size()}},
         {"voxel_size", result.voxels.size},
         {"grid", result.voxels.dims},
         {"voxels", result.voxels.count()},
         {"refinements", result.refinements},
         {"deformation_retries", result.deformation_retries},
         {"thin_feature_voxels", result.thin_feature_voxels},
         {"far_point_voxels", result.far_point_voxels},
         {"refused_openings", result.optimization.refused_openings},
         {"optimization_guarded", result.optimization_guarded},
         {"plane_merge",
          {{"planes_before", result.plane_merge.planes_before},
           {"planes_after", result.plane_merge.planes_after},
           {"removed", result.plane_merge.removed},
           {"flips", result.plane_merge.flips}}},
         {"well_composed_flips", result.well_composed_flips},
         {"topology",
          {{"input", topology_json(result.expected)},
           {"voxelized", topology_json(result.initial)},
           {"polycube", topology_json(result.final)}}},
         {"alpha", options.optimization.alpha},
         {"energy_before",
          {{"corners", opt.before.corners}, {"deviation", opt.before.deviation}, {"total", opt.before.total}}},
         {"energy_after",
          {{"corners", opt.after.corners}, {"deviation", opt.after.deviation}, {"total", opt.after.total}}},
         {"openings", opt.openings},
         {"closings", opt.closings},
         {"quads", result.surface.quads.size()},
         {"stage_seconds", stages},
         {"peak_rss_mb", peak_rss_mb()}});
    return 0;
  };
}

}  // namespace structmesh::cli
