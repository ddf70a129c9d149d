// The progress reporter: forced output ends with a 100% line, quiet prints nothing,
// and concurrent advances with repeated finish() print one final line.
#include "structmesh/progress.hpp"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

namespace structmesh {
namespace {

struct SettingsGuard {
  ProgressSettings saved = progress_settings();
  ~SettingsGuard() { progress_settings() = saved; }
};

TEST(Progress, ForcedReportEndsWithACompleteLine) {
  SettingsGuard guard;
  progress_settings() = {.quiet = false, .force = true};
  testing::internal::CaptureStderr();
  {
    Progress progress("reading things", 1000);
    EXPECT_TRUE(progress.enabled());
    for (int i = 0; i < 1000; ++i) progress.advance();
  }
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("reading things 100%"), std::string::npos) << err;
  EXPECT_NE(err.find("/s)"), std::string::npos) << err;  // the rate
  EXPECT_EQ(err.back(), '\n');
}

TEST(Progress, QuietWinsOverForce) {
  SettingsGuard guard;
  progress_settings() = {.quiet = true, .force = true};
  testing::internal::CaptureStderr();
  {
    Progress progress("silent", 10);
    EXPECT_FALSE(progress.enabled());
    progress.advance(10);
    status("a status line");
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(Progress, NotATerminalAndNotForcedIsSilent) {
  SettingsGuard guard;
  progress_settings() = {.quiet = false, .force = false};
  testing::internal::CaptureStderr();  // redirects stderr to a file: not a TTY
  { Progress progress("hidden", 5); }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(Progress, ConcurrentAdvancesAndRepeatedFinishPrintOneFinalLine) {
  SettingsGuard guard;
  progress_settings() = {.quiet = false, .force = true};
  testing::internal::CaptureStderr();
  {
    Progress progress("parallel", 100000);
    tbb::parallel_for(0, 100000, [&](int) { progress.advance(); });
    progress.finish();
    progress.finish();
  }
  const std::string err = testing::internal::GetCapturedStderr();
  const auto first = err.find("parallel 100%");
  ASSERT_NE(first, std::string::npos) << err;
  EXPECT_EQ(err.find("parallel 100%", first + 1), std::string::npos) << "final line printed twice";
}

}  // namespace
}  // namespace structmesh
