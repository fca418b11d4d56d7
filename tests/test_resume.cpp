// run --resume: a rawlog split at a step and run as two sessions gives the one-shot run's
// estimate and decisions (docs/OUTPUTS.md "Session state"); a bad state file or a mismatched
// option is one line, exit 1, and nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "AppTestUtil.h"

namespace budget_slam::testing {
namespace {

struct Split {
  std::string name, rawlog, backend, cap;
  std::size_t at;  ///< the step the rawlog is split at
};

std::vector<std::string> runArgs(const Split& s, const std::filesystem::path& out) {
  return {"run", "-c",         kRoot + "/config.ini", "-i",      kRoot + "/rawlogs/" + s.rawlog,
          "-o",  out.string(), "--backend",           s.backend, "--cap",
          s.cap, "--quiet"};
}

std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/// Column `name` of every row of a CSV as numbers, keyed by the first column (the step or id).
std::map<std::string, std::vector<double>> numbers(const std::filesystem::path& csv,
                                                   const std::vector<std::string>& names) {
  const CsvTable t = readCsvTable(csv);
  std::map<std::string, std::vector<double>> out;
  for (std::size_t r = 0; r < t.rows.size(); ++r)
    for (const auto& n : names) out[t.rows[r][0]].push_back(std::stod(t.at(r, n)));
  return out;
}

/// Largest absolute difference of the values both tables hold for the keys of `b`.
double maxDiff(const std::map<std::string, std::vector<double>>& a,
               const std::map<std::string, std::vector<double>>& b) {
  double d = 0;
  for (const auto& [k, v] : b) {
    const auto it = a.find(k);
    if (it == a.end()) return INFINITY;
    for (std::size_t i = 0; i < v.size(); ++i) d = std::max(d, std::abs(v[i] - it->second[i]));
  }
  return d;
}

/// (step, landmark, reason) of every drop at or after `from`.
std::vector<std::string> drops(const std::filesystem::path& csv, std::size_t from) {
  const CsvTable t = readCsvTable(csv);
  std::vector<std::string> out;
  for (std::size_t r = 0; r < t.rows.size(); ++r)
    if (std::stoul(t.at(r, "step")) >= from)
      out.push_back(t.at(r, "step") + "," + t.at(r, "landmark_id") + "," + t.at(r, "reason"));
  return out;
}

/// trajectory.tum's positions (x, y) by timestamp.
std::map<std::string, std::vector<double>> tum(const std::filesystem::path& p) {
  std::map<std::string, std::vector<double>> out;
  std::istringstream in(slurp(p));
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream l(line);
    std::string t;
    double x, y, z, qx, qy, qz, qw;
    l >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
    // Positions only: a yaw near +-pi would read as 2 pi off (the bound below is on metres).
    out[t] = {x, y};
    (void)qx, (void)qy, (void)qz, (void)qw;
  }
  return out;
}

struct SplitResult {
  double pose_diff, landmark_diff;
  bool same_drops, same_ids;
  double final_trajectory_diff;  ///< trajectory.tum (the graph's smoothed path after its solve)
  std::size_t kept;
  std::size_t drops_before, drops_after;  ///< evictions.csv rows before the split, after it
};

SplitResult runSplit(const Split& s) {
  const auto dir = freshDir("resume_" + s.name);
  const auto one = runApp(runArgs(s, dir / "one"));
  EXPECT_EQ(one.exit_code, 0) << one.err;
  const auto a = runApp(plus(runArgs(s, dir / "a"), {"--max-steps", std::to_string(s.at)}));
  EXPECT_EQ(a.exit_code, 0) << a.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "a" / "session_state.txt"));
  const auto b = runApp(plus(runArgs(s, dir / "b"), {"--resume", (dir / "a").string(),
                                                     "--skip-steps", std::to_string(s.at)}));
  EXPECT_EQ(b.exit_code, 0) << b.err;
  const auto steps_one = numbers(dir / "one" / "steps.csv", {"x", "y", "yaw", "n_landmarks"});
  const auto steps_b = numbers(dir / "b" / "steps.csv", {"x", "y", "yaw", "n_landmarks"});
  EXPECT_EQ(steps_b.size() + s.at, steps_one.size());
  EXPECT_EQ(readCsvTable(dir / "b" / "steps.csv").rows.at(0).at(0),
            std::to_string(s.at));  // step indices run on
  const std::vector<std::string> lm = {"x", "y", "cov_xx", "cov_xy", "cov_yy"};
  const auto lm_one = numbers(dir / "one" / "landmarks.csv", lm);
  const auto lm_b = numbers(dir / "b" / "landmarks.csv", lm);
  std::vector<std::string> ids_one, ids_b;
  for (const auto& [k, v] : lm_one) ids_one.push_back(k);
  for (const auto& [k, v] : lm_b) ids_b.push_back(k);
  const auto summary = readJson(dir / "b" / "summary.json");
  EXPECT_EQ(summary["resumed_from"], (dir / "a").string());
  return {maxDiff(steps_one, steps_b),
          maxDiff(lm_one, lm_b),
          drops(dir / "one" / "evictions.csv", s.at) == drops(dir / "b" / "evictions.csv", 0),
          ids_one == ids_b,
          maxDiff(tum(dir / "one" / "trajectory.tum"), tum(dir / "b" / "trajectory.tum")),
          lm_b.size(),
          drops(dir / "one" / "evictions.csv", 0).size() -
              drops(dir / "one" / "evictions.csv", s.at).size(),
          drops(dir / "one" / "evictions.csv", s.at).size()};
}

// The EKF's whole state goes into the file with every double exact: two sessions are the one-shot
// run (1e-9), drop for drop, under the default reducer (localization-information: place records).
TEST(Resume, SplitEqualsOneShotEkfKfDemo) {
  const auto r = runSplit({"ekf_demo", "kf-slam_demo.rawlog", "ekf", "10", 60});
  EXPECT_LE(r.pose_diff, 1e-9);
  EXPECT_LE(r.landmark_diff, 1e-9);
  EXPECT_TRUE(r.same_drops);
  EXPECT_TRUE(r.same_ids);
}

TEST(Resume, SplitEqualsOneShotEkfRooms) {
  const auto r = runSplit({"ekf_rooms", "rooms.rawlog", "ekf", "20", 300});
  EXPECT_LE(r.pose_diff, 1e-9);
  EXPECT_LE(r.landmark_diff, 1e-9);
  EXPECT_TRUE(r.same_drops);
  EXPECT_TRUE(r.same_ids);
}

// Every reducer that keeps memory (random's generator, mi's schedule, place-coverage's places)
// continues it exactly.
TEST(Resume, SplitEqualsOneShotEkfEveryReducerWithMemory) {
  for (const std::string reducer : {"random", "place-coverage", "mi"}) {
    Split s{"ekf_" + reducer, "kf-slam_demo.rawlog", "ekf", "10", 60};
    const auto dir = freshDir("resume_reducer_" + reducer);
    const std::vector<std::string> more = {"--reducer", reducer};
    ASSERT_EQ(runApp(plus(runArgs(s, dir / "one"), more)).exit_code, 0);
    ASSERT_EQ(runApp(plus(runArgs(s, dir / "a"), plus(more, {"--max-steps", "60"}))).exit_code, 0);
    const auto b =
        runApp(plus(runArgs(s, dir / "b"),
                    plus(more, {"--resume", (dir / "a").string(), "--skip-steps", "60"})));
    ASSERT_EQ(b.exit_code, 0) << b.err;
    EXPECT_EQ(drops(dir / "one" / "evictions.csv", 60), drops(dir / "b" / "evictions.csv", 0))
        << reducer;
    const std::vector<std::string> lm = {"x", "y", "cov_xx", "cov_xy", "cov_yy"};
    EXPECT_LE(maxDiff(numbers(dir / "one" / "landmarks.csv", lm),
                      numbers(dir / "b" / "landmarks.csv", lm)),
              1e-9)
        << reducer;
  }
}

// The budget's negative evidence (docs/ALGORITHMS.md "Negative evidence": misses, passes, the
// place cells a landmark was seen from) is saved too: two sessions count the same misses and drop
// the same landmarks for it as one run.
TEST(Resume, SplitEqualsOneShotEkfWithNegativeEvidence) {
  Split s{"ekf_negative", "rooms.rawlog", "ekf", "20", 300};
  const auto dir = freshDir("resume_negative_evidence");
  const std::vector<std::string> more = {"--set", "LandmarkBudget.negative_evidence=always",
                                         "--set", "LandmarkBudget.viewpoint_cell=2"};
  ASSERT_EQ(runApp(plus(runArgs(s, dir / "one"), more)).exit_code, 0);
  ASSERT_EQ(runApp(plus(runArgs(s, dir / "a"), plus(more, {"--max-steps", "300"}))).exit_code, 0);
  EXPECT_NE(slurp(dir / "a" / "session_state.txt").find("negative_evidence"), std::string::npos);
  const auto b =
      runApp(plus(runArgs(s, dir / "b"),
                  plus(more, {"--resume", (dir / "a").string(), "--skip-steps", "300"})));
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_EQ(drops(dir / "one" / "evictions.csv", 300), drops(dir / "b" / "evictions.csv", 0));
  const std::vector<std::string> lm = {"x", "y", "last_confirmed_step", "misses"};
  const auto lm_one = numbers(dir / "one" / "landmarks.csv", lm);
  const auto lm_b = numbers(dir / "b" / "landmarks.csv", lm);
  EXPECT_EQ(lm_one.size(), lm_b.size());
  EXPECT_LE(maxDiff(lm_one, lm_b), 1e-9);
}

// The graph saves itself whole, factor for factor (docs/GRAPH.md "Resuming a session"): two
// sessions are the one-shot run to rounding, online poses, final path, map and drops, with drops
// in both halves under the default reducer.
TEST(Resume, SplitEqualsOneShotGraph) {
  for (const auto& s : {Split{"graph_demo", "kf-slam_demo.rawlog", "graph", "10", 60},
                        Split{"graph_rooms", "rooms.rawlog", "graph", "20", 300}}) {
    const auto r = runSplit(s);
    EXPECT_LE(r.pose_diff, 1e-6) << s.name;
    EXPECT_LE(r.landmark_diff, 1e-6) << s.name;
    EXPECT_LE(r.final_trajectory_diff, 1e-6) << s.name;
    EXPECT_TRUE(r.same_drops) << s.name;
    EXPECT_TRUE(r.same_ids) << s.name;
    EXPECT_GT(r.drops_before, 0u) << s.name;
    EXPECT_GT(r.drops_after, 0u) << s.name;
    EXPECT_EQ(r.kept, std::stoul(s.cap)) << s.name;
  }
}

class ResumeRefused : public ::testing::Test {
 protected:
  void SetUp() override {
    // A folder a test: ctest runs the tests of this fixture at the same time.
    dir = freshDir(std::string("resume_refused_") +
                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
    const auto a = runApp(plus(runArgs(s, dir / "a"), {"--max-steps", "40"}));
    ASSERT_EQ(a.exit_code, 0) << a.err;
    state = dir / "a" / "session_state.txt";
    text = slurp(state);
  }
  /// Resumes into a fresh folder `out`: the exit code and stderr; `out` must not be made.
  AppResult resume(const std::vector<std::string>& more = {}) {
    const auto r =
        runApp(plus(plus(runArgs(s, dir / "out"), {"--resume", (dir / "a").string()}), more));
    EXPECT_FALSE(std::filesystem::exists(dir / "out")) << "the output folder was made";
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    return r;
  }
  void write(const std::string& bytes) {
    std::ofstream(state, std::ios::binary | std::ios::trunc) << bytes;
  }
  Split s{"refused", "kf-slam_demo.rawlog", "ekf", "10", 40};
  std::filesystem::path dir, state;
  std::string text;
};

TEST_F(ResumeRefused, CorruptStateFile) {
  std::string bad = text;
  bad[bad.size() / 2] = bad[bad.size() / 2] == '1' ? '2' : '1';
  write(bad);
  const auto r = resume();
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("session state '" + state.string() + "'"), std::string::npos) << r.err;
}

TEST_F(ResumeRefused, TruncatedStateFile) {
  write(text.substr(0, text.size() / 3));
  const auto r = resume();
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("session state '" + state.string() + "'"), std::string::npos) << r.err;
}

TEST_F(ResumeRefused, ForeignFile) {
  write("PK\x03\x04 not a state at all\n");
  const auto r = resume();
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("not a budget-slam session state"), std::string::npos) << r.err;
}

TEST_F(ResumeRefused, MissingStateFile) {
  std::filesystem::remove(state);
  const auto r = resume();
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
}

TEST_F(ResumeRefused, OtherCapNamesTheKey) {
  auto args = runArgs(s, dir / "out");
  args[std::find(args.begin(), args.end(), "--cap") - args.begin() + 1] = "12";
  const auto r = runApp(plus(args, {"--resume", (dir / "a").string()}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  EXPECT_NE(r.err.find("[LandmarkBudget] max_landmarks = 12, the saved session had 10"),
            std::string::npos)
      << r.err;
}

TEST_F(ResumeRefused, OtherBackendNamesTheKey) {
  auto args = runArgs(s, dir / "out");
  args[std::find(args.begin(), args.end(), "--backend") - args.begin() + 1] = "graph";
  const auto r = runApp(plus(args, {"--resume", (dir / "a").string()}));
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("backend = graph, the saved session had ekf"), std::string::npos) << r.err;
}

TEST_F(ResumeRefused, OutputFolderIsTheSavedSession) {
  const auto before = text;
  const auto r = runApp(plus(runArgs(s, dir / "a"), {"--resume", (dir / "a").string()}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(slurp(state), before);
  EXPECT_NE(r.err.find("the output folder must be another one"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace budget_slam::testing

namespace budget_slam::testing {
namespace {

// --wake-up: another traversal of the same rooms, started anywhere, is found on the saved map by
// the landmark ids of its first steps and mapped on from there; a robot not found is one line,
// exit 1, and no output.
TEST(ResumeWakeUp, FoundOnTheSavedMapThenMapsOn) {
  const auto dir = freshDir("resume_wake_up");
  const Split first{"wake", "rooms.rawlog", "ekf", "51", 0};
  ASSERT_EQ(runApp(runArgs(first, dir / "a")).exit_code, 0);
  Split next = first;
  next.rawlog = "rooms_revisit.rawlog";
  const auto r =
      runApp(plus(runArgs(next, dir / "b"), {"--resume", (dir / "a").string(), "--wake-up"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = readJson(dir / "b" / "summary.json");
  EXPECT_EQ(j["wake_up"]["status"], "found");
  EXPECT_TRUE(j["wake_up"]["by_ids"]);
  EXPECT_LE(j["wake_up"]["steps"].get<int>(), 10);
  EXPECT_EQ(j["status"], "ok");
  EXPECT_LE(j["counts"]["landmarks_final"].get<int>(), 51);

  const auto refused =
      runApp(plus(runArgs(next, dir / "c"), {"--resume", (dir / "a").string(), "--wake-up", "--set",
                                             "WakeUp.min_landmarks=1000"}));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("--wake-up: the robot was not found on the saved map in"),
            std::string::npos)
      << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "c"));
}

}  // namespace
}  // namespace budget_slam::testing
