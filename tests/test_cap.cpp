// The cap is a budget: after every step the map holds at most [LandmarkBudget] max_landmarks in
// every mode of every reducer; `none` means no cap and goes only with reducers that decide the
// map's size themselves (docs/ALGORITHMS.md "Common to every reducer").
#include <gtest/gtest.h>

#include "AppTestUtil.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

const std::string kConfig = kRoot + "/config.ini";
const std::string kMrclam = kRoot + "/rawlogs/mrclam7_robot1.rawlog";

/// steps.csv's largest n_landmarks and its row count.
std::pair<long, std::size_t> peakLandmarks(const fs::path& dir) {
  long peak = 0;
  const auto rows = readCsv(dir / "steps.csv");
  for (const auto& r : rows) peak = std::max(peak, std::stol(r.at(2)));
  return {peak, rows.size()};
}

}  // namespace

TEST(Cap, HeldAtEveryStepInIncrementalMode) {
  // The command that ran uncapped (up to 15 landmarks, "cap": null) while config_used.ini said 8.
  const auto dir = freshDir("cap_incremental");
  const auto r =
      runApp({"run", "-c", kConfig, "-i", kMrclam, "-o", dir.string(), "--quiet", "--reducer", "mi",
              "--set", "MutualInformationReducer.mode=incremental", "--cap", "8"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto [peak, steps] = peakLandmarks(dir);
  EXPECT_EQ(steps, 1663u);
  EXPECT_EQ(peak, 8);
  const auto s = readJson(dir / "summary.json");
  EXPECT_EQ(s["cap"], 8);
  EXPECT_EQ(s["counts"]["landmarks_peak"], 8);
  // Cap decisions only (config.ini's admission = compete refuses some newcomers at the cap).
  for (const auto& e : readCsv(dir / "evictions.csv"))
    EXPECT_TRUE(e.at(6) == "over_cap" || e.at(6) == "refused") << e.at(6);
  EXPECT_NE(slurp(dir / "config_used.ini").find("max_landmarks = 8"), std::string::npos);
}

TEST(Cap, ScheduledDropsFirstThenTheCap) {
  // With lambda 0.95 and psi 100 Alg. 5 drops landmarks itself every 100 steps; the cap still
  // holds in between and right after each minimization.
  const auto dir = freshDir("cap_incremental_scheduled");
  const auto r =
      runApp({"run", "-c", kConfig, "-i", kMrclam, "-o", dir.string(), "--quiet", "--reducer", "mi",
              "--cap", "8", "--set", "MutualInformationReducer.mode=incremental", "--set",
              "MutualInformationReducer.psi=100", "--set", "MutualInformationReducer.lambda=0.95"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(peakLandmarks(dir).first, 8);
  std::size_t scheduled = 0, capped = 0;
  std::string last_reason_of_step;
  long last_step = -1;
  for (const auto& e : readCsv(dir / "evictions.csv")) {
    const long step = std::stol(e.at(0));
    if (e.at(6) == "incremental") {
      ++scheduled;
      EXPECT_EQ((step + 1) % 100, 0) << step;
      // Within one step the scheduled drops come before any cap drop.
      if (step == last_step) EXPECT_EQ(last_reason_of_step, "incremental") << step;
    } else {
      ++capped;
      EXPECT_EQ(e.at(6), "over_cap") << step;
    }
    last_step = step;
    last_reason_of_step = e.at(6);
  }
  EXPECT_GT(scheduled, 0u);
  EXPECT_GT(capped, 0u);
  EXPECT_EQ(readJson(dir / "summary.json")["cap"], 8);
}

TEST(Cap, HeldInObjectiveModeBeforeAlgorithm3) {
  // Objective mode with a cap of 10: the cap-mode rule during the run, Alg. 3 after the last
  // step. With pose lag 0 every kept landmark is an Alg. 3 candidate, and at lambda 0.95 rho
  // falls all along the greedy sequence of these 10, so all of them go.
  const auto dir = freshDir("cap_objective");
  const auto r = runApp(
      {"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--quiet", "--reducer", "mi",
       "--cap", "10", "--set", "MutualInformationReducer.mode=objective", "--set",
       "MutualInformationReducer.lambda=0.95", "--set", "MutualInformationReducer.pose_lag=0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(peakLandmarks(dir).first, 10);
  std::size_t objective = 0;
  for (const auto& e : readCsv(dir / "evictions.csv")) {
    if (e.at(6) != "objective") continue;
    ++objective;
    EXPECT_EQ(e.at(0), "248");  // after the last step
  }
  EXPECT_GT(objective, 0u);
  const auto s = readJson(dir / "summary.json");
  EXPECT_EQ(s["cap"], 10);
  EXPECT_EQ(s["counts"]["landmarks_final"], 10 - static_cast<int>(objective));
}

TEST(Cap, NoneOnlyWhereTheReducerDecidesTheMapSize) {
  const std::string why =
      ": reducer 'oldest' drops landmarks only to keep the map under a cap, so it needs a number "
      "(no cap suits reducer none, and mi in objective or incremental mode)";
  // On the command line...
  const auto flag = freshDir("cap_none_oldest");
  auto r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", flag.string(), "--quiet", "--reducer",
                   "oldest", "--cap", "none"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(isErrorLine(r.err, "--cap none" + why));
  EXPECT_EQ(readJson(flag / "summary.json")["error"], "--cap none" + why);
  // ...and in the ini, named with its file.
  const auto ini = freshDir("cap_none_oldest_ini");
  r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", ini.string(), "--quiet", "--reducer",
              "oldest", "--set", "LandmarkBudget.max_landmarks=none"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(isErrorLine(r.err, kMrptIni + ": [LandmarkBudget] max_landmarks = none" + why));
  // compare checks every reducer it runs, not the ini's.
  const auto cmp = freshDir("cap_none_compare");
  r = runApp({"compare", "-c", kMrptIni, "-i", kDemo, "-o", cmp.string(), "--quiet", "--reducers",
              "mi,oldest", "--cap", "none", "--set", "MutualInformationReducer.mode=objective"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(isErrorLine(r.err, "--cap none" + why));

  // The unreduced run and mi's objective mode need no cap: summary.json says "cap": null.
  const auto reference = freshDir("cap_none_reference");
  r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", reference.string(), "--quiet", "--reducer",
              "none", "--cap", "none"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(readJson(reference / "summary.json")["cap"].is_null());
  EXPECT_EQ(peakLandmarks(reference).first, 70);
}

TEST(Cap, ANumberWithReducerNoneIsAnErrorNamingTheFlag) {
  // MRPT's kf-slam ini has no [LandmarkBudget]: its reducer is none, which keeps every landmark.
  // A --cap given with it was ignored (70 landmarks kept, "cap": null) while config_used.ini said
  // max_landmarks = 20 (issue 35): the user believed the run capped.
  const std::string why =
      "--cap 20: reducer none keeps every landmark, so a cap would do nothing; give --reducer NAME "
      "(budget-slam --help lists them), or leave --cap out for the unreduced run";
  const auto dir = freshDir("cap_with_none");
  auto r =
      runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--quiet", "--cap", "20"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(isErrorLine(r.err, why));
  EXPECT_EQ(readJson(dir / "summary.json")["error"], why);
  EXPECT_FALSE(fs::exists(dir / "steps.csv"));
  // Named explicitly, the same.
  const auto named = freshDir("cap_with_none_named");
  r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", named.string(), "--quiet", "--reducer",
              "none", "--cap", "20"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(isErrorLine(r.err, why));
  // With a reducer the same command caps the map (the README's second command).
  const auto capped = freshDir("cap_with_reducer");
  r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", capped.string(), "--quiet", "--reducer",
              "info-content", "--cap", "20"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(readJson(capped / "summary.json")["cap"], 20);
  EXPECT_EQ(peakLandmarks(capped).first, 20);
  // The cap an ini holds for the other reducers (config.ini's 50) does not stop an unreduced run.
  const auto unreduced = freshDir("cap_ini_with_none");
  r = runApp({"run", "-c", kConfig, "-i", kDemo, "-o", unreduced.string(), "--quiet", "--reducer",
              "none"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(readJson(unreduced / "summary.json")["cap"].is_null());
}
