// runs::localize through the run layer's API: a typed specification in (no command line), a typed
// report out, and the summary.json the one writer makes of it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/engine/BuiltinBackends.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/runs/Localize.h"
#include "budget_slam/runs/RequestChecks.h"
#include "budget_slam/runs/RunConfig.h"
#include "budget_slam/runs/RunSpecs.h"
#include "budget_slam/runs/Runs.h"

namespace budget_slam::runs {
namespace {

namespace fs = std::filesystem;

const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;
const std::string kConfig = kRoot + "/config.ini";

std::string freshDir(const std::string& name) {
  const auto dir = fs::temp_directory_path() / "budget_slam_tests" / "localize_run" / name;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  return dir.string();
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// config.ini's run of `rawlog` into a fresh folder, through runs::runSlam: the map to localize in.
std::string mapOf(const std::string& rawlog, const std::string& name) {
  mrpt::config::CConfigFileMemory params;
  loadIniText(params, slurp(kConfig), kConfig);
  RunRequest request;
  request.common.rawlog = kRoot + "/rawlogs/" + rawlog;
  request.common.outdir = freshDir(name);
  const RunConfig rc = loadRunConfig(params, request.common, configFlags(request), kConfig);
  RunSpec spec;
  spec.ini = rc.ini;
  spec.backends = &builtinBackends();
  spec.driver = driverSpec(rc);
  spec.driver.save_3d_scene = false;
  spec.rawlog = rc.rawlog;
  spec.outdir = rc.outdir;
  const RunReport r = runSlam(spec, {});
  EXPECT_TRUE(r.outcome.ok()) << r.line;
  return r.folder;
}

/// localize's specification as `budget-slam localize -c config.ini --map MAP -i RAWLOG -o OUT`.
struct LocalizeSpec {
  LocalizeRequest request;
  RequestContext context;
};
LocalizeSpec specOf(const std::string& map, const std::string& rawlog, const std::string& out) {
  LocalizeSpec spec;
  spec.request.common.config = kConfig;
  spec.request.map_dir = map;
  spec.request.common.rawlog = kRoot + "/rawlogs/" + rawlog;
  spec.request.common.outdir = freshDir(out);
  spec.context.config_text = slurp(kConfig);
  spec.context.config_label = kConfig;
  return spec;
}

double numberOr(const nlohmann::json& j, double nan) { return j.is_null() ? nan : j.get<double>(); }

TEST(LocalizeRun, RoomsRevisitInTheRoomsMapIsTypedAsItsSummary) {
  Cancellation::clear();
  const std::string map = mapOf("rooms.rawlog", "rooms_map");
  const LocalizeSpec spec = specOf(map, "rooms_revisit.rawlog", "rooms_revisit");
  std::size_t steps_heard = 0;
  RunHooks hooks;
  hooks.on_step = [&](StepIndex) { ++steps_heard; };
  std::vector<std::string> warned;
  hooks.warning = [&](const std::string& w) { warned.push_back(w); };
  const LocalizeReport r = localize(spec.request, spec.context, hooks);
  ASSERT_TRUE(r.outcome.ok()) << r.line;
  EXPECT_EQ(r.line, "");
  EXPECT_EQ(exitCode(r.outcome), 0);
  EXPECT_EQ(r.folder, spec.request.common.outdir);
  EXPECT_EQ(warned, r.warnings);
  EXPECT_FALSE(r.outcome.wake_up);
  ASSERT_TRUE(r.outcome.localization);
  const LocalizationOutcome& l = *r.outcome.localization;
  EXPECT_EQ(l.start.source, "ground truth");
  EXPECT_EQ(l.counts.steps, steps_heard);
  EXPECT_EQ(l.counts.map_landmarks, r.map_landmarks);
  const auto& m = l.localization;
  EXPECT_EQ(m.error_against, "ground_truth");
  EXPECT_FALSE(m.diverged_at_step);
  // The revisit of the same rooms tracks: errors in centimetres against the ground truth.
  EXPECT_LT(m.score.rmse_m, 0.2);
  EXPECT_EQ(m.score.lost, 0u);
  EXPECT_EQ(m.score.steps, l.counts.steps);

  // summary.json, as written, holds the same numbers as the typed blocks (and is exactly what
  // the one writer makes of the outcome).
  const nlohmann::json j = nlohmann::json::parse(slurp(r.folder + "/summary.json"));
  EXPECT_EQ(j, summaryJson(r.outcome));
  const double nan = std::nan("");
  const auto& js = j["localization"];
  EXPECT_EQ(j["status"], "ok");
  EXPECT_EQ(j["command"], "localize");
  EXPECT_EQ(j["counts"]["steps"].get<std::size_t>(), l.counts.steps);
  EXPECT_EQ(j["counts"]["map_landmarks"].get<std::size_t>(), l.counts.map_landmarks);
  EXPECT_EQ(j["start_pose"]["source"], l.start.source);
  EXPECT_EQ(j["start_pose"]["x"].get<double>(), l.start.pose.mean.x);
  EXPECT_EQ(j["start_pose"]["yaw"].get<double>(), l.start.pose.mean.phi);
  EXPECT_EQ(js["rmse_m"].get<double>(), m.score.rmse_m);
  EXPECT_EQ(js["max_m"].get<double>(), m.score.max_m);
  EXPECT_EQ(js["lost_pct"].get<double>(), m.score.lost_pct);
  EXPECT_EQ(js["coverage_pct"].get<double>(), m.score.coverage_pct);
  EXPECT_EQ(js["nees_mean"].get<double>(), m.score.nees_mean);
  EXPECT_EQ(numberOr(js["success_per_place_pct"], nan), m.score.success_pct);
  EXPECT_EQ(js["steps_scored"].get<std::size_t>(), m.score.scored);
  EXPECT_EQ(js["readings_used"].get<std::size_t>(), m.readings_used);
  EXPECT_TRUE(js["diverged_at_step"].is_null());
  EXPECT_EQ(js["mapped_area"], "cells of 0.750000 m within 3.000000 m of the mapping path");
  EXPECT_EQ(j["timings"]["steps_s"].get<double>(), l.timings.steps_s);
  EXPECT_EQ(j["map"], map);
  EXPECT_EQ(j["started"], true);
  // steps.csv: a row a step localized.
  std::ifstream csv(r.folder + "/steps.csv");
  std::size_t lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 1 + l.counts.steps);
}

TEST(LocalizeRun, AWakeUpOnAMapOfAnotherWorldIsNotFound) {
  Cancellation::clear();
  const std::string map = mapOf("paper_synthetic.rawlog", "paper_map");
  LocalizeSpec spec = specOf(map, "rooms_revisit.rawlog", "not_found");
  spec.request.wake_up = true;
  const LocalizeReport r = localize(spec.request, spec.context, {});
  EXPECT_EQ(r.outcome.status, RunStatus::NotFound);
  EXPECT_EQ(r.outcome.kind, ErrorKind::None);
  EXPECT_EQ(exitCode(r.outcome), 3);
  EXPECT_EQ(r.line,
            "wake-up: the robot was not found on the map in 10 steps (not_found, "
            "too_few_landmarks: 0 landmark(s), 2 needed); no pose is guessed");
  EXPECT_FALSE(r.outcome.localization);  // no filter ran
  ASSERT_TRUE(r.outcome.wake_up);
  const LocalizationWakeUp& w = *r.outcome.wake_up;
  EXPECT_FALSE(w.found());
  EXPECT_TRUE(w.asked);
  EXPECT_EQ(w.steps_used, 10u);
  EXPECT_EQ(w.max_steps, 10u);
  EXPECT_EQ(w.result.status, wakeup::WakeUpStatus::NotFound);
  EXPECT_FALSE(w.error);
  const nlohmann::json j = nlohmann::json::parse(slurp(r.folder + "/summary.json"));
  EXPECT_EQ(j, summaryJson(r.outcome));
  EXPECT_EQ(j["status"], "not_found");
  EXPECT_EQ(j["started"], false);
  EXPECT_EQ(j["wake_up"]["requested"], "--wake-up");
  EXPECT_EQ(j["wake_up"]["found"], false);
  EXPECT_TRUE(j["wake_up"]["pose"].is_null());
  EXPECT_EQ(j["wake_up"]["why_not_found"], w.why_not_found);
  EXPECT_EQ(j["error"], r.outcome.error);
}

TEST(LocalizeRun, AWakeUpOnTheSameRoomsFindsTheRobotAndSaysHowFar) {
  Cancellation::clear();
  const std::string map = mapOf("rooms.rawlog", "rooms_map_wake");
  LocalizeSpec spec = specOf(map, "rooms_revisit.rawlog", "woken");
  spec.request.wake_up = true;
  const LocalizeReport r = localize(spec.request, spec.context, {});
  ASSERT_TRUE(r.outcome.ok()) << r.line;
  ASSERT_TRUE(r.outcome.wake_up);
  const LocalizationWakeUp& w = *r.outcome.wake_up;
  ASSERT_TRUE(w.found());
  ASSERT_TRUE(w.error);
  EXPECT_EQ(w.error->against, "ground_truth");
  EXPECT_LT(w.error->xy_m, 0.25);
  ASSERT_TRUE(r.outcome.localization);
  EXPECT_EQ(r.outcome.localization->start.source, "wake-up");
  // The steps that woke the robot up are not localized.
  EXPECT_EQ(r.outcome.localization->counts.steps + w.steps_used, 318u);
  const nlohmann::json j = nlohmann::json::parse(slurp(r.folder + "/summary.json"));
  EXPECT_EQ(j["wake_up"]["error"]["xy_m"].get<double>(), w.error->xy_m);
  EXPECT_EQ(j["wake_up"]["steps_used"].get<std::size_t>(), w.steps_used);
  EXPECT_EQ(j["wake_up"]["pose"]["x"].get<double>(), w.result.pose.mean.x);
}

TEST(LocalizeRun, AMissingMapFolderIsAFailedInputOutcomeInOneLine) {
  Cancellation::clear();
  const std::string missing = freshDir("no_such_map");
  const LocalizeSpec spec = specOf(missing, "kf-slam_demo.rawlog", "bad_map");
  const LocalizeReport r = localize(spec.request, spec.context, {});
  EXPECT_EQ(r.outcome.status, RunStatus::Failed);
  EXPECT_EQ(r.outcome.kind, ErrorKind::Input);
  EXPECT_EQ(exitCode(r.outcome), 1);
  EXPECT_EQ(r.line, "map folder '" + missing + "': no such folder");
  EXPECT_EQ(r.outcome.error, r.line);
  EXPECT_FALSE(r.outcome.localization);
  // The output folder says why, and that nothing started.
  const nlohmann::json j = nlohmann::json::parse(slurp(r.folder + "/summary.json"));
  EXPECT_EQ(j["status"], "failed");
  EXPECT_EQ(j["error"], r.line);
  EXPECT_EQ(j["started"], false);
  EXPECT_EQ(j["command"], "localize");
}

TEST(LocalizeRun, TheRequestChecksAreTheCommandLines) {
  LocalizeRequest r;
  r.start_pose = "1,2";
  try {
    checkRequest(r);
    ADD_FAILURE() << "a start pose of two numbers passed";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "--start-pose '1,2': expected x,y,yaw (metres, metres, degrees)");
  }
  r.start_pose = "1,2,90";
  const auto pose = parseStartPose(*r.start_pose);
  EXPECT_EQ(pose.x, 1.0);
  EXPECT_DOUBLE_EQ(pose.phi, M_PI / 2);
  r.wake_up = true;
  try {
    checkRequest(r);
    ADD_FAILURE() << "a start pose with wake_up passed";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "--wake-up: not with --start-pose (a start pose is not looked for)");
  }
}

}  // namespace
}  // namespace budget_slam::runs
