// mesh_region_quads(): the threaded pipeline of ch. 3.3 on one machine:
// partition -> consistent boundary samples -> paving of every part in parallel
// (largest predicted work first, so the long parts do not finish last) -> merge ->
// relaxation near the separators -> quality report.
#include "partition2d/partition_internal.hpp"
#include "quad2d/untangle_quads.hpp"

#include "structmesh/error.hpp"
#include "structmesh/io.hpp"
#include "structmesh/progress.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/quality.hpp"

#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_reduce.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <string>

namespace structmesh {

namespace {

using Clock = std::chrono::steady_clock;

// Unplanned polar layouts (polar_block_candidates) are tried on parts of up to this
// many expected quads (polar_mesh()'s polish takes up to 20k free points, as for the
// planned ones in sample_partition()), at most this many layouts per part, and a part
// stops trying after a layout polished to under kHopelessLayout.
constexpr double kUnplannedBlocksMaxQuads = 15000;
constexpr std::size_t kUnplannedLayouts = 3;
constexpr double kHopelessLayout = 0.1;
// Separators shorter than this many element sizes are collapsed to a point before
// sampling (collapse_tiny_separators()).
constexpr double kTinySeparator = 0.1;
// Transition layouts (transition_block_candidates()) tried per part after those: one.
// The Key's two parts that take one take the first. With two tries the Pipe gained a
// part (588 -> 556 singular vertices; its first layout polished to 0.588), but the
// Gulf in 1024 parts went from 45 to 68 s in the benchmark; with one, its paving takes
// 31.8 s instead of 27.8 (run side by side) and 18 more of its parts get blocks.
constexpr std::size_t kTransitionLayouts = 1;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

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

double quad_mesh_area(const QuadMesh& mesh) {
  // Half the cross product of the diagonals: exact for planar quads and free of
  // the cancellation a shoelace over large coordinates (metres) would suffer.
  // A deterministic reduce: the same blocks summed in the same tree whatever the
  // threads, so the area is bit-identical on 1 and N threads.
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, mesh.quads.size(), 16384), 0.0,
      [&](const tbb::blocked_range<std::size_t>& range, double total) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const auto& q = mesh.quads[i];
          const Vec3 d0 = mesh.points[q[2]] - mesh.points[q[0]];
          const Vec3 d1 = mesh.points[q[3]] - mesh.points[q[1]];
          total += 0.5 * (d0.x() * d1.y() - d0.y() * d1.x());
        }
        return total;
      },
      std::plus<double>());
}

std::size_t default_part_count(std::size_t expected_quads, std::size_t processes) {
  // Small meshes are best in one piece (every separator adds singular vertices);
  // large ones get at least 8 parts (load balance over threads), one per 500k quads
  // and two per MPI process. Thread counts do not enter, so the default mesh is the
  // same for any number of threads. A large part is a grid inside a paved band
  // (pave_with_grid_interior) whose cost grows with the separators' length, so fewer,
  // larger parts are cheaper: the Gulf at 20M quads on two threads, 80 parts (one per
  // 250k) against 40, paving 50.3 / 50.8 against 43.3 / 47.8 core-seconds, total 36.5 /
  // 38.0 against 30.7 / 34.3 s, singular vertices 48,547 against 39,986.
  if (expected_quads < 20000) return 1;
  return std::max({std::size_t{8}, (expected_quads + 499999) / 500000, 2 * processes});
}

Quad2dSetup setup_quad2d(const Polygon2& region, const Quad2dOptions& options, std::size_t processes) {
  if (options.size < 0 || !std::isfinite(options.size)) throw InputError("quad2d: --size must be positive");
  Quad2dSetup setup;
  auto stage_start = Clock::now();
  // Size and part count in the metric plane (lon/lat input is projected the same
  // way partition_region() projects it), then the partition and the samples.
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
  if (options.min_channel < 0 || options.min_island < 0)
    throw InputError("quad2d: --min-channel and --min-island must not be negative");
  partition_options.min_channel_width = options.min_channel * size;
  partition_options.min_island_area = options.min_island * size * size;
  if (partition_options.parts == 0)
    partition_options.parts = default_part_count(static_cast<std::size_t>(expected_quads), processes);
  if (options.auto_cells) {
    const double wanted = std::clamp(expected_quads / 100.0, 256.0, 4000.0);
    partition_options.cells = std::max(24 * partition_options.parts, static_cast<std::size_t>(wanted));
  }
  if (options.progress)
    status("quad2d: element size " + std::to_string(size) + ", about " +
           std::to_string(static_cast<long long>(expected_quads)) + " quads in " +
           std::to_string(partition_options.parts) + " parts");
  setup.partition = partition_region(region, partition_options);
  setup.stage_seconds.emplace_back("partition", seconds_since(stage_start));
  stage_start = Clock::now();
  collapse_tiny_separators(setup.partition, kTinySeparator * size);
  setup.sampled = sample_partition(setup.partition, size, options.blocks);
  setup.size = size;
  setup.stage_seconds.emplace_back("sample", seconds_since(stage_start));
  return setup;
}

std::vector<PavedPart> pave_parts(const Quad2dSetup& setup, std::span<const std::size_t> parts,
                                  const PavingOptions& options, std::vector<double>& part_seconds, bool progress_bar) {
  const std::size_t count = setup.sampled.part_loops.size();
  std::vector<PavedPart> paved(count);
  part_seconds.assign(count, 0);
  for (const std::size_t p : parts)
    if (p >= count) throw InputError("pave_parts: no part " + std::to_string(p));
  std::vector<std::size_t> order(parts.begin(), parts.end());
  std::vector<double> work(count, 0);
  for (const std::size_t p : order) work[p] = predicted_part_work(setup, p);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return work[a] > work[b]; });
  PavingOptions paving = options;
  if (paving.size == 0) paving.size = setup.size;
  std::unique_ptr<Progress> progress;
  if (progress_bar) progress = std::make_unique<Progress>("paving parts", order.size());
  // Every worker takes the next part in order (greedy LPT). A parallel_for over the
  // order would split it into halves, so the second thread would start in the middle
  // of the list and the largest parts could end up last on one thread.
  std::atomic<std::size_t> next{0};
  const auto workers = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  tbb::parallel_for(
      std::size_t{0}, std::min(workers, order.size()),
      [&](std::size_t) {
        for (std::size_t i = next++; i < order.size(); i = next++) {
          const std::size_t p = order[i];
          const auto part_start = Clock::now();
          const Polygon2 boundary = part_boundary(setup.sampled, p).first;
          try {
            // Four-sided parts with matching sides become structured grids (no
            // interior singular vertex); paving when the map would fold.
            const auto& corners = setup.sampled.part_corners[p];
            std::optional<PavedPart> mapped;
            try {
              if (!setup.sampled.part_polar.empty() && !setup.sampled.part_polar[p].corners.empty()) {
                mapped = polar_mesh(boundary, setup.sampled.part_polar[p]);
              } else if (corners[0] >= 0) {
                mapped =
                    mapped_mesh(boundary, {static_cast<std::size_t>(corners[0]), static_cast<std::size_t>(corners[1]),
                                           static_cast<std::size_t>(corners[2]), static_cast<std::size_t>(corners[3])});
              }
            } catch (const InputError&) {
              // A part the block meshers cannot take (e.g. its sampled loop turned
              // clockwise) is paved like any other; pave() reports what is wrong.
              mapped.reset();
            }
            // No layout planned, or the planned one failed its quality check: polar
            // blocks that fit the counts as sampled (the first of up to three layouts
            // that passes, with a mean of kRescuedBlocksMinMean), before paving. A paved
            // part of 2k quads leaves about 50 interior singular vertices, polar blocks
            // one: on the Key in 32 parts this took the singular vertices from 560 to 368
            // (paving time 1.8 -> 4.3 s on one thread, for the layouts that fail), on the
            // Gulf in 1024 parts from 16,213 to 14,416 (paving 10.7 -> 27 s on two threads).
            bool unplanned = false;
            const auto try_layouts = [&](const std::vector<PolarBlocks>& layouts) {
              for (const PolarBlocks& blocks : layouts) {
                double reached = -std::numeric_limits<double>::infinity();
                try {
                  mapped = polar_mesh(boundary, blocks, {}, &reached);
                } catch (const InputError&) {
                  mapped.reset();
                }
                // A layout polished to under kHopelessLayout, or not made at all (the
                // centroid, the same for every layout, outside the part, or a block
                // folded): the part's other layouts rarely do better (none on the Key;
                // the Pipe's paving time 5.0 -> 3.8 s on one thread, the same mesh).
                if (!mapped && reached < kHopelessLayout) break;
                if (mapped &&
                    !(paving::mean_scaled_jacobian(mapped->points, mapped->quads) >= paving::kRescuedBlocksMinMean))
                  mapped.reset();
                if (mapped) {
                  unplanned = true;
                  break;
                }
              }
            };
            if (!mapped && boundary.ring_count() == 1 &&
                setup.partition.part_areas[p] / (setup.size * setup.size) <= kUnplannedBlocksMaxQuads) {
              try_layouts(polar_block_candidates(boundary, kUnplannedLayouts));
              // Then a centre with a triangle block (transition_block_candidates(): a
              // 3-5 pair for four corners whose opposite sides differ).
              if (!mapped) try_layouts(transition_block_candidates(boundary, kTransitionLayouts));
            }
            if (mapped) {
              paved[p] = std::move(*mapped);
              if (paved[p].stats.polar == 0) paved[p].stats.mapped = 1;
              if (unplanned) paved[p].stats.unplanned_blocks = 1;
            } else {
              paved[p] = pave(boundary, paving);
            }
          } catch (const std::exception& e) {
            // STRUCTMESH_DUMP_FAILED=DIR keeps the part's boundary for a bug report.
            std::string kept;
            if (const char* dir = std::getenv("STRUCTMESH_DUMP_FAILED")) {
              const std::string path = std::string(dir) + "/part-" + std::to_string(p) + ".poly";
              write_region(path, {boundary});
              kept = " (boundary written to " + path + ")";
            }
            throw Error("quad2d: part " + std::to_string(p) + ": " + e.what() + kept);
          }
          part_seconds[p] = seconds_since(part_start);
          if (progress) progress->advance();
        }
      },
      tbb::simple_partitioner());
  return paved;
}

double predicted_part_work(const Quad2dSetup& setup, std::size_t part) {
  const SampledPartition& sampled = setup.sampled;
  if (part >= sampled.part_loops.size()) throw InputError("predicted_part_work: no part " + std::to_string(part));
  const double quads = setup.partition.part_areas[part] / (setup.size * setup.size);
  const bool polar = !sampled.part_polar.empty() && !sampled.part_polar[part].corners.empty();
  const bool mapped = !sampled.part_corners.empty() && sampled.part_corners[part][0] >= 0;
  // Polar parts are polished as a whole (untangle_quads), which costs about as much as
  // paving them; only grids are cheap.
  return mapped && !polar ? kBlockWorkFactor * quads : quads;
}

Quad2dResult mesh_region_quads(const Polygon2& region, const Quad2dOptions& options) {
  const auto start = Clock::now();
  Quad2dResult result;
  Quad2dReport& report = result.report;
  const Quad2dSetup setup = setup_quad2d(region, options, 1);
  const Partition& partition = setup.partition;
  const SampledPartition& sampled = setup.sampled;
  const double size = setup.size;
  const std::size_t parts = sampled.part_loops.size();
  report.stage_seconds = setup.stage_seconds;
  auto stage_start = Clock::now();
  const auto stage = [&](const char* name) {
    report.stage_seconds.emplace_back(name, seconds_since(stage_start));
    stage_start = Clock::now();
  };

  // Paving, largest part first.
  std::vector<std::size_t> all(parts);
  std::iota(all.begin(), all.end(), 0);
  std::vector<PavedPart> paved = pave_parts(setup, all, options.paving, report.part_seconds, true);
  std::vector<std::vector<Index>> maps(parts);
  for (std::size_t p = 0; p < parts; ++p) maps[p] = part_boundary(sampled, p).second;
  stage("paving");

  // Merge and relax.
  result.merged = merge_parts(sampled, paved, maps);
  for (const PavedPart& part : paved) {
    report.paving.rows += part.stats.rows;
    report.paving.seams += part.stats.seams;
    report.paving.splits += part.stats.splits;
    report.paving.templates += part.stats.templates;
    report.paving.fallback_loops += part.stats.fallback_loops;
    report.paving.repairs += part.stats.repairs;
    report.paving.untangled += part.stats.untangled;
    report.paving.mapped += part.stats.mapped;
    report.paving.polar += part.stats.polar;
    report.paving.unplanned_blocks += part.stats.unplanned_blocks;
    report.paving.retries += part.stats.retries;
    report.paving.cleanup_operations += part.stats.cleanup_operations;
    report.paving.grid_interior_quads += part.stats.grid_interior_quads;
  }
  paved.clear();
  paved.shrink_to_fit();
  stage("merge");
  report.relax = relax_near_separators(result.merged, options.relax);
  stage("relax");

  // Report.
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
  report.mesh_area = quad_mesh_area(result.merged.mesh);
  report.projection = partition.projection;
  report.coastline_filter = partition.simplification;
  report.partition = partition.metrics;
  stage("quality");
  report.stage_seconds.emplace_back("total", seconds_since(start));
  report.peak_rss_mb = peak_rss_mb();
  return result;
}

}  // namespace structmesh
