// run and compare from a typed request (runs::run, runs::compare) and the request's checks
// (runs::checkRequest): the report against the files the command wrote, and how a bad request,
// a bad configuration and a missing rawlog end.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/engine/SummaryJson.h"
#include "budget_slam/runs/Commands.h"
#include "budget_slam/runs/RequestChecks.h"

namespace budget_slam::runs {
namespace {

namespace fs = std::filesystem;

const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;
const std::string kDemo = kRoot + "/rawlogs/kf-slam_demo.rawlog";

/// A fresh (absent) output folder for test `name`.
std::string outdir(const std::string& name) {
  const auto dir = fs::temp_directory_path() / "budget_slam_tests" / "commands" / name;
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  return dir.string();
}

/// The demo's first 60 steps under a cap of 10, into `out`: a `run` or a `compare` request.
template <class Request>
Request request(const std::string& out) {
  Request r;
  r.common.rawlog = kDemo;
  r.common.outdir = out;
  r.common.max_steps = 60;
  r.common.quiet = true;
  r.cap = parseCap("10");
  return r;
}

/// The ini of these tests (the demo's sidecar adds its sensor noise), as a -c file's text.
RequestContext context(const std::string& text = "[MappingApplication]\nsave_3d_scene = false\n") {
  RequestContext c;
  c.config_text = text;
  c.config_label = "test.ini";
  c.writer = "budget-slam test";
  return c;
}

/// The first column of each row of a CSV file (its header left out).
std::vector<std::string> firstColumn(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) out.push_back(line.substr(0, line.find(',')));
  return out;
}

std::string fileText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(CompareCommand, TwoReducersOkAsItsFilesSay) {
  Cancellation::clear();
  const std::string out = outdir("ok");
  CompareRequest r = request<CompareRequest>(out);
  r.reducers = {"random", "oldest"};
  std::vector<std::string> warnings, notes;
  RunHooks hooks;
  hooks.warning = [&](const std::string& w) { warnings.push_back(w); };
  hooks.note = [&](const std::string& n) { notes.push_back(n); };
  std::size_t end_phases = 0;
  hooks.on_end_phase = [&] { ++end_phases; };  // from the runs' threads, one at a time each
  r.threads = 1;
  const CompareReport c = compare(r, context(), hooks);
  EXPECT_EQ(c.outcome.status, RunStatus::Ok) << c.outcome.first_error;
  EXPECT_EQ(c.outcome.kind, ErrorKind::None);
  EXPECT_EQ(c.outcome.exitCode(), 0);
  EXPECT_TRUE(c.outcome.lines.empty());
  EXPECT_TRUE(warnings.empty());
  EXPECT_TRUE(notes.empty());
  EXPECT_TRUE(c.started);
  EXPECT_EQ(end_phases, 3u);
  EXPECT_EQ(c.folder, out);

  // The rows are comparison.csv's, the reference first; the markdown is comparison.md.
  ASSERT_EQ(c.rows.size(), 3u);
  EXPECT_EQ(firstColumn(out + "/comparison.csv"),
            (std::vector<std::string>{"reference", "random", "oldest"}));
  // Each run's outcome is in the report, as its summary.json says it.
  ASSERT_EQ(c.runs.size(), c.rows.size());
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    const auto& row = c.rows[i];
    SCOPED_TRACE(row.run);
    EXPECT_EQ(row.status, "ok");
    EXPECT_EQ(row.backend, "ekf");
    const SummaryFile file = readSummary(out + "/" + row.run + "/summary.json");
    EXPECT_EQ(file.outcome.status, RunStatus::Ok);
    EXPECT_EQ(c.runs[i].name, row.run);
    ASSERT_TRUE(c.runs[i].summary);
    EXPECT_EQ(summaryJson(*c.runs[i].summary), file.json);
  }
  EXPECT_EQ(c.rows[0].reducer, "none");
  EXPECT_EQ(c.rows[1].cap, 10);
  EXPECT_LE(c.rows[1].landmarks, 10u);
  EXPECT_GT(c.rows[1].evictions, 0u);
  EXPECT_EQ(c.markdown, fileText(out + "/comparison.md"));
  EXPECT_EQ(
      c.markdown.rfind("### budget-slam compare: " + kDemo + ", backend ekf, cap 10, 60 steps", 0),
      0u)
      << c.markdown;

  // The top summary.json is the outcome.
  const SummaryFile top = readSummary(out + "/summary.json");
  EXPECT_EQ(top.outcome.status, RunStatus::Ok);
  EXPECT_EQ(summaryJson(c.summary), top.json);
  EXPECT_EQ(top.json.at("runs"), 3);
  EXPECT_EQ(top.json.at("steps"), 60);
  EXPECT_EQ(top.json.at("config"), "test.ini");
  EXPECT_EQ(top.json.at("started"), true);
}

TEST(CompareCommand, ABadConfigurationFailsInOneLine) {
  Cancellation::clear();
  const std::string out = outdir("bad_config");
  const CompareReport c = compare(request<CompareRequest>(out),
                                  context("[LandmarkBudget]\nprotect_recent_steps = many\n"), {});
  EXPECT_EQ(c.outcome.status, RunStatus::Failed);
  EXPECT_EQ(c.outcome.kind, ErrorKind::Config);
  EXPECT_EQ(c.outcome.exitCode(), 1);
  EXPECT_FALSE(c.started);
  EXPECT_TRUE(c.rows.empty());
  EXPECT_EQ(c.markdown, "");
  ASSERT_EQ(c.outcome.lines.size(), 1u);
  EXPECT_EQ(c.outcome.lines[0].kind, CompareLine::Kind::Error);
  EXPECT_EQ(c.outcome.lines[0].text, c.outcome.first_error);
  EXPECT_NE(c.outcome.first_error.find("[LandmarkBudget] protect_recent_steps"), std::string::npos)
      << c.outcome.first_error;
  // The folder says why, and that nothing started.
  const SummaryFile top = readSummary(out + "/summary.json");
  EXPECT_EQ(top.outcome.status, RunStatus::Failed);
  EXPECT_EQ(top.outcome.error, c.outcome.first_error);
  EXPECT_EQ(top.json.at("started"), false);
}

TEST(CompareCommand, AMissingRawlogIsAnInputFailure) {
  Cancellation::clear();
  CompareRequest r = request<CompareRequest>(outdir("no_rawlog"));
  r.common.rawlog = "/nonexistent/x.rawlog";
  const CompareReport c = compare(r, context(), {});
  EXPECT_EQ(c.outcome.status, RunStatus::Failed);
  EXPECT_EQ(c.outcome.kind, ErrorKind::Input);
  ASSERT_EQ(c.outcome.lines.size(), 1u);
  EXPECT_EQ(c.outcome.lines[0].shown(), "error: rawlog '/nonexistent/x.rawlog': no such file");
  EXPECT_FALSE(c.started);
}

TEST(RunCommand, ARequestRunsAsItsSummarySays) {
  Cancellation::clear();
  const std::string out = outdir("run_ok");
  RunRequest r = request<RunRequest>(out);
  r.reducer = "oldest";
  std::size_t steps = 0;
  RunHooks hooks;
  hooks.on_step = [&](StepIndex) { ++steps; };
  std::vector<std::string> warnings;
  hooks.warning = [&](const std::string& w) { warnings.push_back(w); };
  const RunReport report = run(r, context(), hooks);
  ASSERT_TRUE(report.outcome.ok()) << report.line;
  EXPECT_EQ(report.line, "");
  EXPECT_EQ(report.folder, out);
  EXPECT_EQ(steps, 60u);
  EXPECT_TRUE(warnings.empty());
  ASSERT_TRUE(report.outcome.run);
  EXPECT_EQ(report.outcome.run->reducer, "oldest");
  EXPECT_EQ(report.outcome.run->cap, std::optional<std::size_t>(10));
  const SummaryFile s = readSummary(out + "/summary.json");
  EXPECT_EQ(s.outcome.status, RunStatus::Ok);
  EXPECT_EQ(s.json.at("config"), "test.ini");
  EXPECT_EQ(s.json.at("counts").at("steps"), 60);
  EXPECT_EQ(s.json.at("counts").at("landmarks_final"), report.landmarks);
  // The sidecar's key over the ini's is a warning, as it arises.
  warnings.clear();
  RunRequest warned = request<RunRequest>(outdir("run_warned"));
  warned.reducer = "oldest";  // a cap with reducer none is refused
  const RunReport again =
      run(warned,
          context("[MappingApplication]\nsave_3d_scene = false\n[RangeBearingKFSLAM]\n"
                  "std_sensor_range = 0.5\n"),
          hooks);
  EXPECT_TRUE(again.outcome.ok()) << again.line;
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("sets [RangeBearingKFSLAM] std_sensor_range = 0.03 over test.ini's "
                             "0.5"),
            std::string::npos)
      << warnings[0];
}

TEST(RunCommand, ABadConfigTextEndsBeforeTheRunAndSaysWhyInTheFolder) {
  Cancellation::clear();
  const std::string out = outdir("run_bad_text");
  const RunReport r =
      run(request<RunRequest>(out), context("[LandmarkBudget]\nseed = 1\nseed = 2\n"), {});
  EXPECT_EQ(r.outcome.status, RunStatus::Failed);
  EXPECT_EQ(r.outcome.kind, ErrorKind::Config);
  EXPECT_EQ(r.line.rfind("test.ini: line 3: ", 0), 0u) << r.line;
  EXPECT_EQ(r.line, r.outcome.error);
  const SummaryFile s = readSummary(out + "/summary.json");
  EXPECT_EQ(s.outcome.error, r.line);
  EXPECT_EQ(s.json.at("started"), false);
}

TEST(RunCommand, AMismatchedResumeIsOneLineAndNoFolder) {
  Cancellation::clear();
  const std::string first = outdir("resume_first"), second = outdir("resume_second");
  RunRequest made = request<RunRequest>(first);
  made.reducer = "oldest";  // a cap with reducer none is refused
  ASSERT_TRUE(run(made, context(), {}).outcome.ok());
  RunRequest r = request<RunRequest>(second);
  r.reducer = "oldest";
  r.resume = first;
  r.cap = parseCap("12");
  const RunReport report = run(r, context(), {});
  EXPECT_EQ(report.outcome.status, RunStatus::Failed);
  EXPECT_EQ(report.outcome.kind, ErrorKind::Config);
  EXPECT_EQ(report.line, "--resume " + first +
                             ": [LandmarkBudget] max_landmarks = 12, the saved session had 10");
  EXPECT_FALSE(fs::exists(second));
}

TEST(RequestChecks, TheCommandLinesMessagesWhoeverFilledTheRequest) {
  const auto refused = [](const auto& r) {
    try {
      checkRequest(r);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const auto cap = [](const std::string& text) {
    try {
      return parseCap(text).text();
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
  };
  RunRequest r;
  CompareRequest c;
  EXPECT_EQ(refused(r), "accepted");
  EXPECT_EQ(refused(c), "accepted");
  EXPECT_EQ(cap("0"), "--cap 0: must be at least 1 (or none for no cap)");
  EXPECT_EQ(cap("ten"), "--cap 'ten': not a number of landmarks, nor none");
  EXPECT_EQ(cap("none"), "none");
  EXPECT_EQ(cap("12"), "12");
  r.cap = parseCap("none");
  r.backend = "kalman";
  EXPECT_EQ(refused(r).rfind("--backend kalman: must be one of ", 0), 0u);
  c.backend = "kalman";
  EXPECT_EQ(refused(c).rfind("--backend kalman: must be one of ", 0), 0u);
  r.backend = "graph", c.backend = "graph";
  c.reducers = {"random", "none"};
  EXPECT_EQ(refused(c), "--reducers: 'none' is the reference run, always included");
  c.reducers = {"random", "random"};
  EXPECT_EQ(refused(c), "--reducers: a reducer is listed twice");
  c.reducers = {"random", "nosuch"};
  EXPECT_EQ(refused(c).rfind("--reducers: unknown reducer 'nosuch' (registered: ", 0), 0u);
  c.reducers = {"random", "oldest"};
  EXPECT_EQ(refused(c), "accepted");
  r.reducer = "nosuch";
  EXPECT_EQ(refused(r).rfind("--reducer: unknown reducer 'nosuch' (registered: ", 0), 0u);
  r.reducer = "mi";
  EXPECT_EQ(refused(r), "accepted");
  r.common.sets = {"LandmarkBudget"};
  EXPECT_THROW(checkRequest(r), ConfigError);
  c.common.sets = {"LandmarkBudget"};
  EXPECT_THROW(checkRequest(c), ConfigError);

  RunRequest wake;
  wake.wake_up = true;
  EXPECT_THROW(checkWakeUp(wake), UsageError);
  wake.resume = "RUN";
  EXPECT_NO_THROW(checkWakeUp(wake));

  EXPECT_EQ(parseSeeds("3:5"), (std::vector<std::uint64_t>{3, 4, 5}));
  EXPECT_EQ(parseSeeds("7,2"), (std::vector<std::uint64_t>{7, 2}));
  EXPECT_THROW(parseSeeds("2,2"), UsageError);
  EXPECT_THROW(parseSeeds("0:1000"), UsageError);
  EXPECT_EQ(parseMaxSteps("0"), 0u);
  EXPECT_THROW(parseMaxSteps("-3"), UsageError);
  EXPECT_THROW(parseSkipSteps("x"), UsageError);
}

}  // namespace
}  // namespace budget_slam::runs
