// docs/ARCHITECTURE.md "Bad input": a one-line error naming the file, step or key, a non-zero exit,
// no crash, and summary.json saying why wherever the output folder could be made.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <csignal>
#include <random>

#include "AppTestUtil.h"
#include "budget_slam/reducers/BuiltinReducers.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

/// A bad command line: exit 2, one line naming the flag, nothing written.
void expectBadCommandLine(const AppResult& r, const fs::path& out, const std::string& message) {
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(isOneLine(r.err, Said::CommandLine, message));
  EXPECT_FALSE(fs::exists(out)) << out;
}

}  // namespace

TEST(BadInput, MissingRawlog) {
  const auto out = freshDir("missing");
  const std::string path = (out.parent_path() / "no_such.rawlog").string();
  expectFailedRun(runOn(path, out), out, "rawlog '" + path + "': no such file");
}

TEST(BadInput, RandomBytes) {
  const auto out = freshDir("random");
  const auto path = out.parent_path() / "random.rawlog";
  std::mt19937 rng(1);
  std::ofstream f(path, std::ios::binary);
  for (int i = 0; i < 4096; ++i) f.put(static_cast<char>(rng() & 0xff));
  f.close();
  expectFailedRun(runOn(path.string(), out), out,
                  "rawlog '" + path.string() +
                      "': not an MRPT rawlog (no serialized MRPT object at its start)");
}

TEST(BadInput, TruncatedRawlogKeepsTheStepsAlreadyDone) {
  const auto out = freshDir("truncated");
  const auto path = out.parent_path() / "truncated.rawlog";
  const std::string bytes = slurp(kDemo);
  std::ofstream(path, std::ios::binary) << bytes.substr(0, 20000);
  const auto r = runOn(path.string(), out);
  expectFailedRun(r, out,
                  "rawlog '" + path.string() +
                      "': truncated or corrupt at step 102 (the file ends inside a "
                      "mrpt::obs::CActionCollection)");
  // The 102 steps before the damage are in the outputs.
  EXPECT_EQ(readCsv(out / "steps.csv").size(), 102u);
  EXPECT_EQ(readJson(out / "summary.json")["counts"]["steps"], 102);
  EXPECT_FALSE(slurp(out / "trajectory.tum").empty());
  EXPECT_FALSE(slurp(out / "landmarks.csv").empty());
}

TEST(BadInput, RawlogWithoutBearingRangeSaysWhatItHolds) {
  const auto out = freshDir("no_bearing_range");
  const auto path = out.parent_path() / "odometry_only.rawlog";
  {
    mrpt::io::CFileGZOutputStream f(path.string());
    auto arch = mrpt::serialization::archiveFrom(f);
    for (int k = 0; k < 5; ++k) {
      mrpt::obs::CActionCollection acts;
      mrpt::obs::CSensoryFrame sf;
      auto odo = std::make_shared<mrpt::obs::CObservationOdometry>();
      odo->odometry = mrpt::poses::CPose2D(0.1 * k, 0, 0);
      sf.insert(odo);
      arch << acts << sf;
    }
  }
  expectFailedRun(runOn(path.string(), out), out,
                  "rawlog '" + path.string() +
                      "' holds no CObservationBearingRange (it holds: CObservationOdometry)");
  EXPECT_EQ(readCsv(out / "steps.csv").size(), 5u);
}

TEST(BadInput, UnknownReducerListsRegistered) {
  std::string list;
  for (const auto& n : reducers::builtinReducers().names()) list += (list.empty() ? "" : ", ") + n;
  // On the command line: a bad command line. In the ini: a failed run.
  const auto flag = freshDir("unknown_reducer_flag");
  expectBadCommandLine(
      runOn(kDemo, flag, {"--reducer", "bogus"}), flag,
      "--reducer: unknown reducer 'bogus' (registered: " + list + "); see budget-slam run --help");
  const auto out = freshDir("unknown_reducer");
  expectFailedRun(runOn(kDemo, out, {"--set", "LandmarkBudget.reducer=bogus"}), out,
                  "unknown reducer 'bogus' (registered: " + list + ")");
}

TEST(BadInput, CapBelowOne) {
  const auto out = freshDir("cap0");
  expectBadCommandLine(runOn(kDemo, out, {"--reducer", "oldest", "--cap", "0"}), out,
                       "--cap 0: must be at least 1 (or none for no cap); see budget-slam run "
                       "--help");
  expectBadCommandLine(runOn(kDemo, out, {"--cap", "lots"}), out,
                       "--cap 'lots': not a number of landmarks, nor none; see budget-slam run "
                       "--help");
  const auto out2 = freshDir("cap0_ini");
  expectFailedRun(runOn(kDemo, out2, {"--set", "LandmarkBudget.max_landmarks=-3"}), out2,
                  "--set 'LandmarkBudget.max_landmarks=-3': [LandmarkBudget] max_landmarks = -3: "
                  "must be at least 1 (or none for no cap)");
}

TEST(BadInput, UnknownIniKeySuggestsTheClosest) {
  const auto out = freshDir("unknown_key");
  expectFailedRun(runOn(kDemo, out, {"--set", "LandmarkBudget.max_landmark=10"}), out,
                  "--set 'LandmarkBudget.max_landmark=10': unknown key [LandmarkBudget] "
                  "max_landmark (did you mean max_landmarks?)");
  const auto out2 = freshDir("unknown_key_mrpt");
  expectFailedRun(runOn(kDemo, out2, {"--set", "RangeBearingKFSLAM.std_sensor_rnage=0.1"}), out2,
                  "--set 'RangeBearingKFSLAM.std_sensor_rnage=0.1': unknown key "
                  "[RangeBearingKFSLAM] std_sensor_rnage (did you mean std_sensor_range?)");
  // A key the -c file holds is named with the file.
  const auto out3 = freshDir("unknown_key_file");
  const auto ini = out3.parent_path() / "unknown_key.ini";
  std::ofstream(ini) << slurp(kMrptIni) << "\n[LandmarkBudget]\nmax_landmark = 10\n";
  expectFailedRun(
      runApp({"run", "-c", ini.string(), "-i", kDemo, "-o", out3.string(), "--quiet"}), out3,
      ini.string() + ": unknown key [LandmarkBudget] max_landmark (did you mean max_landmarks?)");
}

TEST(BadInput, NonEmptyOutputFolderNeedsForceAndNothingIsDeleted) {
  const auto out = freshDir("non_empty");
  fs::create_directories(out);
  std::ofstream(out / "notes.txt") << "mine";
  const auto r = runOn(kDemo, out);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(isErrorLine(
      r.err, "output folder '" + out.string() + "' is not empty (use --force to write into it)"));
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  const auto forced = runOn(kDemo, out, {"--force"});
  EXPECT_EQ(forced.exit_code, 0) << forced.err;
  EXPECT_EQ(slurp(out / "notes.txt"), "mine");
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

TEST(BadInput, CtrlCEndsWithStatusInterruptedAndOutputs) {
  const auto out = freshDir("interrupted");
  const auto r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", out.string(), "--quiet",
                         "--reducer", "oldest", "--cap", "10"},
                        [](app::BudgetSlamApp& a) {
                          a.on_step = [](StepIndex s) {
                            if (s == 100) std::raise(SIGINT);  // as Ctrl-C does
                          };
                        });
  EXPECT_EQ(r.exit_code, 130);
  EXPECT_TRUE(isOneLine(r.err, Said::Interrupted, "interrupted by Ctrl-C after step 100"));
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_EQ(s["counts"]["steps"], 101);
  EXPECT_EQ(readCsv(out / "steps.csv").size(), 101u);
}

/// A copy of the demo rawlog at `path` whose step 3 reading 1 has the range `range` [m].
void writeDemoWithRange(const fs::path& path, float range) {
  mrpt::io::CFileGZInputStream in(kDemo);
  auto ia = mrpt::serialization::archiveFrom(in);
  mrpt::io::CFileGZOutputStream o(path.string());
  auto oa = mrpt::serialization::archiveFrom(o);
  mrpt::obs::CActionCollection::Ptr act;
  mrpt::obs::CSensoryFrame::Ptr sf;
  size_t entry = 0;
  for (int k = 0; mrpt::obs::CRawlog::readActionObservationPair(ia, act, sf, entry); ++k) {
    if (k == 3) {
      auto obs = sf->getObservationByClass<mrpt::obs::CObservationBearingRange>();
      obs->sensedData.at(1).range = range;
    }
    oa << *act << *sf;
  }
}

TEST(BadInput, NegativeAndNanReadingsNameTheStep) {
  // A copy of the demo whose step 3 has a negative range.
  const auto out = freshDir("negative_range");
  const auto path = out.parent_path() / "negative_range.rawlog";
  writeDemoWithRange(path, -2.5f);
  const auto r = runOn(path.string(), out);
  expectFailedRun(r, out,
                  "rawlog '" + path.string() +
                      "': step 3: reading 1 has a negative or non-finite range (-2.500000)");
  EXPECT_EQ(readCsv(out / "steps.csv").size(), 3u);
}

TEST(BadInput, ZeroRangeOnTheGraphBackendNamesTheStepAndReading) {
  // The rawlog reader admits a zero range (the EKF takes it); the graph's range-bearing factor
  // cannot (its Jacobian divides by the range): a bad-input line, not an internal error.
  const auto out = freshDir("zero_range_graph");
  const auto path = out.parent_path() / "zero_range_graph.rawlog";
  writeDemoWithRange(path, 0.0f);
  const auto r = runOn(path.string(), out, {"--backend", "graph"});
  expectFailedRun(r, out,
                  "step 3: reading 1 has range 0.000000 m; the graph backend needs a finite range "
                  "above 0");
  EXPECT_EQ(readCsv(out / "steps.csv").size(), 3u);
}

TEST(BadInput, MissingConfigFileAndBadSetSyntax) {
  const auto r = runApp({"run", "-c", "/nonexistent/config.ini"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(isOneLine(r.err, Said::CommandLine,
                        "config file '/nonexistent/config.ini': no such file or not "
                        "readable"));
  const auto out = freshDir("bad_set");
  expectBadCommandLine(runOn(kDemo, out, {"--set", "nodot=3"}), out,
                       "--set 'nodot=3': expected Section.key=value; see budget-slam run --help");
}

TEST(BadInput, SigtermEndsLikeCtrlC) {
  const auto out = freshDir("sigterm");
  const auto r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", out.string(), "--quiet"},
                        [](app::BudgetSlamApp& a) {
                          a.on_step = [](StepIndex s) {
                            if (s == 50) std::raise(SIGTERM);  // kill, timeout, SLURM
                          };
                        });
  EXPECT_EQ(r.exit_code, 130);
  EXPECT_TRUE(isOneLine(r.err, Said::Interrupted, "interrupted by SIGTERM after step 50"));
  EXPECT_EQ(readJson(out / "summary.json")["status"], "interrupted");
}
