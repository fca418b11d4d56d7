// The ETA of a compare's runs (issue 35): a 576-landmark EKF reference took 8 minutes while the
// progress line said ETA 0:01-0:03, the share of all steps done being nearly full with the reduced
// runs. The ETA now follows each run's own pace.
#include <gtest/gtest.h>

#include <cmath>

#include "budget_slam/engine/CompareRuns.h"

using namespace budget_slam;
using namespace budget_slam::runs;

TEST(CompareEta, TheSlowestRunBoundsIt) {
  // The reduced runs are done; the reference has 2,000 of its 6,000 steps left at 0.25 s a step:
  // 500 s, not the few seconds the share of all steps done (5/6 of 7 runs' steps) would say.
  std::vector<RunPace> runs(7);
  runs[0] = {2000, 0.25};
  EXPECT_DOUBLE_EQ(compareEta(runs, 2), 500.0);
  // The share-of-steps ETA it replaces: elapsed x (1 - f) / f.
  const double elapsed = 600, f = (7 * 6000.0 - 2000) / (7 * 6000.0);
  EXPECT_LT(elapsed * (1 - f) / f, 32.0);
}

TEST(CompareEta, QueuedRunsShareTheThreads) {
  // Two threads busy with 100 s each; two queued runs of 1,000 steps at the median pace of the
  // measured ones (0.1 s): 400 s of work on 2 threads.
  const std::vector<RunPace> runs = {{1000, 0.1}, {1000, 0.1}, {1000, NAN}, {1000, NAN}};
  EXPECT_DOUBLE_EQ(compareEta(runs, 2), 200.0);
  EXPECT_DOUBLE_EQ(compareEta(runs, 1), 400.0);
}

TEST(CompareEta, UnknownBeforeAnyStepAndZeroWhenDone) {
  EXPECT_TRUE(std::isnan(compareEta({{10, NAN}, {10, NAN}}, 2)));
  EXPECT_EQ(compareEta({{0, NAN}, {0, 0.5}}, 2), 0.0);
}

TEST(CompareEta, ALargeEkfReferenceIsNamedAndTheGraphBackendPointedTo) {
  EXPECT_EQ(largeReferenceNote("ekf", 576),
            "the unreduced reference will hold up to 576 landmarks (the rawlog's distinct ids), "
            "and an EKF step costs the square of the map's size: the reference will take the "
            "longest by far; --backend graph serves large maps (docs/GRAPH.md)");
  EXPECT_EQ(largeReferenceNote("ekf", kLargeEkfMap - 1), "");
  EXPECT_EQ(largeReferenceNote("graph", 5000), "");
  Step a, b;
  a.scan.emplace(), b.scan.emplace();
  a.scan->readings = {{3, 1, 0, 0}, {4, 1, 0, 0}};
  b.scan->readings = {{4, 1, 0, 0}, {9, 1, 0, 0}};
  EXPECT_EQ(distinctLandmarkIds({a, b}), 3u);
}
