// partition_region(): the driver of geometry-aware partitioning (dissertation
// §3.2.6; design/partition2d.md §1.8, §2.9). Every method runs through the same
// projection, tessellation-to-graph, geometry and metrics code, so the comparisons
// of Tables 3.1/3.2 are on identical input.
#include "structmesh/partition2d.hpp"

#include "partition2d/partition_internal.hpp"
#include "structmesh/check.hpp"
#include "structmesh/error.hpp"
#include "structmesh/progress.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace structmesh {

using namespace partition2d;

namespace {

class StageTimer {
 public:
  explicit StageTimer(PartitionMetrics& metrics) : metrics_(metrics) {}
  void stage(const std::string& name) {
    const auto now = std::chrono::steady_clock::now();
    metrics_.stage_seconds.emplace_back(name, std::chrono::duration<double>(now - start_).count());
    start_ = now;
  }

 private:
  PartitionMetrics& metrics_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

void validate(const Polygon2& region, const PartitionOptions& options) {
  if (options.parts < 1) throw InputError("partition_region: --parts must be at least 1");
  if (options.p < 2 || options.p % 2 != 0) {
    throw InputError("partition_region: --p must be an even integer >= 2 (got " + std::to_string(options.p) + ")");
  }
  if (!(options.imbalance > 0)) throw InputError("partition_region: --imbalance must be positive");
  if (!(options.angle_weight >= 0)) throw InputError("partition_region: --angle-weight must be >= 0");
  if (options.cells < 1) throw InputError("partition_region: --cells must be at least 1");
  const RegionReport report = check_region({region});
  if (!report.valid) {
    std::string message = "partition_region: the region is not valid";
    for (std::size_t i = 0; i < report.problems.size() && i < 5; ++i) message += "\n  " + report.problems[i].message;
    if (report.problems.size() > 5) message += "\n  ... (" + std::to_string(report.problems.size()) + " problems)";
    throw InputError(message);
  }
}

// Farthest-point sampling of k sites from a fine grid of candidates, starting at the
// candidate nearest the centroid: the direct-CVT baseline's initial sites (§2.9).
std::vector<Vec2> farthest_point_sites(const std::vector<Vec2>& candidates, std::size_t k) {
  Vec2 centroid = Vec2::Zero();
  for (const Vec2& c : candidates) centroid += c;
  centroid /= static_cast<double>(candidates.size());
  std::size_t first = 0;
  for (std::size_t i = 1; i < candidates.size(); ++i) {
    if ((candidates[i] - centroid).squaredNorm() < (candidates[first] - centroid).squaredNorm()) first = i;
  }
  std::vector<double> distance(candidates.size());
  std::vector<Vec2> sites{candidates[first]};
  for (std::size_t i = 0; i < candidates.size(); ++i) distance[i] = (candidates[i] - candidates[first]).squaredNorm();
  while (sites.size() < k) {
    const std::size_t next =
        static_cast<std::size_t>(std::max_element(distance.begin(), distance.end()) - distance.begin());
    sites.push_back(candidates[next]);
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      distance[i] = std::min(distance[i], (candidates[i] - candidates[next]).squaredNorm());
    }
  }
  return sites;
}

std::size_t segment_count(const Polygon2& region) { return region.points.size(); }

constexpr double kCornerResolution = 0.1;  // cell sizes (normalised frame)

}  // namespace

Partition partition_region(const Polygon2& region, const PartitionOptions& options) {
  validate(region, options);
  Partition partition;
  PartitionMetrics& metrics = partition.metrics;
  StageTimer timer(metrics);
  const std::size_t k = options.parts;

  // Projection and the normalised frame (design §2.0).
  const Projection projection = choose_projection(region);
  Polygon2 metric_region = project_region(region, projection);
  partition.projection = projection.describe();
  // Features narrower than the mesh can hold are filtered in the metric plane; the
  // kept vertices are input vertices, so the input-coordinate region is their subset.
  Polygon2 filtered_input;
  const Polygon2* input_region = &region;
  if (options.min_channel_width > 0 || options.min_island_area > 0) {
    if (options.progress)
      status("partition2d: closing water narrower than " + std::to_string(options.min_channel_width));
    NarrowWaterResult filtered = remove_narrow_water(metric_region, options.min_channel_width, options.min_island_area);
    partition.simplification = filtered.report;
    if (filtered.report.changed) {
      filtered_input = select_rings(region, filtered.rings);
      metric_region = std::move(filtered.region);
      input_region = &filtered_input;
    }
  }
  const double region_area = std::abs(area(metric_region));
  // One part is the region itself: a one-site CVT gives it without optimising thousands of cells.
  const bool cvt_baseline = options.method == PartitionMethod::Cvt || k == 1;
  std::size_t cells = options.exact_cells ? options.cells : std::max(options.cells, 24 * k);
  if (cvt_baseline) cells = k;
  metrics.cells = cells;
  Frame frame;
  const BoundingBox2 box = metric_region.bounding_box();
  frame.center = 0.5 * (box.min + box.max);
  frame.scale = std::sqrt(region_area / static_cast<double>(cells));
  timer.stage("projection");

  Tessellation tessellation;
  if (options.method == PartitionMethod::Metis || options.method == PartitionMethod::Madd) {
    status("partition2d: triangulating (" + std::to_string(cells) + " triangles wanted)");
    tessellation = triangle_tessellation(metric_region, frame, cells, options.method == PartitionMethod::Madd);
    timer.stage("triangulation");
  } else {
    // L_p-CVT (eq. 3.11-3.12). With far more boundary segments than cells the
    // optimisation runs on a simplified proxy (design §2.4); the final clip always
    // uses the full boundary.
    const bool use_proxy = options.proxy_domain && segment_count(metric_region) > 20 * cells;
    const Polygon2 proxy =
        use_proxy ? proxy_region(metric_region, 0.02 * frame.scale, 0.01 * frame.scale * frame.scale) : metric_region;
    const bool proxied = use_proxy && proxy.points.size() != metric_region.points.size();
    // Steiner points every half cell: each triangle then meets only a few cells.
    const double spacing = 0.5 * frame.scale;
    status("partition2d: triangulating the domain" + std::string(proxied ? " (proxy boundary)" : ""));
    DomainMesh domain = build_domain_mesh(proxy, frame, spacing);
    timer.stage("domain triangulation");

    std::vector<Vec2> sites;
    if (cvt_baseline) {
      sites = farthest_point_sites(initial_grid_sites(domain, std::max<std::size_t>(64 * k, 256), options.seed), k);
    } else {
      sites = initial_grid_sites(domain, cells, options.seed);
    }
    LpCvtOptions cvt;
    cvt.p = options.p;
    cvt.max_iterations = options.cvt_max_iterations;
    cvt.gradient_tolerance = options.cvt_gradient_tolerance;
    cvt.progress = options.progress && !progress_settings().quiet;
    status("partition2d: L" + std::to_string(options.p) + "-CVT of " + std::to_string(sites.size()) + " sites");
    LpCvtResult optimised = optimise_lp_cvt(domain, std::move(sites), cvt);
    metrics.cvt_energy_initial = optimised.energy_initial;
    metrics.cvt_energy_final = optimised.energy_final;
    metrics.cvt_iterations = optimised.iterations;
    metrics.cvt_stop_reason = optimised.stop_reason;
    timer.stage("L_p-CVT");

    if (proxied) {
      domain = build_domain_mesh(metric_region, frame, spacing);
      timer.stage("full domain triangulation");
    }
    tessellation = restricted_voronoi(domain, optimised.sites);
    assign_boundary_rings(tessellation, metric_region);
    partition.sites.reserve(optimised.sites.size());
    for (const Vec2& s : optimised.sites) partition.sites.push_back(frame.to_metric(s));
    timer.stage("restricted Voronoi");
  }

  // The dual graph (§3.2.1). Corners joined by a straight separator edge shorter than
  // a tenth of a cell are one corner, both for the refinement's D_theta and for the
  // reported (3.8): a near-grid L_p-CVT replaces each four-cell junction by two
  // degree-3 vertices and a short edge of arbitrary direction, which would otherwise
  // add two 45-degree corners per junction to a staircase that is really all right
  // angles (design §1.4). The same resolution applies to every method.
  const CellGraph graph = build_cell_graph(tessellation, kCornerResolution);
  metrics.graph_nodes = graph.node_count();
  metrics.graph_arcs = graph.adjacency.size() / 2;
  timer.stage("cell graph");

  std::vector<std::int32_t> node_part;
  GraphPartitionReport report;
  if (cvt_baseline) {
    node_part.resize(graph.node_count());
    for (std::size_t n = 0; n < node_part.size(); ++n) node_part[n] = static_cast<std::int32_t>(graph.node_cell[n]);
    report.components_before_repair = max_components_per_part(graph, node_part, k);
    report.moved_by_repair = repair_connectivity(graph, node_part, k);
  } else {
    GraphPartitionOptions engine;
    engine.parts = k;
    engine.imbalance = options.imbalance;
    engine.angle_weight = options.angle_weight;
    engine.boundary_corners = options.boundary_corners;
    engine.refinement_passes = options.refinement_passes;
    engine.exact_time_limit = options.exact_time_limit;
    engine.seed = options.seed;
    switch (options.method) {
      case PartitionMethod::CvtGp:
        engine.engine = GraphPartitionOptions::Engine::RecursiveGp;
        break;
      case PartitionMethod::Metis:
        engine.engine = GraphPartitionOptions::Engine::MetisKway;
        break;
      case PartitionMethod::Madd:
        engine.engine = GraphPartitionOptions::Engine::MetisRecursive;
        break;
      case PartitionMethod::Exact:
        if (graph.node_count() > options.exact_max_nodes) {
          throw InputError("partition_region: --method exact solves graphs of at most " +
                           std::to_string(options.exact_max_nodes) + " nodes; this one has " +
                           std::to_string(graph.node_count()) + " (lower --cells)");
        }
        engine.engine = GraphPartitionOptions::Engine::Exact;
        break;
      case PartitionMethod::Cvt:
        break;
    }
    status("partition2d: partitioning " + std::to_string(graph.node_count()) + " cells into " + std::to_string(k) +
           " parts (" + method_name(options.method) + ")");
    node_part = partition_cell_graph(graph, engine, &report);
  }
  metrics.components_before_repair = report.components_before_repair;
  metrics.exact_gap = report.exact_gap;
  timer.stage("graph partitioning");

  // Part geometry in input coordinates (input vertices bit-identical).
  std::vector<std::int32_t> face_part(tessellation.face_count());
  for (std::size_t f = 0; f < face_part.size(); ++f) face_part[f] = node_part[graph.face_node[f]];
  CoordinateMaps maps;
  maps.normalised_to_metric = [frame](const Vec2& p) { return frame.to_metric(p); };
  if (projection.active) {
    maps.metric_to_input = [projection](const Vec2& p) { return projection.inverse(p); };
  } else {
    maps.metric_to_input = [](const Vec2& p) { return p; };
  }
  build_part_geometry(tessellation, face_part, k, *input_region, maps, partition);
  timer.stage("part geometry");

  const CornerCost corners = corner_cost(graph, node_part);
  metrics.angle_deviation =
      corners.separator_corners > 0 ? corners.separator_sum / static_cast<double>(corners.separator_corners) : 0.0;
  metrics.corners = corners.separator_corners;
  metrics.corner_resolution = kCornerResolution;
  {
    // The same measure at (almost) full resolution, reported beside it.
    const CellGraph fine = build_cell_graph(tessellation, 1e-3);
    std::vector<std::int32_t> fine_part(fine.node_count());
    for (std::size_t f = 0; f < face_part.size(); ++f) fine_part[fine.face_node[f]] = face_part[f];
    const CornerCost c = corner_cost(fine, fine_part);
    metrics.angle_deviation_fine =
        c.separator_corners > 0 ? c.separator_sum / static_cast<double>(c.separator_corners) : 0.0;
  }
  measure_partition_geometry(partition, region_area, 0.5 * frame.scale);
  timer.stage("metrics");
  metrics.peak_rss_mb = peak_rss_mb();
  return partition;
}

}  // namespace structmesh
