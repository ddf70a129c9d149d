#include "structmesh/progress.hpp"

#include <sys/resource.h>

#include <unistd.h>

#include <cstdio>

namespace structmesh {

ProgressSettings& progress_settings() {
  static ProgressSettings settings;
  return settings;
}

namespace {

std::string human_count(double value) {
  char buffer[32];
  if (value >= 1e9)
    std::snprintf(buffer, sizeof buffer, "%.1fG", value / 1e9);
  else if (value >= 1e6)
    std::snprintf(buffer, sizeof buffer, "%.1fM", value / 1e6);
  else if (value >= 1e3)
    std::snprintf(buffer, sizeof buffer, "%.1fk", value / 1e3);
  else
    std::snprintf(buffer, sizeof buffer, "%.0f", value);
  return buffer;
}

}  // namespace

Progress::Progress(std::string label, std::uint64_t total)
    : label_(std::move(label)), total_(total), start_(std::chrono::steady_clock::now()) {
  const ProgressSettings& settings = progress_settings();
  tty_ = isatty(fileno(stderr)) != 0;
  enabled_ = !settings.quiet && (tty_ || settings.force);
}

Progress::~Progress() { finish(); }

void Progress::advance(std::uint64_t n) {
  done_.fetch_add(n, std::memory_order_relaxed);
  if (enabled_) draw(false);
}

void Progress::set(std::uint64_t done) {
  done_.store(done, std::memory_order_relaxed);
  if (enabled_) draw(false);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (enabled_) draw(true);
}

void Progress::draw(bool final_line) {
  using namespace std::chrono;
  const std::int64_t now_ns = duration_cast<nanoseconds>(steady_clock::now() - start_).count();
  // Redraw at most 5 times a second on a terminal, once every 2 s into a log.
  const std::int64_t interval = tty_ ? 200'000'000 : 2'000'000'000;
  std::int64_t last = last_draw_ns_.load(std::memory_order_relaxed);
  if (!final_line && (now_ns - last < interval || !last_draw_ns_.compare_exchange_strong(last, now_ns))) return;
  std::lock_guard lock(draw_mutex_);
  const double seconds = now_ns * 1e-9;
  const std::uint64_t done = final_line ? total_ : std::min(done_.load(), total_);
  const double fraction = total_ == 0 ? 1.0 : static_cast<double>(done) / static_cast<double>(total_);
  const double rate = seconds > 0 ? done / seconds : 0.0;
  char line[256];
  if (final_line) {
    std::snprintf(line, sizeof line, "%s 100%% %s in %.2fs (%s/s)", label_.c_str(), human_count(total_).c_str(),
                  seconds, human_count(rate).c_str());
  } else {
    const double eta = rate > 0 ? (total_ - done) / rate : 0.0;
    std::snprintf(line, sizeof line, "%s %3.0f%% %s/s ETA %.0fs", label_.c_str(), 100.0 * fraction,
                  human_count(rate).c_str(), eta);
  }
  std::fprintf(stderr, tty_ ? "\r\033[K%s%s" : "%s%s", line, (final_line || !tty_) ? "\n" : "");
  std::fflush(stderr);
}

void status(const std::string& message) {
  if (progress_settings().quiet) return;
  std::fprintf(stderr, "%s\n", message.c_str());
}

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace structmesh
