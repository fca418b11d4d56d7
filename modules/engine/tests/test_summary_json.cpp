// summary.json: what the writer writes the reader reads back, and the reader's bad-input lines.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/engine/SummaryJson.h"

namespace budget_slam::runs {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const auto d = fs::temp_directory_path() / "budget_slam_tests" / "runs" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

RunOutcome fullOutcome() {
  RunOutcome o;
  o.fail(RunStatus::Failed, ErrorKind::Output, "trajectory.tum: no space left on device");
  o.files_not_written = {"trajectory.tum", "map.png"};
  auto& run = o.run.emplace();
  run.backend = "graph";
  run.reducer = "mi";
  run.cap = 20;
  run.counts = {110, 20, 0, 0, 24, 61, 41, 3, 110, 0};
  run.timings = {1.25, 11.4, 30.5, 123456789};
  run.agreement = nlohmann::json::array({{{"a", "mi"}, {"b", "random"}, {"agree", 3}}});
  run.relocalization.coverage.min_landmarks = 2;
  run.relocalization.coverage.steps = 110;
  run.relocalization.coverage.steps_covered = 90;
  run.relocalization.coverage.coverage_pct = 100.0 * 90 / 110;
  run.relocalization.coverage.mean_landmarks = 3.5;
  run.relocalization.source = "landmark_ids";
  run.relocalization.details = {{"landmarks_matched_to_reference", 18}};
  auto& gt = o.ground_truth.emplace();
  gt.landmarks_file = "a_ground_truth.txt";
  gt.path_file = "a_ground_truth_robot_path.txt";
  gt.errors.poses = 110;
  gt.errors.trajectory_rmse = 0.25;
  gt.errors.trajectory_max = 0.5;
  gt.errors.trajectory_rmse_aligned = 0.125;
  gt.errors.alignment_rotation_deg = 1.5;
  gt.errors.rpe = {12, 0.0625, 0.2};
  gt.errors.landmarks = 20;
  gt.errors.landmark_rmse = 0.3;  // landmark_rmse_aligned stays NaN: written as null
  gt.nees = {2.9, 100};
  gt.alignment = metrics::MapAlignment::fromPose(1.5, -2.0, 0.25, "landmarks", 20);
  o.given = {{"rawlog", "a.rawlog"}, {"config", "c.ini"}, {"started", true}};
  return o;
}

TEST(SummaryJson, WriterThenReaderGivesTheSameSummary) {
  const RunOutcome o = fullOutcome();
  const auto path = (scratch("round_trip") / "summary.json").string();
  writeSummary(path, o);
  const SummaryFile read = readSummary(path);
  EXPECT_EQ(read.status_text, "failed");
  EXPECT_EQ(read.outcome.status, RunStatus::Failed);
  EXPECT_EQ(read.outcome.error, o.error);
  EXPECT_EQ(read.outcome.files_not_written, o.files_not_written);
  ASSERT_TRUE(read.outcome.run);
  EXPECT_EQ(read.outcome.run->cap, o.run->cap);
  EXPECT_EQ(read.outcome.run->counts.evictions, 41u);
  EXPECT_EQ(read.outcome.run->counts.refused, 3u);
  EXPECT_DOUBLE_EQ(read.outcome.run->relocalization.coverage.coverage_pct, 100.0 * 90 / 110);
  ASSERT_TRUE(read.outcome.ground_truth);
  EXPECT_DOUBLE_EQ(read.outcome.ground_truth->errors.rpe.rmse, 0.0625);
  EXPECT_TRUE(std::isnan(read.outcome.ground_truth->errors.landmark_rmse_aligned));
  EXPECT_DOUBLE_EQ(read.outcome.ground_truth->nees.mean, 2.9);
  ASSERT_TRUE(read.outcome.ground_truth->alignment);
  EXPECT_NEAR(read.outcome.ground_truth->alignment->yaw(), 0.25, 1e-12);
  EXPECT_EQ(read.outcome.ground_truth->alignment->source, "landmarks");
  EXPECT_EQ(read.outcome.given, o.given);
  // The outcome read back writes the same text (the alignment's yaw to the last bit aside).
  nlohmann::json again = summaryJson(read.outcome), first = summaryJson(o);
  EXPECT_NEAR(again["ground_truth"]["map_alignment"]["yaw"].get<double>(), 0.25, 1e-12);
  again["ground_truth"]["map_alignment"]["yaw"] = first["ground_truth"]["map_alignment"]["yaw"];
  EXPECT_EQ(again.dump(), first.dump());
}

TEST(SummaryJson, ASummaryWithoutARunHasNoRunBlocks) {
  RunOutcome o;
  o.fail(RunStatus::Interrupted, ErrorKind::Stopped, "interrupted by SIGINT before the first step");
  o.given = {{"started", false}};
  const nlohmann::json j = summaryJson(o);
  EXPECT_EQ(j, nlohmann::json({{"status", "interrupted"},
                               {"error", "interrupted by SIGINT before the first step"},
                               {"started", false}}));
  const SummaryFile read = summaryFromJson(j, "summary.json");
  EXPECT_EQ(read.outcome.status, RunStatus::Interrupted);
  EXPECT_FALSE(read.outcome.run);
  EXPECT_FALSE(read.outcome.ground_truth);
}

TEST(SummaryJson, AStatusThatIsNoneOfTheWordsIsNotOk) {
  for (const char* text : {R"({"status": "done"})", R"({"status": 1})", "{}"}) {
    const SummaryFile read = summaryFromJson(nlohmann::json::parse(text), "summary.json");
    EXPECT_EQ(read.outcome.status, RunStatus::Failed) << text;
    EXPECT_EQ(exitCode(read.outcome), 1) << text;
  }
  EXPECT_EQ(summaryFromJson(nlohmann::json::parse(R"({"status": "done"})"), "s").status_text,
            "done");
}

TEST(SummaryJson, GivenKeysWinOverTheOutcomes) {
  RunOutcome o;
  o.fail(RunStatus::Failed, ErrorKind::Input, "the comparison did not start: x");
  o.given = {{"status", "failed"}, {"error", "x"}};
  EXPECT_EQ(summaryJson(o)["error"], "x");
}

void expectRefused(const std::string& text, const std::string& line) {
  const auto path = (scratch("bad") / "summary.json").string();
  std::ofstream(path) << text;
  try {
    readSummary(path);
    ADD_FAILURE() << "read: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + line);
  }
}

TEST(SummaryJson, ReaderRefusesWhatIsNotASummary) {
  expectRefused("[1, 2]", ": not a budget-slam summary (not an object)");
  expectRefused(R"({"ground_truth": {"map_alignment": 3}})",
                ": ground_truth.map_alignment is not an object");
  expectRefused(R"({"ground_truth": {"map_alignment": {"x": null, "y": 0, "yaw": 0}}})",
                ": ground_truth.map_alignment.x is not a finite number");
  expectRefused(
      R"({"ground_truth": {"map_alignment": {"x": 0, "y": 0, "yaw": 0, "source": "guess"}}})",
      ": ground_truth.map_alignment.source 'guess' is none of landmarks, trajectory, start_pose");
  std::string deep(40, '[');
  deep += std::string(40, ']');
  expectRefused(deep, ": nested deeper than 16 levels, not a budget-slam summary");
}

TEST(SummaryJson, KeysListTheWritersTopLevel) {
  const auto& keys = summaryKeys();
  const RunOutcome o = fullOutcome();
  const nlohmann::json j = summaryJson(o);
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (o.given.contains(it.key())) continue;
    EXPECT_NE(std::find(keys.begin(), keys.end(), it.key()), keys.end()) << it.key();
  }
}

}  // namespace
}  // namespace budget_slam::runs
