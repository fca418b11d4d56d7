// An outcome from a small run through the run layer's API (runs::runSlam), and its summary.json.
#include <gtest/gtest.h>

#include <filesystem>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/graph/GraphBackend.h"
#include "budget_slam/runs/Runs.h"
#include "budget_slam/runs/SummaryJson.h"

namespace budget_slam::runs {
namespace {

namespace fs = std::filesystem;

const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;

const BackendRegistry& backends() {
  static const BackendRegistry r = [] {
    BackendRegistry b;
    b.add(ekf::EkfBackend::entry());
    b.add(graph::GraphBackend::entry());
    return b;
  }();
  return r;
}

RunSpec demoSpec(const std::string& name, const std::string& backend) {
  RunSpec spec;
  spec.backends = &backends();
  spec.driver.backend = backend;
  spec.driver.budget.reducer = "random";
  spec.driver.budget.max_landmarks = 10;
  spec.driver.save_3d_scene = false;
  spec.rawlog = kRoot + "/rawlogs/kf-slam_demo.rawlog";
  const auto dir = fs::temp_directory_path() / "budget_slam_tests" / "runs" / name;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  spec.outdir = dir.string();
  spec.max_steps = 40;
  spec.given = {{"rawlog", spec.rawlog}};
  return spec;
}

TEST(RunSlam, ASmallRunsOutcomeIsItsSummary) {
  Cancellation::clear();
  for (const std::string backend : {"ekf", "graph"}) {
    SCOPED_TRACE(backend);
    const RunSpec spec = demoSpec("small_" + backend, backend);
    std::size_t steps_heard = 0;
    RunHooks hooks;
    hooks.on_step = [&](StepIndex) { ++steps_heard; };
    const RunReport r = runSlam(spec, hooks);
    ASSERT_TRUE(r.outcome.ok()) << r.line;
    EXPECT_EQ(exitCode(r.outcome), 0);
    EXPECT_EQ(r.line, "");
    EXPECT_EQ(r.steps, 40u);
    EXPECT_EQ(steps_heard, 40u);
    ASSERT_TRUE(r.outcome.run);
    const RunOutcome::Run& run = *r.outcome.run;
    EXPECT_EQ(run.backend, backend);
    EXPECT_EQ(run.reducer, "random");
    EXPECT_EQ(run.cap, std::optional<std::size_t>(10));
    EXPECT_EQ(run.counts.steps, 40u);
    EXPECT_LE(run.counts.landmarks_final, 10u);
    EXPECT_EQ(run.counts.landmarks_final, r.landmarks);
    EXPECT_EQ(run.counts.landmarks_added, run.counts.landmarks_final + run.counts.evictions);
    EXPECT_GT(run.counts.evictions, 0u);
    EXPECT_GT(run.timings.steps_s, 0.0);
    EXPECT_EQ(run.relocalization.coverage.steps, 40u);
    EXPECT_EQ(run.relocalization.source, "landmark_ids");
    ASSERT_TRUE(r.final_pose);
    // The demo has ground truth next to it: the errors are there and finite.
    ASSERT_TRUE(r.outcome.ground_truth);
    EXPECT_LT(r.outcome.ground_truth->errors.trajectory_rmse_aligned, 1.0);
    EXPECT_EQ(r.outcome.ground_truth->errors.poses, 40u);

    // summary.json is the outcome, read back through the one reader.
    const SummaryFile read = readSummary(r.folder + "/summary.json");
    EXPECT_EQ(read.json, summaryJson(r.outcome));
    EXPECT_EQ(read.outcome.run->counts.evictions, run.counts.evictions);
    EXPECT_EQ(read.json["rawlog"], spec.rawlog);
    EXPECT_EQ(read.json["started"], true);
    EXPECT_EQ(read.json["session_state"]["written"], true);
  }
}

TEST(RunSlam, AMissingRawlogIsAFailedOutcomeWithItsKind) {
  Cancellation::clear();
  RunSpec spec = demoSpec("missing", "ekf");
  spec.rawlog = kRoot + "/rawlogs/no_such.rawlog";
  const RunReport r = runSlam(spec, {});
  EXPECT_EQ(r.outcome.status, RunStatus::Failed);
  EXPECT_EQ(r.outcome.kind, ErrorKind::Input);
  EXPECT_EQ(exitCode(r.outcome), 1);
  EXPECT_NE(r.line.find("no_such.rawlog"), std::string::npos) << r.line;
  const SummaryFile read = readSummary(r.folder + "/summary.json");
  EXPECT_EQ(read.outcome.status, RunStatus::Failed);
  EXPECT_EQ(read.json["started"], false);
}

TEST(RunSlam, AStopRequestIsAnInterruptedOutcome) {
  Cancellation::clear();
  const RunSpec spec = demoSpec("stopped", "ekf");
  RunHooks hooks;
  hooks.on_step = [](StepIndex step) {
    if (step == 5) Cancellation::request(2);
  };
  const RunReport r = runSlam(spec, hooks);
  Cancellation::clear();
  EXPECT_EQ(r.outcome.status, RunStatus::Interrupted);
  EXPECT_EQ(exitCode(r.outcome), 130);
  EXPECT_EQ(r.line, "interrupted by Ctrl-C after step 5");
  const SummaryFile read = readSummary(r.folder + "/summary.json");
  EXPECT_EQ(read.outcome.status, RunStatus::Interrupted);
  EXPECT_EQ(read.outcome.run->counts.steps, 6u);
}

}  // namespace
}  // namespace budget_slam::runs
