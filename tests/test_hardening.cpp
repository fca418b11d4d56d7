// The application under hostile input (docs/RELIABILITY.md "Application"): bad option values, files
// that are not ini files, a diverged filter, error text holding bytes that are not UTF-8, a forced
// run into an earlier run's folder, and stop requests in the end phase and in compare. Each ends
// with exit 1 (130 when interrupted), one line on stderr and summary.json saying why.
#include <gtest/gtest.h>

#include <csignal>
#include <random>

#include "AppTestUtil.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

/// A --set value and the error it must give (after "<ini>: ").
struct BadValue {
  std::string set, message;
};

/// Lines of a text file; the last one must end with '\n' (no partial line).
std::size_t wholeLines(const fs::path& p) {
  const std::string s = slurp(p);
  EXPECT_TRUE(s.empty() || s.back() == '\n') << p;
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

/// steps.csv, trajectory.tum and summary.json agree on the steps done: one steps.csv row a step,
/// one trajectory.tum row a step for the EKF and a kept pose for the graph (whose drops
/// marginalize poses), never a row cut in the middle.
void expectConsistentOutputs(const fs::path& out) {
  const auto s = readJson(out / "summary.json");
  const std::size_t steps = wholeLines(out / "steps.csv") - 1;  // header
  EXPECT_EQ(s["counts"]["steps"], steps);
  const std::size_t poses =
      s["backend"] == "graph" ? s["counts"]["poses_kept"].get<std::size_t>() : steps;
  EXPECT_EQ(wholeLines(out / "trajectory.tum"), poses);
}

fs::path writeFile(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

}  // namespace

// The values that made the filter diverge, and every MRPT ekf key with a range.
TEST(Hardening, SensorNoiseValuesAreCheckedWhereRead) {
  const std::string r = "[RangeBearingKFSLAM] ";
  const std::vector<BadValue> cases = {
      {"RangeBearingKFSLAM.std_sensor_range=0",
       r + "std_sensor_range = 0: must be > 0 (a standard deviation)"},
      {"RangeBearingKFSLAM.std_sensor_range=-0.1",
       r + "std_sensor_range = -0.1: must be > 0 (a standard deviation)"},
      {"RangeBearingKFSLAM.std_sensor_range=", r + "std_sensor_range = '': not a number"},
      {"RangeBearingKFSLAM.std_sensor_range=nan", r + "std_sensor_range = 'nan': not a number"},
      {"RangeBearingKFSLAM.std_sensor_range=inf",
       r + "std_sensor_range = inf: must be a finite number"},
      {"RangeBearingKFSLAM.std_sensor_yaw_deg=0",
       r + "std_sensor_yaw_deg = 0: must be > 0 (a standard deviation)"},
      {"RangeBearingKFSLAM.std_sensor_yaw_deg=NaN", r + "std_sensor_yaw_deg = 'NaN': not a number"},
      {"RangeBearingKFSLAM.std_sensor_yaw_deg=1e-300",
       r + "std_sensor_yaw_deg = 1e-300: must be at least 1e-12"},
      {"RangeBearingKFSLAM.stds_Q_no_odo=0.1 0.1",
       r + "stds_Q_no_odo = '0.1 0.1': must be 3 values (x [m], y [m], yaw [deg]), each finite "
           "and >= 0 (the motion noise of a step without odometry)"},
      {"RangeBearingKFSLAM.stds_Q_no_odo=0.1 -1 2",
       r + "stds_Q_no_odo = '0.1 -1 2': must be 3 values (x [m], y [m], yaw [deg]), each finite "
           "and >= 0 (the motion noise of a step without odometry)"},
      {"RangeBearingKFSLAM.data_assoc_IC_chi2_thres=1",
       r + "data_assoc_IC_chi2_thres = 1: must be in (0, 1) (a confidence level)"},
      {"RangeBearingKFSLAM.data_assoc_method=assocBogus",
       r + "data_assoc_method = 'assocBogus': must be one of assocNN, assocJCBB"},
      {"RangeBearingKFSLAM_KalmanFilter.method=bogus",
       "[RangeBearingKFSLAM_KalmanFilter] method = 'bogus': must be one of kfEKFNaive, "
       "kfEKFAlaDavison, kfIKFFull"},
      {"RangeBearingKFSLAM_KalmanFilter.IKF_iterations=0",
       "[RangeBearingKFSLAM_KalmanFilter] IKF_iterations = 0: must be at least 1"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.set);
    const auto out = freshDir("bad_value");
    const auto res = runOn(kDemo, out, {"--set", c.set});
    // Named by where the value came from: the --set, not the -c file (issue 25).
    expectFailedRun(res, out, "--set '" + c.set + "': " + c.message);
    EXPECT_EQ(res.err.find("MRPT exception"), std::string::npos);
  }
}

// The same keys in the ini file itself (not --set), on either backend.
TEST(Hardening, BadValuesInTheIniFileNameFileSectionKeyAndValue) {
  const auto out = freshDir("bad_value_ini");
  std::string ini = slurp(kMrptIni);
  const auto at = ini.find("std_sensor_range");
  ASSERT_NE(at, std::string::npos);
  ini.replace(at, ini.find('\n', at) - at, "std_sensor_range = 0");
  const auto path = writeFile(out.parent_path() / "zero_range.ini", ini);
  for (const char* backend : {"ekf", "graph"}) {
    const auto o = freshDir(std::string("bad_value_ini_") + backend);
    expectFailedRun(runOn(kDemo, o, {"--backend", backend}, path.string()), o,
                    path.string() +
                        ": [RangeBearingKFSLAM] std_sensor_range = 0: must be > 0 (a standard "
                        "deviation)");
  }
}

// --set and ini errors.
TEST(Hardening, UnknownSectionsAreErrors) {
  const auto out = freshDir("unknown_section_set");
  expectFailedRun(runOn(kDemo, out, {"--set", "Foo.bar=1"}), out,
                  "--set 'Foo.bar=1': unknown section [Foo] (neither budget-slam nor another MRPT "
                  "application reads it)");
  const auto out2 = freshDir("unknown_section_typo");
  expectFailedRun(runOn(kDemo, out2, {"--set", "LandmarkBuget.max_landmarks=3"}), out2,
                  "--set 'LandmarkBuget.max_landmarks=3': unknown section [LandmarkBuget] (did you "
                  "mean [LandmarkBudget]?)");
  const auto out3 = freshDir("unknown_section_ini");
  const auto ini =
      writeFile(out3.parent_path() / "unknown_section.ini", slurp(kMrptIni) + "\n[Foo]\nbar = 1\n");
  expectFailedRun(runOn(kDemo, out3, {}, ini.string()), out3,
                  ini.string() +
                      ": unknown section [Foo] (neither budget-slam nor another MRPT application "
                      "reads it)");
}

TEST(Hardening, ADuplicatedKeyNamesBothLines) {
  const auto out = freshDir("duplicated_key");
  const auto ini = writeFile(out.parent_path() / "duplicated.ini",
                             "[LandmarkBudget]\nmax_landmarks = 10\nreducer = oldest\n"
                             "max_landmarks = 20\n");
  expectFailedRun(
      runOn(kDemo, out, {}, ini.string()), out,
      ini.string() +
          ": line 4: duplicated key [LandmarkBudget] max_landmarks (first set at line 2)");
}

TEST(Hardening, FilesThatAreNotIniFilesAreRefused) {
  const auto dir = freshDir("not_ini");
  fs::create_directories(dir);
  // Prose: the first line is neither a section, a key nor a comment.
  const auto prose =
      writeFile(dir / "prose.ini", "It was a dark and stormy night, and the robot was lost.\n");
  auto out = freshDir("not_ini_prose");
  expectFailedRun(runOn(kDemo, out, {}, prose.string()), out,
                  prose.string() +
                      ": line 1: neither [section], key = value nor a comment: 'It was a dark and "
                      "stormy night, and the...'");
  // Binary: a gzip rawlog given as the ini.
  out = freshDir("not_ini_binary");
  expectFailedRun(runOn(kDemo, out, {}, kDemo), out,
                  kDemo + ": line 1: control byte 0x1f, not a text file");
  // 1 MB of random bytes.
  std::mt19937 rng(7);
  std::string garbage(1000000, '\0');
  for (auto& c : garbage) c = static_cast<char>(rng() & 0xff);
  const auto junk = writeFile(dir / "garbage.ini", garbage);
  out = freshDir("not_ini_garbage");
  const auto r = runOn(kDemo, out, {}, junk.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err.rfind("budget-slam: error: " + junk.string() + ": line 1: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
  EXPECT_EQ(readJson(out / "summary.json")["status"], "failed");
  // Lines only, no section.
  const auto nosection = writeFile(dir / "nosection.ini", "# a comment\n\n");
  out = freshDir("not_ini_nosection");
  expectFailedRun(runOn(kDemo, out, {}, nosection.string()), out,
                  nosection.string() + ": holds no [section], not an ini file");
}

TEST(Hardening, AFolderGivenAsConfigIsACommandLineError) {
  const auto dir = freshDir("config_folder");
  fs::create_directories(dir);
  const auto r = runApp({"run", "-c", dir.string(), "-i", kDemo, "--quiet"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(isOneLine(r.err, Said::CommandLine,
                        "config file '" + dir.string() + "': is a folder, not a file"));
}

TEST(Hardening, VariableExpansionFailureIsOneLineNotAnAbort) {
  const auto out = freshDir("variable");
  const auto ini = writeFile(out.parent_path() / "variable.ini",
                             "@define CAP 10\n[LandmarkBudget]\nmax_landmarks = ${CAP}\n"
                             "reducer = ${NOPE}\n");
  expectFailedRun(runOn(kDemo, out, {}, ini.string()), out,
                  ini.string() + ": line 4: unknown variable ${NOPE} (no @define NOPE above it)");
  // A defined one works, and expands once.
  const auto ok = writeFile(out.parent_path() / "variable_ok.ini",
                            slurp(kMrptIni) +
                                "\n@define CAP 10\n[LandmarkBudget]\n"
                                "max_landmarks = ${CAP}\nreducer = oldest\n");
  const auto out2 = freshDir("variable_ok");
  const auto r = runOn(kDemo, out2, {"--set", "MappingApplication.max_steps=30"}, ok.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(readJson(out2 / "summary.json")["cap"], 10);
  // --set values are not expanded.
  const auto out3 = freshDir("variable_set");
  expectFailedRun(
      runOn(kDemo, out3, {"--set", "LandmarkBudget.reducer=${X}"}), out3,
      "--set 'LandmarkBudget.reducer=${X}': ${...} is expanded in ini files only, not in "
      "a value given here");
}

// An error text echoing bytes that are not UTF-8 still gives a valid summary.json.
TEST(Hardening, SummaryIsWrittenWhateverBytesTheErrorEchoes) {
  const auto out = freshDir("bad_bytes");
  const std::string path = out.parent_path().string() + "/no\xff\xfe such.rawlog";
  const auto r = runOn(path, out);
  const std::string shown = out.parent_path().string() + "/no\\xff\\xfe such.rawlog";
  expectFailedRun(r, out, "rawlog '" + shown + "': no such file");
}

// A filter that diverges (MRPT's filter with a near-zero sensor noise, the smallest the checks
// allow) stops the run cleanly: no NaN reaches k-means, the map, the metrics or the files.
TEST(Hardening, DivergedFilterStopsCleanlyWithoutNan) {
  const auto out = freshDir("diverged");
  const auto r = runOn(
      kDemo, out,
      {"--reducer", "coverage", "--cap", "8", "--set", "RangeBearingKFSLAM.std_sensor_range=1e-12",
       "--set", "RangeBearingKFSLAM.std_sensor_yaw_deg=1e-12",
       // MRPT's own update: where a filter this ill-conditioned diverges depends on the order
       // of its arithmetic, and this test is about the divergence, not the update.
       "--set", "EkfSLAM.update=mrpt"});
  expectFailedRun(r, out,
                  "step 6: the ekf estimate diverged (the robot pose or its covariance is not "
                  "finite)");
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["counts"]["steps"], 6);
  EXPECT_GT(s["counts"]["landmarks_not_finite"], 0);  // left out of every output
  expectConsistentOutputs(out);
  EXPECT_EQ(slurp(out / "trajectory.tum").find("nan"), std::string::npos);
  EXPECT_EQ(slurp(out / "landmarks.csv").find("nan"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "map.png"));
}

// A forced run never mixes its files with an earlier run's.
TEST(Hardening, AForcedRunMovesTheEarlierRunAsideAndSaysSo) {
  const auto out = freshDir("forced");
  const auto first =
      runOn(kDemo, out,
            {"--reducer", "oldest", "--cap", "10", "--set", "LandmarkBudget.dump_states=true",
             "--set", "MappingApplication.max_steps=60"});
  ASSERT_EQ(first.exit_code, 0) << first.err;
  ASSERT_TRUE(fs::exists(out / "states"));
  ASSERT_TRUE(fs::exists(out / "ground_truth.tum"));
  std::ofstream(out / "notes.txt") << "mine";

  // The second run fails at once (a bad value), with --force.
  const auto second =
      runOn(kDemo, out, {"--force", "--set", "RangeBearingKFSLAM.std_sensor_range=0"});
  EXPECT_EQ(second.exit_code, 1);
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["status"], "failed");
  std::set<std::string> names;
  std::string earlier;
  for (const auto& e : fs::directory_iterator(out)) {
    const std::string n = e.path().filename().string();
    names.insert(n);
    if (n.rfind("earlier_run_", 0) == 0) earlier = n;
  }
  ASSERT_FALSE(earlier.empty());
  EXPECT_EQ(names, (std::set<std::string>{"summary.json", "notes.txt", earlier}));
  EXPECT_EQ(s["earlier_run_moved_to"], earlier);
  EXPECT_TRUE(fs::exists(out / earlier / "ground_truth.tum"));
  EXPECT_TRUE(fs::exists(out / earlier / "states"));
  EXPECT_EQ(readJson(out / earlier / "summary.json")["status"], "ok");
}

// Ctrl-C in the end phase (active minimization, the graph's final solve).
TEST(Hardening, CtrlCInTheEndPhaseEndsTheRun) {
  const auto out = freshDir("end_phase");
  const auto r = runApp(
      {"run", "-c", kMrptIni, "-i", kDemo, "-o", out.string(), "--quiet", "--backend", "graph",
       "--reducer", "mi", "--cap", "10", "--set", "MutualInformationReducer.mode=objective",
       "--set", "MappingApplication.max_steps=80"},
      [](app::BudgetSlamApp& a) {
        a.on_end_phase = [] { std::raise(SIGINT); };  // as Ctrl-C does
      });
  EXPECT_EQ(r.exit_code, 130);
  EXPECT_TRUE(
      isOneLine(r.err, Said::Interrupted, "interrupted by Ctrl-C in the end phase, after step 79"));
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_EQ(s["error"], "interrupted by Ctrl-C in the end phase, after step 79");
  expectConsistentOutputs(out);
}

TEST(Hardening, CtrlCInCompareEndsEveryRunAsInterrupted) {
  const auto out = freshDir("compare_interrupted");
  const auto r = runApp({"compare",    "-c",
                         kMrptIni,     "-i",
                         kDemo,        "-o",
                         out.string(), "--quiet",
                         "--backend",  "graph",
                         "--reducers", "mi,oldest",
                         "--cap",      "10",
                         "--set",      "MutualInformationReducer.mode=objective",
                         "--set",      "MappingApplication.max_steps=60",
                         "--threads",  "1"},
                        [](app::BudgetSlamApp& a) { a.on_end_phase = [] { std::raise(SIGINT); }; });
  EXPECT_EQ(r.exit_code, 130);
  // One line a run: the reference was stopped in its end phase, the others before their first step.
  const auto lines = linesOf(r.err);
  ASSERT_EQ(lines.size(), 3u) << r.err;
  EXPECT_TRUE(isOneLine(lines[0], Said::Interrupted,
                        "run 'reference': interrupted by Ctrl-C in the end phase, after step 59"));
  EXPECT_TRUE(isOneLine(lines[1], Said::Interrupted,
                        "run 'mi': interrupted by Ctrl-C before the first step"));
  EXPECT_TRUE(isOneLine(lines[2], Said::Interrupted,
                        "run 'oldest': interrupted by Ctrl-C before the first step"));
  EXPECT_EQ(readJson(out / "summary.json")["status"], "interrupted");
  for (const char* run : {"reference", "mi", "oldest"}) {
    SCOPED_TRACE(run);
    const auto s = readJson(out / run / "summary.json");
    EXPECT_EQ(s["status"], "interrupted");
    if (std::string(run) == "reference") {
      expectConsistentOutputs(out / run);
    } else {
      // Stopped before their first step: no file that would look like a result (issue 35).
      EXPECT_EQ(s["counts"]["steps"], 0);
      for (const char* file : {"steps.csv", "trajectory.tum", "map.png", "landmarks.csv"})
        EXPECT_FALSE(fs::exists(out / run / file)) << file;
    }
  }
  const auto rows = readCsv(out / "comparison.csv");
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) EXPECT_EQ(row.at(3), "interrupted");
}
