// Tables 3.1 and 3.2 of the dissertation recomputed: every method on identical
// input (same projection, domain, metrics), beside the printed numbers.
//
//   bench_partition2d tables DATA_DIR [SEGMENTS]   Key, Pipe, Gulf; all methods
//   bench_partition2d exact                        CVT-GP vs the exact MILP on small graphs
//   bench_partition2d large SEGMENTS               runtime/memory on a huge Key boundary
//
// Prints Markdown; bench/run_partition2d.sh stores it in bench/results/partition2d.md.
#include "structmesh/io.hpp"
#include "structmesh/partition2d.hpp"
#include "structmesh/regions.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

using namespace structmesh;

namespace {

struct Printed {
  const char* rw;
  const char* rc;
  const char* delta;
};

// Table 3.2 (and 3.1 where 3.2 has no entry), keyed by "input/k/method".
const std::map<std::string, Printed>& dissertation() {
  static const std::map<std::string, Printed> table = {
      {"key/128/cvt", {"2.01 (T3.1: 1.23)", "13.25 (T3.1: 9.41)", "0.18/0.15"}},
      {"key/1024/cvt", {"1.92", "104.3", "0.15/0.14"}},
      {"key/128/metis", {"1.03", "12.21", "0.32/0.26"}},
      {"key/1024/metis", {"1.02", "93.31", "0.41/0.21"}},
      {"key/128/madd", {"1.13", "14.26", "0.32/0.20"}},
      {"key/1024/madd", {"1.08", "104.91", "0.25/0.19"}},
      {"key/128/cvtgp", {"1.06 (T3.1: 1.11)", "13.57 (T3.1: 9.24)", "0.17/0.15"}},
      {"key/1024/cvtgp", {"1.04", "105.21", "0.15/0.14"}},
      {"key/16/cvt", {"1.65", "1.21", "0.26"}},
      {"key/16/cvtgp", {"1.15", "1.11", "0.21"}},
      {"key/32/cvt", {"1.45", "2.21", "0.21"}},
      {"key/32/cvtgp", {"1.24", "2.01", "0.16"}},
      {"pipe/128/cvt", {"2.09", "4.76", "0.18/0.15"}},
      {"pipe/1024/cvt", {"1.98", "36.51", "0.15/0.15"}},
      {"pipe/128/metis", {"1.05", "4.64", "0.32/0.25"}},
      {"pipe/1024/metis", {"1.04", "36.37", "0.42/0.21"}},
      {"pipe/128/madd", {"1.25", "5.06", "0.32/0.20"}},
      {"pipe/1024/madd", {"1.13", "35.48", "0.25/0.21"}},
      {"pipe/128/cvtgp", {"1.13", "4.71", "0.15/0.12"}},
      {"pipe/1024/cvtgp", {"1.10", "36.42", "0.13/0.11"}},
      {"pipe/32/cvt", {"1.81", "1.82", "0.23"}},
      {"pipe/32/cvtgp", {"1.31", "1.77", "0.20"}},
  };
  return table;
}

double total_seconds(const PartitionMetrics& m) {
  double total = 0;
  for (const auto& [name, seconds] : m.stage_seconds) total += seconds;
  return total;
}

double stage(const PartitionMetrics& m, const std::string& name) {
  for (const auto& [stage_name, seconds] : m.stage_seconds) {
    if (stage_name == name) return seconds;
  }
  return 0;
}

void table(const std::string& name, const Polygon2& region, const std::vector<std::size_t>& ks) {
  std::printf("\n### %s (%zu boundary segments, %zu holes)\n\n", name.c_str(), region.points.size(),
              region.hole_count());
  std::printf(
      "| k | method | cells | R_W | R_C (3.5) | R_C norm | R_C / METIS | delta (3.8) | delta at 1e-3 | delta junction "
      "| delta / METIS "
      "| "
      "comps | time (s) | dissertation R_W | R_C | delta |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::size_t k : ks) {
    std::map<std::string, PartitionMetrics> results;
    for (const PartitionMethod method :
         {PartitionMethod::Metis, PartitionMethod::Madd, PartitionMethod::Cvt, PartitionMethod::CvtGp}) {
      PartitionOptions options;
      options.parts = k;
      options.method = method;
      const std::string key = method_name(method);
      try {
        results[key] = partition_region(region, options).metrics;
      } catch (const std::exception& e) {
        std::printf("| %zu | %s | failed: %s ||||||||||||||\n", k, key.c_str(), e.what());
        continue;
      }
      const PartitionMetrics& m = results[key];
      const PartitionMetrics* metis = results.count("metis") ? &results["metis"] : nullptr;
      const auto found = dissertation().find(name + "/" + std::to_string(k) + "/" + key);
      const Printed printed = found != dissertation().end() ? found->second : Printed{"", "", ""};
      std::printf(
          "| %zu | %s | %zu | %.3f | %.4g | %.3f | %.3f | %.3f | %.3f | %.3f | %.2f | %zu | %.2f | %s | %s | %s |\n", k,
          key.c_str(), m.cells, m.workload_ratio, m.compactness, m.compactness_normalized,
          metis ? m.compactness / metis->compactness : 0.0, m.angle_deviation, m.angle_deviation_fine,
          m.junction_angle_deviation,
          metis && metis->angle_deviation > 0 ? m.angle_deviation / metis->angle_deviation : 0.0,
          m.max_components_per_part, total_seconds(m), printed.rw, printed.rc, printed.delta);
      std::fflush(stdout);
    }
  }
}

void exact_table() {
  std::printf("\n### CVT-GP against the exact MILP (CBC), small graphs\n\n");
  std::printf("| input | k | cells | method | R_W | separator length | delta (3.8) | exact gap | time (s) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& [name, region] :
       {std::pair{std::string("key"), make_key_region(2000)}, std::pair{std::string("pipe"), make_pipe_region(4000)}}) {
    for (const std::size_t k : {2, 4}) {
      for (const PartitionMethod method : {PartitionMethod::CvtGp, PartitionMethod::Exact}) {
        PartitionOptions options;
        options.parts = k;
        options.cells = 200;
        options.exact_cells = true;
        options.method = method;
        options.exact_time_limit = 60;
        try {
          const PartitionMetrics m = partition_region(region, options).metrics;
          std::printf("| %s | %zu | %zu | %s | %.3f | %.4g | %.3f | %.3g | %.2f |\n", name.c_str(), k, m.cells,
                      method_name(method), m.workload_ratio, m.separator_length, m.angle_deviation, m.exact_gap,
                      total_seconds(m));
        } catch (const std::exception& e) {
          std::printf("| %s | %zu | 200 | %s | failed: %s |||||\n", name.c_str(), k, method_name(method), e.what());
        }
        std::fflush(stdout);
      }
    }
  }
}

void large(std::size_t segments) {
  const auto start = std::chrono::steady_clock::now();
  const Polygon2 key = make_key_region(segments);
  const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  PartitionOptions options;
  options.parts = 128;
  options.cells = 4000;
  const PartitionMetrics m = partition_region(key, options).metrics;
  std::printf("\n### Key with %zu boundary segments, CVT-GP, k = 128, 4000 cells\n\n", segments);
  std::printf("| stage | seconds |\n|---|---|\n");
  for (const auto& [name, seconds] : m.stage_seconds) std::printf("| %s | %.2f |\n", name.c_str(), seconds);
  std::printf("| **L_p-CVT (target <= 10 s)** | **%.2f** |\n", stage(m, "domain triangulation") + stage(m, "L_p-CVT"));
  std::printf("| **full partition (target <= 15 s)** | **%.2f** |\n", total_seconds(m));
  std::printf(
      "\nBuilding the region itself took %.2f s (not counted). Peak RSS %.0f MB. R_W %.3f, delta %.3f, "
      "CVT %d iterations (%s).\n",
      build, m.peak_rss_mb, m.workload_ratio, m.angle_deviation, m.cvt_iterations, m.cvt_stop_reason.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "tables" && argc > 2) {
    const std::size_t segments = argc > 3 ? std::stoul(argv[3]) : 20000;
    table("key", make_key_region(segments), {16, 32, 128, 1024});
    table("pipe", make_pipe_region(segments), {16, 32, 128, 1024});
    const std::filesystem::path gulf = std::filesystem::path(argv[2]) / "regions" / "gulf_of_mexico.geojson";
    if (std::filesystem::exists(gulf)) table("gulf", read_region(gulf).front(), {128, 1024});
    return 0;
  }
  if (mode == "exact") {
    exact_table();
    return 0;
  }
  if (mode == "large" && argc > 2) {
    large(std::stoul(argv[2]));
    return 0;
  }
  std::fprintf(stderr, "usage: bench_partition2d tables DATA_DIR [SEGMENTS] | exact | large SEGMENTS\n");
  return 2;
}
