// An outcome from a small run through the run layer's API (runs::runSlam), and its summary.json;
// the run driver's observers, each block against the files the run wrote.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <unordered_set>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/graph/GraphBackend.h"
#include "budget_slam/metrics/NeesAccumulator.h"
#include "budget_slam/runs/Runs.h"

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
  spec.given.rawlog = spec.rawlog;
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

/// A CSV file of plain cells (no quotes), its cells found by column name.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  static std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    std::istringstream in(line);
    for (std::string c; std::getline(in, c, ',');) out.push_back(c);
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
  }
  explicit Csv(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    if (std::getline(in, line)) header = cells(line);
    while (std::getline(in, line)) rows.push_back(cells(line));
  }
  const std::string& at(std::size_t row, const std::string& name) const {
    const auto c = std::find(header.begin(), header.end(), name);
    if (c == header.end()) throw std::out_of_range("no column " + name);
    return rows.at(row).at(static_cast<std::size_t>(c - header.begin()));
  }
  double num(std::size_t row, const std::string& name) const { return std::stod(at(row, name)); }
};

// Each observer of the step loop fills its block of the outcome and keeps its accessor: the
// numbers equal what steps.csv and evictions.csv hold, the relocalization coverage equals one
// computed afresh from the rawlog's landmark IDs against the final map, the NEES equals one
// accumulated from the online poses kept, and the scenes are written every N steps.
TEST(RunDriverObservers, EachObserverFillsItsBlockAsTheFilesSay) {
  Cancellation::clear();
  const std::string rawlog = kRoot + "/rawlogs/kf-slam_demo.rawlog";
  constexpr std::size_t kSteps = 60, kSceneEvery = 9;
  for (const std::string backend : {"ekf", "graph"}) {
    SCOPED_TRACE(backend);
    const auto dir =
        fs::temp_directory_path() / "budget_slam_tests" / "runs" / ("observers_" + backend);
    fs::remove_all(dir);
    fs::create_directories(dir.parent_path());
    mrpt::config::CConfigFileMemory ini;
    DriverSpec spec;
    spec.backend = backend;
    spec.budget.reducer = "random";
    spec.budget.max_landmarks = 6;
    spec.save_3d_scene = false;
    spec.scene_every_steps = kSceneEvery;
    auto truth = std::make_shared<dataset::GroundTruth>(dataset::loadGroundTruth(rawlog));
    ASSERT_FALSE(truth->path.empty());
    RunDriver driver(ini, backends(), spec, report::OutputFolder(dir.string(), false), truth);

    // The step loop as runs::runSlam drives it, and the landmark IDs each step's readings carry.
    dataset::RawlogReader reader(rawlog);
    std::vector<metrics::ObservedAtStep> observed;
    for (std::size_t k = 0; k < kSteps; ++k) {
      auto step = reader.next();
      ASSERT_TRUE(step);
      step->index = static_cast<StepIndex>(k);
      metrics::ObservedAtStep o;
      o.step = step->index;
      if (step->scan)
        for (const auto& r : step->scan->readings) o.ids.push_back(r.id);
      observed.push_back(std::move(o));
      driver.process(*step);
    }
    const std::size_t steps_in_rawlog = reader.stepsRead();
    const RunOutcome out = driver.finish(RunStatus::Ok, ErrorKind::None, "", steps_in_rawlog);
    ASSERT_TRUE(out.ok()) << out.error;
    ASSERT_TRUE(out.run && out.ground_truth);
    const RunCounts& counts = out.run->counts;

    const Csv steps(dir / "steps.csv");
    ASSERT_EQ(steps.rows.size(), kSteps);
    EXPECT_EQ(counts.steps, kSteps);
    EXPECT_EQ(driver.stepsDone(), kSteps);

    // The map's counts: the peak and the sum of the landmarks added, and the per-step history.
    std::size_t peak = 0, added = 0, dropped_column = 0, refused_column = 0;
    double total_ms = 0, max_ms = 0;
    ASSERT_EQ(driver.landmarkCounts().size(), kSteps);
    ASSERT_EQ(driver.onlinePoses().size(), kSteps);
    for (std::size_t r = 0; r < kSteps; ++r) {
      const auto n = static_cast<std::size_t>(steps.num(r, "n_landmarks"));
      peak = std::max(peak, n);
      added += static_cast<std::size_t>(steps.num(r, "n_new"));
      dropped_column += static_cast<std::size_t>(steps.num(r, "n_dropped"));
      refused_column += static_cast<std::size_t>(steps.num(r, "n_refused"));
      total_ms += steps.num(r, "step_ms");
      max_ms = std::max(max_ms, steps.num(r, "step_ms"));
      EXPECT_EQ(driver.landmarkCounts()[r], n);
      const auto& pose = driver.onlinePoses()[r];
      EXPECT_EQ(pose.step, static_cast<StepIndex>(steps.num(r, "step")));
      EXPECT_NEAR(pose.estimate.mean.x, steps.num(r, "x"), 1e-12);
      EXPECT_NEAR(pose.estimate.mean.y, steps.num(r, "y"), 1e-12);
      EXPECT_NEAR(pose.estimate.mean.phi, steps.num(r, "yaw"), 1e-12);
    }
    EXPECT_EQ(counts.landmarks_peak, peak);
    EXPECT_EQ(counts.landmarks_added, added);
    EXPECT_LE(peak, 6u);

    // The eviction log: evictions.csv's rows, refusals apart, and steps.csv's columns (the
    // random reducer makes no end-of-run drops).
    const Csv evictions(dir / "evictions.csv");
    std::size_t refused_rows = 0;
    for (std::size_t r = 0; r < evictions.rows.size(); ++r)
      refused_rows += evictions.at(r, "reason") == "refused";
    EXPECT_GT(counts.evictions, 0u);
    EXPECT_EQ(counts.refused, refused_rows);
    EXPECT_EQ(counts.evictions, evictions.rows.size() - refused_rows);
    EXPECT_EQ(counts.evictions, dropped_column);
    EXPECT_EQ(counts.refused, refused_column);
    EXPECT_EQ(driver.evictions(), counts.evictions);
    EXPECT_EQ(driver.refused(), counts.refused);
    EXPECT_EQ(counts.landmarks_added, counts.landmarks_final + counts.evictions);

    // The probes: the timings are steps.csv's step times summed (printed to the last digit).
    const RunTimings& t = out.run->timings;
    EXPECT_GT(t.steps_s, 0.0);
    EXPECT_NEAR(t.steps_s, total_ms / 1e3, 1e-9 * std::max(1.0, t.steps_s));
    EXPECT_NEAR(t.step_ms_max, max_ms, 1e-9 * std::max(1.0, max_ms));
    EXPECT_NEAR(t.step_ms_mean, total_ms / kSteps, 1e-9 * std::max(1.0, t.step_ms_mean));
    EXPECT_EQ(driver.totalStepSeconds(), t.steps_s);
    EXPECT_GT(t.peak_rss_bytes, 0u);

    // Relocalization coverage: the tracker's, followed step by step, equals the final map's
    // coverage of the rawlog's IDs computed in one go, and the last row's coverage so far.
    std::unordered_set<LandmarkId> in_map;
    for (const auto& l : driver.backend().landmarks()) in_map.insert(l.id);
    const metrics::RelocalizationCoverage expected = metrics::coverageOf(
        observed, [&](LandmarkId id) { return in_map.count(id) > 0; }, 2);
    const auto& reloc = out.run->relocalization;
    EXPECT_EQ(reloc.source, "landmark_ids");
    EXPECT_EQ(reloc.coverage.steps, kSteps);
    EXPECT_EQ(reloc.coverage.steps_covered, expected.steps_covered);
    EXPECT_GT(expected.steps_covered, 0u);
    EXPECT_DOUBLE_EQ(reloc.coverage.coverage_pct, expected.coverage_pct);
    EXPECT_DOUBLE_EQ(reloc.coverage.mean_landmarks, expected.mean_landmarks);
    EXPECT_NEAR(reloc.coverage.coverage_pct, steps.num(kSteps - 1, "reloc_coverage_so_far_pct"),
                1e-9);
    EXPECT_EQ(driver.relocalization().steps().size(), kSteps);

    // The NEES, accumulated online, equals the one of the online poses kept.
    metrics::NeesAccumulator nees(*truth);
    for (const auto& p : driver.onlinePoses()) nees.add(p.step, p.estimate);
    const metrics::NeesMean want = nees.result(steps_in_rawlog);
    EXPECT_GT(want.samples, kSteps / 2);
    EXPECT_EQ(out.ground_truth->nees.samples, want.samples);
    EXPECT_DOUBLE_EQ(out.ground_truth->nees.mean, want.mean);
    EXPECT_LT(out.ground_truth->nees.mean, 10.0);  // a consistent filter: 3 on average

    // The scenes: one every kSceneEvery steps, named by the step.
    std::set<std::string> scenes, want_scenes;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().filename().string().rfind("kf_state_", 0) == 0)
        scenes.insert(e.path().filename().string());
    for (std::size_t k = 0; k < kSteps; k += kSceneEvery) {
      char name[48];
      std::snprintf(name, sizeof name, "kf_state_%05zu.3Dscene", k);
      want_scenes.insert(name);
    }
    EXPECT_EQ(scenes, want_scenes);
    EXPECT_FALSE(fs::exists(dir / "map.3Dscene"));
  }
}

}  // namespace
}  // namespace budget_slam::runs
