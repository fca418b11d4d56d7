// How runs report what goes wrong (docs/OUTPUTS.md): a failing shadow reducer is logged and the
// run goes on; a filter whose covariance lost positive definiteness is a one-line error naming
// the step; compare names every failed run; a failed run keeps its inputs in summary.json and
// no non-finite landmark in landmarks.csv; a value that does not apply is an empty CSV field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "AppTestUtil.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

/// Sensor noise far below what the demo's readings carry: MRPT's EKF then loses the positive
/// definiteness of its covariance (at step 1 with 1e-6; from step 161 on with 3e-4, which the
/// filter itself survives).
std::vector<std::string> tinyNoise(const std::string& sigma) {
  return {"--set", "RangeBearingKFSLAM.std_sensor_range=" + sigma, "--set",
          "RangeBearingKFSLAM.std_sensor_yaw_deg=" + sigma};
}

std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

const std::string kLostDefiniteness =
    ": the ekf filter's covariance lost positive definiteness, so the mutual information of its "
    "landmarks is undefined";

}  // namespace

TEST(Failures, AFailingShadowReducerIsLoggedAndTheRunFinishes) {
  // random drops; the mi shadow fails at every decision after the covariance went bad.
  const auto run = [](const std::string& shadows, const fs::path& dir) {
    return runApp(
        plus({"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--quiet", "--reducer",
              "random", "--cap", "10", "--set", "LandmarkBudget.shadow_reducers=" + shadows},
             tinyNoise("3e-4")));
  };
  const auto dir = freshDir("shadow_fails");
  const auto r = run("mi,oldest", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto s = readJson(dir / "summary.json");
  EXPECT_EQ(s["status"], "ok");
  ASSERT_EQ(s["shadow_failures"].size(), 1u);
  const auto& f = s["shadow_failures"][0];
  EXPECT_EQ(f["shadow"], "mi");
  const std::size_t first = f["first_step"], last = f["last_step"], failures = f["failures"];
  EXPECT_GT(failures, 0u);
  EXPECT_EQ(f["first_error"], "step " + std::to_string(first) + kLostDefiniteness);
  EXPECT_TRUE(isOneLine(r.err, Said::Warning,
                        "shadow reducer 'mi' failed at " + std::to_string(failures) +
                            " drop decisions from step " + std::to_string(first) + " to " +
                            std::to_string(last) + " (first: step " + std::to_string(first) +
                            kLostDefiniteness + "); the active reducer's drops stand"));

  // evictions.csv: a failed shadow has no choice ("mi::") and its error, of that very step.
  std::size_t logged = 0;
  for (const auto& e : readCsv(dir / "evictions.csv")) {
    ASSERT_EQ(e.size(), 9u);
    if (e[8].empty()) {
      EXPECT_EQ(e[7].rfind("mi:", 0), 0u) << e[7];
      EXPECT_EQ(e[7].rfind("mi::", 0), std::string::npos) << e[7];
      continue;
    }
    ++logged;
    EXPECT_EQ(e[7].rfind("mi::;oldest:", 0), 0u) << e[7];
    EXPECT_EQ(e[8], "mi: step " + e[0] + kLostDefiniteness);
  }
  EXPECT_EQ(logged, failures);
  // Agreement counts only the decisions at which both answered.
  EXPECT_EQ(s["agreement"][0]["b"], "mi");
  EXPECT_EQ(s["agreement"][0]["total"], s["counts"]["evictions"].get<std::size_t>() - failures);

  // The active reducer's choices stand: the same map as without the failing shadow.
  const auto alone = freshDir("shadow_fails_without");
  ASSERT_EQ(run("oldest", alone).exit_code, 0);
  EXPECT_EQ(slurp(alone / "landmarks.csv"), slurp(dir / "landmarks.csv"));
}

TEST(Failures, LostDefinitenessNamesTheStep) {
  const auto dir = freshDir("lost_definiteness");
  const auto r = runApp(plus({"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--quiet",
                              "--reducer", "mi", "--cap", "10"},
                             tinyNoise("1e-6")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(isErrorLine(r.err, "step 1" + kLostDefiniteness));
  const auto s = readJson(dir / "summary.json");
  EXPECT_EQ(s["status"], "failed");
  EXPECT_EQ(s["error"], "step 1" + kLostDefiniteness);
  // A failed run says what it was given, as an ok one does.
  EXPECT_EQ(s["config"], kMrptIni);
  EXPECT_EQ(s["rawlog"], kDemo);
  EXPECT_EQ(s["sidecar_ini"], kRoot + "/rawlogs/kf-slam_demo.ini");
}

TEST(Failures, ADivergedRunWritesNoNonFiniteLandmark) {
  // random with tiny noise: the EKF diverges (its landmarks turn NaN) after 4 steps.
  // MRPT's own update (EkfSLAM.update = mrpt): where a filter this ill-conditioned diverges
  // depends on the order of its arithmetic, and this test is about the divergence.
  const auto dir = freshDir("diverged_landmarks");
  const auto r = runApp(plus({"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--quiet",
                              "--reducer", "random", "--cap", "10", "--set", "EkfSLAM.update=mrpt"},
                             tinyNoise("1e-6")));
  EXPECT_EQ(r.exit_code, 1);
  const auto s = readJson(dir / "summary.json");
  EXPECT_EQ(s["status"], "failed");
  EXPECT_EQ(s["rawlog"], kDemo);
  EXPECT_EQ(s["config"], kMrptIni);
  EXPECT_TRUE(s.contains("sidecar_ini"));
  const auto rows = readCsv(dir / "landmarks.csv");
  EXPECT_EQ(rows.size(), s["counts"]["landmarks_final"].get<std::size_t>());
  EXPECT_GT(s["counts"]["landmarks_not_finite"].get<std::size_t>(), 0u);
  for (const auto& row : rows)
    for (std::size_t c = 1; c < 9; ++c)
      EXPECT_TRUE(std::isfinite(std::stod(row.at(c)))) << row.at(0) << " column " << c;
}

TEST(Failures, CompareNamesEveryFailedRun) {
  const auto dir = freshDir("compare_failures");
  const auto r = runApp(plus({"compare", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--quiet",
                              "--reducers", "mi,coverage-mi", "--cap", "10"},
                             tinyNoise("1e-8")));
  EXPECT_EQ(r.exit_code, 1);
  const auto err = lines(r.err);
  ASSERT_EQ(err.size(), 3u) << r.err;
  EXPECT_EQ(err[0].rfind("budget-slam: error: run 'reference': step ", 0), 0u) << err[0];
  EXPECT_EQ(err[1], "budget-slam: error: run 'mi': step 1" + kLostDefiniteness);
  EXPECT_EQ(err[2].rfind("budget-slam: error: run 'coverage-mi': step ", 0), 0u) << err[2];
  for (const std::string run : {"reference", "mi", "coverage-mi"}) {
    const auto s = readJson(dir / run / "summary.json");
    EXPECT_EQ(s["status"], "failed") << run;
    EXPECT_EQ(s["config"], kMrptIni) << run;
    EXPECT_EQ(s["rawlog"], kDemo) << run;
    EXPECT_TRUE(s.contains("sidecar_ini")) << run;
  }
}

TEST(Failures, MetricsThatDoNotApplyAreEmptyCsvFields) {
  // The demo without its ground-truth files: the ground-truth columns do not apply.
  const auto dir = freshDir("compare_no_truth");
  const auto rawlog = dir.parent_path() / "no_truth" / "demo.rawlog";
  fs::create_directories(rawlog.parent_path());
  fs::copy_file(kDemo, rawlog, fs::copy_options::overwrite_existing);
  const auto r = runApp({"compare", "-c", kMrptIni, "-i", rawlog.string(), "-o", dir.string(),
                         "--quiet", "--reducers", "mi,oldest", "--cap", "30"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = slurp(dir / "comparison.csv");
  EXPECT_EQ(csv.find("nan"), std::string::npos) << csv;
  const auto header = csvCells(lines(csv).at(0));
  const auto rows = readCsv(dir / "comparison.csv");
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), header.size());
    for (std::size_t c = 0; c < header.size(); ++c) {
      const bool truth = header[c].rfind("gt_", 0) == 0 || header[c] == "nees_mean";
      // Without compare --relocalize the other traversals' columns do not apply either.
      const bool traversal = header[c].rfind("reloc_", 0) == 0 &&
                             header[c] != "reloc_coverage_pct" &&
                             header[c] != "reloc_mean_landmarks";
      // The reference has no cap; everything else applies.
      const bool applies = !truth && !traversal && !(row[0] == "reference" && header[c] == "cap");
      EXPECT_EQ(row[c].empty(), !applies) << row[0] << " " << header[c];
    }
  }
}

TEST(Failures, ARunThatReadNoStepWritesNoResultFile) {
  // A missing rawlog left an empty map.png (axes -1..1, a legend), an empty trajectory.tum and
  // map.3Dscene, which look like results (issue 35). Now only what says why: summary.json, and
  // config_used.ini (what the run was asked).
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"missing", (fs::path(freshDir("no_such_rawlog_in")) / "nothing.rawlog").string()},
      {"not a rawlog", kMrptIni}};
  for (const auto& [what, rawlog] : cases) {
    SCOPED_TRACE(what);
    const auto dir = freshDir("no_step_read");
    const auto r = runApp({"run", "-c", kMrptIni, "-i", rawlog, "-o", dir.string(), "--quiet"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    std::set<std::string> files;
    for (const auto& e : fs::directory_iterator(dir)) files.insert(e.path().filename().string());
    EXPECT_EQ(files, (std::set<std::string>{"config_used.ini", "summary.json"}));
    const auto s = readJson(dir / "summary.json");
    EXPECT_EQ(s["status"], "failed");
    EXPECT_NE(s["error"].get<std::string>().find(rawlog), std::string::npos) << s["error"];
    EXPECT_EQ(s["counts"]["steps"], 0);
  }
}
