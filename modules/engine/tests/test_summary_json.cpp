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
  o.given.rawlog = "a.rawlog", o.given.config = "c.ini", o.given.started = true;
  o.given.session_state = SessionStateWritten{false, "disk full"};
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
  EXPECT_EQ(read.outcome.given.rawlog, o.given.rawlog);
  EXPECT_EQ(read.outcome.given.config, o.given.config);
  EXPECT_EQ(read.outcome.given.started, o.given.started);
  ASSERT_TRUE(read.outcome.given.session_state);
  EXPECT_FALSE(read.outcome.given.session_state->written);
  EXPECT_EQ(read.outcome.given.session_state->why, "disk full");
  EXPECT_FALSE(read.outcome.given.map);
  // The outcome read back writes the same text (the alignment's yaw to the last bit aside).
  nlohmann::json again = summaryJson(read.outcome), first = summaryJson(o);
  EXPECT_NEAR(again["ground_truth"]["map_alignment"]["yaw"].get<double>(), 0.25, 1e-12);
  again["ground_truth"]["map_alignment"]["yaw"] = first["ground_truth"]["map_alignment"]["yaw"];
  EXPECT_EQ(again.dump(), first.dump());
}

TEST(SummaryJson, ASummaryWithoutARunHasNoRunBlocks) {
  RunOutcome o;
  o.fail(RunStatus::Interrupted, ErrorKind::Stopped, "interrupted by SIGINT before the first step");
  o.given.started = false;
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

TEST(SummaryJson, EachGivenFieldIsOneKeyWrittenWhenSet) {
  RunOutcome o;
  EXPECT_EQ(summaryJson(o), nlohmann::json({{"status", "ok"}, {"error", ""}}));
  RunGiven& g = o.given;
  g.command = "localize", g.rawlog = "r.rawlog", g.sidecar_ini = "", g.config = "c.ini";
  g.started = true, g.earlier_run_moved_to = "out.1", g.resumed_from = "RUN";
  ResumeWakeUp w;
  w.status = "found", w.by_ids = true, w.steps = 3, w.landmarks = 4, w.inliers = 9;
  w.time_ms = 1.5, w.pose = {{1.0, -2.0, 90.0}};
  g.wake_up = w;
  g.session_state = SessionStateWritten{true, ""};
  g.run = "mi/seed2";
  metrics::ReferenceMetrics m;
  m.poses = 10, m.landmarks = 5, m.ate = 0.25, m.eig_rows = 0;  // the rest NaN: null
  g.reference_metrics = m;
  g.runs = 3, g.seeds = std::vector<std::uint64_t>{1, 2}, g.steps = 60, g.threads = 2;
  g.map = "MAP", g.map_status = "ok";
  const nlohmann::json null;
  EXPECT_EQ(summaryJson(o),
            nlohmann::json::parse(R"({"status": "ok", "error": "", "command": "localize",
              "rawlog": "r.rawlog", "sidecar_ini": "", "config": "c.ini", "started": true,
              "earlier_run_moved_to": "out.1", "resumed_from": "RUN",
              "wake_up": {"status": "found", "reason": "", "by_ids": true, "steps": 3,
                          "landmarks": 4, "inliers": 9, "time_ms": 1.5,
                          "pose": [1.0, -2.0, 90.0]},
              "session_state": {"written": true}, "run": "mi/seed2",
              "reference_metrics": {"poses": 10, "landmarks": 5, "ate_m": 0.25, "ale_m": null,
                                    "are_deg": null, "ud_pct": null, "ud_std_factor": null,
                                    "eig_min": null, "eig_max": null, "eig_rows": 0},
              "runs": 3, "seeds": [1, 2], "steps": 60, "threads": 2, "map": "MAP",
              "map_status": "ok"})"));
  // Read back: the scalar keys and the session state; the nested wake_up and reference_metrics
  // stay in the document.
  const RunGiven read = summaryFromJson(summaryJson(o), "summary.json").outcome.given;
  EXPECT_EQ(read.command, g.command);
  EXPECT_EQ(read.sidecar_ini, g.sidecar_ini);
  EXPECT_EQ(read.earlier_run_moved_to, g.earlier_run_moved_to);
  EXPECT_EQ(read.seeds, g.seeds);
  EXPECT_EQ(read.threads, g.threads);
  EXPECT_EQ(read.map_status, g.map_status);
  EXPECT_FALSE(read.wake_up);
  EXPECT_FALSE(read.reference_metrics);
  // A later given replaces only what it sets.
  RunGiven later;
  later.started = false, later.map = "OTHER";
  g.update(later);
  EXPECT_EQ(g.started, std::optional<bool>(false));
  EXPECT_EQ(g.map, std::optional<std::string>("OTHER"));
  EXPECT_EQ(g.rawlog, std::optional<std::string>("r.rawlog"));
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
  RunOutcome given_only;
  given_only.given = o.given;
  const nlohmann::json given = summaryJson(given_only);
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (given.contains(it.key()) && it.key() != "status" && it.key() != "error") continue;
    EXPECT_NE(std::find(keys.begin(), keys.end(), it.key()), keys.end()) << it.key();
  }
}

}  // namespace
}  // namespace budget_slam::runs
