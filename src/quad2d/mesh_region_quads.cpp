// mesh_region_quads(): the threaded pipeline of ch. 3.3 on one machine:
// partition -> consistent boundary samples -> paving of every part in parallel
// (largest predicted work first, so the long parts do not finish last) -> merge ->
// relaxation near the separators -> quality report.
#include "partition2d/partition_internal.hpp"

#include "structmesh/error.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/quality.hpp"

#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

namespace structmesh {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB on Linux
}

// Mean length of the input boundary segments in the metric plane: the default
// element size of §3.3.1.
double mean_boundary_segment(const Polygon2& metric_region) {
  double length = 0;
  for (std::size_t r = 0; r < metric_region.ring_count(); ++r) {
    const auto ring = metric_region.ring(r);
    for (std::size_t i = 0; i < ring.size(); ++i) length += (ring[(i + 1) % ring.size()] - ring[i]).norm();
  }
  return length / static_cast<double>(std::max<std::size_t>(1, metric_region.points.size()));
}

}  // namespace

std::size_t default_part_count(std::size_t expected_quads, std::size_t threads) {
  // Small meshes are best in one piece (every separator adds singular vertices);
  // large ones get a few parts per thread for load balance, and at least one part
  // per 250k quads so a part's front stays short.
  if (expected_quads < 20000) return 1;
  const std::size_t per_thread = 4 * std::max<std::size_t>(1, threads);
  return std::max(per_thread, (expected_quads + 249999) / 250000);
}

Quad2dResult mesh_region_quads(const Polygon2& region, const Quad2dOptions& options) {
  if (options.size < 0 || !std::isfinite(options.size)) throw InputError("quad2d: --size must be positive");
  const auto start = Clock::now();
  Quad2dResult result;
  Quad2dReport& report = result.report;
  auto stage_start = Clock::now();
  const auto stage = [&](const char* name) {
    report.stage_seconds.emplace_back(name, seconds_since(stage_start));
    stage_start = Clock::now();
  };

  // 1. Size and part count in the metric plane (lon/lat input is projected the
  //    same way partition_region() projects it), then the partition.
  PartitionOptions partition_options = options.partition;
  partition_options.progress = options.progress;
  const Polygon2 metric_region = partition2d::project_region(region, partition2d::choose_projection(region));
  const double planar_area = area(metric_region);
  double size = options.size;
  if (size == 0 && options.target_quads == 0) size = mean_boundary_segment(metric_region);
  if (size == 0) size = size_for_quad_count(planar_area, options.target_quads);
  if (!(size > 0)) throw InputError("quad2d: could not derive an element size (empty region?)");
  const double expected_quads = planar_area / (size * size);
  if (expected_quads > 4.0e9) throw InputError("quad2d: --size gives more than 4e9 quads; choose a larger size");
  if (partition_options.parts == 0)
    partition_options.parts = default_part_count(static_cast<std::size_t>(expected_quads),
                                                 static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()));
  if (options.progress)
    status("quad2d: element size " + std::to_string(size) + ", about " +
           std::to_string(static_cast<long long>(expected_quads)) + " quads in " +
           std::to_string(partition_options.parts) + " parts");
  const Partition partition = partition_region(region, partition_options);
  stage("partition");

  // 2. Consistent boundary samples.
  const SampledPartition sampled = sample_partition(partition, size);
  const std::size_t parts = sampled.part_loops.size();
  stage("sample");

  // 3. Paving, largest part first.
  std::vector<Polygon2> boundaries(parts);
  std::vector<std::vector<Index>> maps(parts);
  for (std::size_t p = 0; p < parts; ++p) std::tie(boundaries[p], maps[p]) = part_boundary(sampled, p);
  std::vector<std::size_t> order(parts);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return partition.part_areas[a] > partition.part_areas[b]; });
  std::vector<PavedPart> paved(parts);
  report.part_seconds.assign(parts, 0);
  PavingOptions paving = options.paving;
  if (paving.size == 0) paving.size = size;
  {
    Progress progress("paving parts", parts);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, parts, 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const std::size_t p = order[i];
            const auto part_start = Clock::now();
            try {
              paved[p] = pave(boundaries[p], paving);
            } catch (const Error& e) {
              throw Error("quad2d: part " + std::to_string(p) + ": " + e.what());
            }
            report.part_seconds[p] = seconds_since(part_start);
            progress.advance();
          }
        },
        tbb::simple_partitioner());
  }
  stage("paving");

  // 4. Merge and relax.
  result.merged = merge_parts(sampled, paved, maps);
  for (const PavedPart& part : paved) {
    report.paving.rows += part.stats.rows;
    report.paving.seams += part.stats.seams;
    report.paving.splits += part.stats.splits;
    report.paving.templates += part.stats.templates;
    report.paving.fallback_loops += part.stats.fallback_loops;
  }
  paved.clear();
  paved.shrink_to_fit();
  stage("merge");
  report.relax = relax_near_separators(result.merged, options.relax);
  stage("relax");

  // 5. Report.
  const QuadQuality quality = quad_quality(result.merged.mesh);
  result.scaled_jacobian = quality.scaled_jacobian;
  report.quads = result.merged.mesh.quads.size();
  report.points = result.merged.mesh.points.size();
  report.parts = parts;
  report.size = size;
  report.scaled_jacobian_avg = quality.scaled_jacobian_stats.mean;
  report.scaled_jacobian_std = quality.scaled_jacobian_stats.stddev;
  report.scaled_jacobian_min = quality.scaled_jacobian_stats.min;
  report.inverted = quality.inverted;
  report.singular_vertices = quality.singular_vertices;
  report.region_area = partition.metrics.region_area;
  double mesh_area = 0;
  for (const auto& q : result.merged.mesh.quads) {
    const auto& P = result.merged.mesh.points;
    // Shoelace over the quad (the points are planar).
    for (int k = 0; k < 4; ++k) {
      const Vec3& a = P[q[k]];
      const Vec3& b = P[q[(k + 1) % 4]];
      mesh_area += 0.5 * (a.x() * b.y() - b.x() * a.y());
    }
  }
  report.mesh_area = mesh_area;
  report.projection = partition.projection;
  report.partition = partition.metrics;
  stage("quality");
  report.stage_seconds.emplace_back("total", seconds_since(start));
  report.peak_rss_mb = peak_rss_mb();
  return result;
}

}  // namespace structmesh
