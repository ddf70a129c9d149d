// Progress reporting for long steps on stderr: "label  42% 1.2M/s ETA 3s".
// Silent when stderr is not a terminal unless forced on (--progress), and always
// silent when quiet (--quiet). Thread-safe: advance() may be called from TBB tasks.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace structmesh {

struct ProgressSettings {
  bool quiet = false;  // --quiet: nothing at all
  bool force = false;  // --progress: report even when stderr is not a TTY
};
/// Process-wide settings, set once by the CLI.
ProgressSettings& progress_settings();

class Progress {
 public:
  Progress(std::string label, std::uint64_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void advance(std::uint64_t n = 1);
  void set(std::uint64_t done);
  /// Prints the final line ("label 100% ... in 1.3s"); also done by the destructor.
  void finish();
  bool enabled() const { return enabled_; }

 private:
  void draw(bool final_line);

  std::string label_;
  std::uint64_t total_;
  std::atomic<std::uint64_t> done_{0};
  std::chrono::steady_clock::time_point start_;
  std::atomic<std::int64_t> last_draw_ns_{0};
  std::mutex draw_mutex_;
  bool enabled_ = false, tty_ = false, finished_ = false;
};

/// Peak resident memory of this process so far, in MB (getrusage's ru_maxrss).
double peak_rss_mb();

/// One status line on stderr unless quiet ("reading bunny.obj ...").
void status(const std::string& message);

}  // namespace structmesh
