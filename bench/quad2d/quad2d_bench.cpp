// Parallel quad meshing benchmark (issue 4, dissertation §3.4): Table 3.4
// recomputed, thread scaling and the predicted speedup of Fig. 3.9(b), and the
// large-mesh throughput run.
//
//   bench_quad2d table DATA_DIR [SEGMENTS]   Table 3.4: Key/32, Pipe/16, Gulf/512,1024; all partitionings
//   bench_quad2d scaling [QUADS]             Key: 1 vs 2 threads; per-part times; predicted speedup 4..1024
//   bench_quad2d large DATA_DIR QUADS        Gulf of Mexico at about QUADS quads: time, quads/s, memory
//   bench_quad2d gmsh                        ours beside Gmsh 4.8's best all-quad, same regions and sizes
//
// Prints Markdown; bench/run_quad2d.sh stores it in bench/results/quad2d.md.
#include "bench_inputs.hpp"
#include "structmesh/io.hpp"
#include "structmesh/quad2d.hpp"
#include "structmesh/regions.hpp"

#include <oneapi/tbb/global_control.h>

#ifdef STRUCTMESH_BENCH_GMSH
#include "gmsh_quads.hpp"
#endif

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

using namespace structmesh;

namespace {

// Table 3.4, "avg / std / min / singular", keyed by "input/parts/method".
const std::map<std::string, const char*>& dissertation() {
  static const std::map<std::string, const char*> table = {
      {"key/32/sequential", "0.97 / 0.13 / 0.39 / 35"}, {"pipe/16/sequential", "0.97 / 0.04 / 0.31 / 34"},
      {"key/32/cvt", "0.98 / 0.14 / 0.38 / 233"},       {"pipe/16/cvt", "0.97 / 0.04 / 0.30 / 55"},
      {"key/32/metis", "0.93 / 0.27 / 0.23 / 411"},     {"pipe/16/metis", "0.94 / 0.09 / 0.23 / 128"},
      {"key/32/madd", "0.97 / 0.18 / 0.23 / 226"},      {"pipe/16/madd", "0.95 / 0.07 / 0.23 / 84"},
      {"key/32/cvtgp", "0.98 / 0.13 / 0.38 / 216"},     {"pipe/16/cvtgp", "0.97 / 0.04 / 0.30 / 50"},
      {"gulf/1024/cvt", "0.97 / 0.04 / 0.36 / 3158"},   {"gulf/1024/metis", "0.96 / 0.15 / 0.21 / 3491"},
      {"gulf/1024/madd", "0.96 / 0.09 / 0.23 / 3201"},  {"gulf/1024/cvtgp", "0.98 / 0.04 / 0.36 / 3104"},
  };
  return table;
}

double total_seconds(const Quad2dReport& r) {
  for (const auto& [name, seconds] : r.stage_seconds)
    if (name == "total") return seconds;
  return 0;
}

struct Input {
  std::string name;
  Polygon2 region;
  std::vector<std::size_t> parts;
  std::size_t quads = 0;  // 0: size = the mean boundary segment (§3.3.1)
};

std::vector<Input> table_inputs(const std::filesystem::path& data, std::size_t segments) {
  std::vector<Input> inputs;
  inputs.push_back({"key", make_key_region(segments), {32}, 0});
  inputs.push_back({"pipe", make_pipe_region(segments), {16}, 0});
  const std::filesystem::path gulf = data / "regions" / "gulf_of_mexico.geojson";
  // The Gulf's mean boundary segment (tiny islands) would give ~20M quads: 1M here.
  if (std::filesystem::exists(gulf)) inputs.push_back({"gulf", read_region(gulf).front(), {512, 1024}, 1000000});
  return inputs;
}

void table(const std::filesystem::path& data, std::size_t segments) {
  std::printf(
      "| input | parts | partitioning | quads | SJ avg / std / min | singular | inverted | fallback loops | "
      "seconds | dissertation (avg / std / min / singular) |\n");
  std::printf("|---|---:|---|---:|---|---:|---:|---:|---:|---|\n");
  const std::vector<std::pair<std::string, PartitionMethod>> methods = {{"cvt", PartitionMethod::Cvt},
                                                                        {"metis", PartitionMethod::Metis},
                                                                        {"madd", PartitionMethod::Madd},
                                                                        {"cvtgp", PartitionMethod::CvtGp}};
  for (const Input& input : table_inputs(data, segments)) {
    for (const std::size_t parts : input.parts) {
      std::vector<std::pair<std::string, Quad2dOptions>> runs;
      if (input.name != "gulf") {
        Quad2dOptions sequential;
        sequential.partition.parts = 1;
        runs.emplace_back("sequential", sequential);
      }
      for (const auto& [name, method] : methods) {
        Quad2dOptions options;
        options.partition.parts = parts;
        options.partition.method = method;
        runs.emplace_back(name, options);
      }
      for (auto& [name, options] : runs) {
        options.target_quads = input.quads;
        const std::string key = input.name + "/" + std::to_string(parts) + "/" + name;
        const auto printed = dissertation().find(key);
        const char* anchor = printed == dissertation().end() ? "-" : printed->second;
        try {
          const Quad2dResult result = mesh_region_quads(input.region, options);
          const Quad2dReport& r = result.report;
          std::printf("| %s | %zu | %s | %zu | %.3f / %.3f / %.3f | %zu | %zu | %zu | %.2f | %s |\n",
                      input.name.c_str(), r.parts, name.c_str(), r.quads, r.scaled_jacobian_avg, r.scaled_jacobian_std,
                      r.scaled_jacobian_min, r.singular_vertices, r.inverted, r.paving.fallback_loops, total_seconds(r),
                      anchor);
        } catch (const std::exception& e) {
          std::printf("| %s | %zu | %s | failed: %s | | | | | | %s |\n", input.name.c_str(), parts, name.c_str(),
                      e.what(), anchor);
        }
        std::fflush(stdout);
      }
    }
  }
}

void scaling(std::size_t quads) {
  // The Key at a fine boundary (20,000 segments) and about `quads` quads.
  const Polygon2 region = make_key_region(20000);
  std::printf("### Threads (Key, 20,000 boundary segments, about %zu quads, 64 parts, CVT-GP)\n\n", quads);
  // Wall times on this shared 2-core VM vary by 10-20% from run to run (one-shot
  // speedups of 1.51-2.15 were measured for the same build), so each thread count
  // runs three times, alternating, and the row shows the run with the median total;
  // the speedup is given from the medians and from the fastest runs.
  constexpr int kRounds = 3;
  struct Run {
    std::size_t quads = 0;
    std::map<std::string, double> stage;
    double total = 0;
  };
  std::map<int, std::vector<Run>> runs;
  for (int round = 0; round < kRounds; ++round)
    for (const int threads : {1, 2}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
      Quad2dOptions options;
      options.target_quads = quads;
      options.partition.parts = 64;
      const Quad2dResult result = mesh_region_quads(region, options);
      const Quad2dReport& r = result.report;
      runs[threads].push_back({r.quads, {r.stage_seconds.begin(), r.stage_seconds.end()}, total_seconds(r)});
    }
  for (auto& [threads, list] : runs)
    std::sort(list.begin(), list.end(), [](const Run& a, const Run& b) { return a.total < b.total; });
  const auto median = [&](int threads) -> const Run& { return runs[threads][kRounds / 2]; };
  std::printf(
      "| threads | quads | partition s | sample s | paving s | merge s | relax s | quality s "
      "| total s (median of %d) | fastest s | quads/s (median) | speedup (median) | speedup (fastest) |\n",
      kRounds);
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const int threads : {1, 2}) {
    const Run& m = median(threads);
    std::map<std::string, double> stage = m.stage;
    std::printf("| %d | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | %.2f | %.2f |\n", threads,
                m.quads, stage["partition"], stage["sample"], stage["paving"], stage["merge"], stage["relax"],
                stage["quality"], m.total, runs[threads].front().total, static_cast<double>(m.quads) / m.total,
                median(1).total / m.total, runs[1].front().total / runs[threads].front().total);
  }
  std::printf("\nAll totals (s): one thread");
  for (const Run& r : runs[1]) std::printf(" %.2f", r.total);
  std::printf("; two threads");
  for (const Run& r : runs[2]) std::printf(" %.2f", r.total);
  std::printf(".\n");
  std::fflush(stdout);
  // Per-part work measured on one thread at 1024 parts predicts the speedup on
  // 4..1024 processes (LPT assignment): Fig. 3.9(b)'s 2.78..601.5.
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
  Quad2dOptions options;
  options.target_quads = quads;
  options.partition.parts = 1024;
  const Quad2dResult result = mesh_region_quads(region, options);
  const std::vector<double>& part_seconds = result.report.part_seconds;
  std::vector<double> sorted = part_seconds;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double q) {
    return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
  };
  double mean = 0;
  for (const double s : sorted) mean += s;
  mean /= static_cast<double>(sorted.size());
  std::printf("\n### Per-part meshing time (Key, 1024 parts, one thread, %zu quads)\n\n", result.report.quads);
  std::printf("| min | 25%% | median | 75%% | max | max / mean |\n|---:|---:|---:|---:|---:|---:|\n");
  std::printf("| %.4f | %.4f | %.4f | %.4f | %.4f | %.2f |\n", sorted.front(), at(0.25), at(0.5), at(0.75),
              sorted.back(), sorted.back() / mean);
  std::printf("\n### Predicted speedup of the meshing stage (LPT assignment of the measured per-part times)\n\n");
  std::printf("| processes | predicted speedup | efficiency | Fig. 3.9(b) |\n|---:|---:|---:|---|\n");
  for (const std::size_t processes : {4, 16, 64, 256, 512, 1024}) {
    const double speedup = predicted_speedup(part_seconds, processes);
    const char* anchor = processes == 4 ? "2.78" : processes == 1024 ? "601.5" : "-";
    std::printf("| %zu | %.1f | %.2f | %s |\n", processes, speedup, speedup / static_cast<double>(processes), anchor);
  }
}

void large(const std::filesystem::path& data, std::size_t quads) {
  const std::filesystem::path gulf_path = data / "regions" / "gulf_of_mexico.geojson";
  const bool have_gulf = std::filesystem::exists(gulf_path);
  const Polygon2 region = have_gulf ? read_region(gulf_path).front() : make_key_region(20000);
  Quad2dOptions options;
  options.target_quads = quads;
  options.progress = true;
  Quad2dResult result;
  try {
    result = mesh_region_quads(region, options);
  } catch (const std::exception& e) {
    std::printf("failed: %s\n", e.what());
    return;
  }
  const Quad2dReport& r = result.report;
  std::map<std::string, double> stage(r.stage_seconds.begin(), r.stage_seconds.end());
  std::printf(
      "| input | quads | parts | SJ avg / min | inverted | partition s | paving s | merge s | relax s | "
      "quality s | total s | quads/s | peak RSS MB |\n");
  std::printf("|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  const double total = total_seconds(r);
  std::printf("| %s | %zu | %zu | %.3f / %.3f | %zu | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | %.0f |\n",
              have_gulf ? "gulf" : "key", r.quads, r.parts, r.scaled_jacobian_avg, r.scaled_jacobian_min, r.inverted,
              stage["partition"], stage["paving"], stage["merge"], stage["relax"], stage["quality"], total,
              static_cast<double>(r.quads) / total, r.peak_rss_mb);
}

void versus_gmsh() {
  struct Case {
    std::string name;
    Polygon2 region;
    double size;
    std::size_t parts;  // 0: our default
  };
  std::vector<Case> cases;
  cases.push_back({"(a) unit square, hole r = 0.25, h = 0.02", bench::square_with_hole(), 0.02, 0});
  cases.push_back({"(b) noisy disk + island, h = 0.01", bench::noisy_disk_with_island(), 0.01, 0});
  Polygon2 key = make_key_region(2000), pipe = make_pipe_region(2000);
  const double key_h = bench::perimeter(key) / 2000, pipe_h = bench::perimeter(pipe) / 2000;
  cases.push_back({"(c) Key, 2000 segments, h = mean segment", std::move(key), key_h, 32});
  cases.push_back({"(d) Pipe, 2000 segments, h = mean segment", std::move(pipe), pipe_h, 16});
  std::printf("| input | mesher | quads | SJ avg / std / min | singular | inverted | seconds | quads/s |\n");
  std::printf("|---|---|---:|---|---:|---:|---:|---:|\n");
  for (const Case& c : cases) {
    for (const int threads : {1, 2}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
      Quad2dOptions options;
      options.size = c.size;
      options.partition.parts = c.parts;
      try {
        const Quad2dResult result = mesh_region_quads(c.region, options);
        const Quad2dReport& r = result.report;
        const double seconds = total_seconds(r);
        std::printf(
            "| %s | structmesh, %zu parts, %d thread%s | %zu | %.3f / %.3f / %.3f | %zu | %zu | %.2f | %.0f |\n",
            c.name.c_str(), r.parts, threads, threads > 1 ? "s" : "", r.quads, r.scaled_jacobian_avg,
            r.scaled_jacobian_std, r.scaled_jacobian_min, r.singular_vertices, r.inverted, seconds,
            static_cast<double>(r.quads) / seconds);
      } catch (const std::exception& e) {
        std::printf("| %s | structmesh, %d threads | failed: %s | | | | | |\n", c.name.c_str(), threads, e.what());
      }
      std::fflush(stdout);
    }
#ifdef STRUCTMESH_BENCH_GMSH
    for (const int algorithm : {6, 8}) {
      const GmshQuadSummary g = gmsh_all_quad_isolated(c.region, c.size, algorithm, 900);
      if (!g.failure.empty()) {
        std::printf("| %s | Gmsh 4.8 alg. %d + Blossom full-quad | %s | | | | | |\n", c.name.c_str(), algorithm,
                    g.failure.c_str());
        continue;
      }
      std::printf(
          "| %s | Gmsh 4.8 alg. %d + Blossom full-quad, 1 thread | %zu (+%zu triangles) | %.3f / %.3f / %.3f | "
          "%zu | %zu | %.2f | %.0f |\n",
          c.name.c_str(), algorithm, g.quads, g.leftover_triangles, g.scaled_jacobian_avg, g.scaled_jacobian_std,
          g.scaled_jacobian_min, g.singular_vertices, g.inverted, g.seconds,
          g.seconds > 0 ? static_cast<double>(g.quads) / g.seconds : 0.0);
      std::fflush(stdout);
    }
#else
    std::printf("| %s | Gmsh | not built (no Gmsh library) | | | | | |\n", c.name.c_str());
#endif
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  try {
    if (mode == "table" && argc >= 3) {
      table(argv[2], argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 2000);
    } else if (mode == "scaling") {
      scaling(argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 2000000);
    } else if (mode == "gmsh") {
      versus_gmsh();
    } else if (mode == "large" && argc >= 4) {
      large(argv[2], std::strtoul(argv[3], nullptr, 10));
    } else {
      std::fprintf(stderr,
                   "usage: bench_quad2d table DATA_DIR [SEGMENTS] | scaling [QUADS] | large DATA_DIR QUADS | gmsh\n");
      return 2;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_quad2d: %s\n", e.what());
    return 1;
  }
  return 0;
}
