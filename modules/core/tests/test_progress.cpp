#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <vector>

#include "budget_slam/core/Progress.h"

using namespace budget_slam;

TEST(Progress, DurationsReadAsClockTimes) {
  EXPECT_EQ(formatDuration(0), "0:00");
  EXPECT_EQ(formatDuration(7.4), "0:07");
  EXPECT_EQ(formatDuration(754), "12:34");
  EXPECT_EQ(formatDuration(3723), "1:02:03");
  EXPECT_EQ(formatDuration(std::nan("")), "?");
}

TEST(Progress, LinesEveryIntervalWithPercentRateAndEta) {
  double now = 100;
  std::ostringstream out;
  ProgressSettings settings;
  settings.style = ProgressSettings::Style::Lines;
  settings.line_every_s = 5;
  ProgressReporter p(out, "run", settings, [&] { return now; });
  // 100 steps a second over 1000 steps: a line at 5 s (50%) and at 10 s (100%) only.
  for (int k = 1; k <= 1000; ++k) {
    now = 100 + k * 0.01;
    p.update(k / 1000.0, k, 1000, "step " + std::to_string(k - 1));
  }
  p.finish(true);
  EXPECT_EQ(out.str(),
            "budget-slam: run 50%, 500 of 1000 steps, 100 steps/s, elapsed 0:05, ETA 0:05 "
            "(step 499)\n"
            "budget-slam: run 100%, 1000 of 1000 steps, 100 steps/s, elapsed 0:10, ETA 0:00 "
            "(step 999)\n");
}

TEST(Progress, UnknownTotalAndNothingBeforeTheFirstInterval) {
  double now = 0;
  std::ostringstream out;
  ProgressSettings settings;
  settings.style = ProgressSettings::Style::Lines;
  ProgressReporter p(out, "compare", settings, [&] { return now; });
  now = 4.9;
  p.update(0.1, 49, 0, "");
  EXPECT_EQ(out.str(), "");  // a short task says nothing
  now = 6;
  p.update(0.25, 60, 0, "1/4 runs done");
  EXPECT_EQ(out.str(),
            "budget-slam: compare 25%, 60 steps, 10 steps/s, elapsed 0:06, ETA 0:18 (1/4 runs "
            "done)\n");
}

TEST(Progress, BarRedrawsInPlaceWithEtaAndIsCleared) {
  double now = 0;
  std::ostringstream out;
  ProgressSettings settings;
  settings.style = ProgressSettings::Style::Bar;
  {
    ProgressReporter p(out, "run", settings, [&] { return now; });
    now = 2;
    p.update(0.5, 10, 20, "");
    EXPECT_EQ(out.str(),
              "\r[###############...............] run 50%, 10 of 20 steps, 5 steps/s, "
              "elapsed 0:02, ETA 0:02\x1b[K");
    now = 2.05;
    p.update(0.6, 12, 20, "");  // within 0.1 s: no redraw
    p.finish(false);
  }
  EXPECT_EQ(out.str().substr(out.str().size() - 4), "\r\x1b[K");
}

TEST(Progress, CallbackIsThrottledAndHearsTheEndOnce) {
  double now = 0;
  std::ostringstream out;
  std::vector<ProgressSnapshot> heard;
  ProgressSettings settings;  // no stream output (--quiet), the callback only
  settings.callback = [&](const ProgressSnapshot& s) { heard.push_back(s); };
  ProgressReporter p(out, "run", settings, [&] { return now; });
  for (int k = 0; k <= 100; ++k) {
    now = k * 0.0625;  // 16 updates a second (exact in binary), over 6.25 s
    p.update(k / 200.0, k, 200, "");
  }
  p.finish(true);
  p.finish(true);
  EXPECT_EQ(out.str(), "");
  ASSERT_EQ(heard.size(),
            26u + 1);  // every 0.25 s (the first update 0.2 s after the last), the end
  for (std::size_t i = 1; i < heard.size(); ++i)
    EXPECT_GE(heard[i].fraction, heard[i - 1].fraction);
  EXPECT_TRUE(heard.back().finished);
  EXPECT_EQ(heard.back().fraction, 1.0);
  EXPECT_EQ(heard.back().steps_done, 100u);
  EXPECT_FALSE(heard[3].finished);
  EXPECT_NEAR(heard[3].steps_per_s, 16, 1e-9);
}
