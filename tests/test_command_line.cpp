// One rule for the command lines of budget-slam, budget-simulate and budget-convert
// (docs/OUTPUTS.md "Exit codes"): help prints the usage once on stdout and exits 0; a bad
// command line is one line on stderr naming the flag, exit 2, and nothing written. The real
// executables run as subprocesses.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>

#include "AppTestUtil.h"

using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

Process run(const std::string& command_line, const fs::path& cwd) {
  return runBinary(command_line, cwd);
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(CommandLine, HelpPrintsTheUsageOnceAndExitsZero) {
  const auto cwd = freshDir("help");
  fs::create_directories(cwd);
  for (const std::string c :
       {"budget-slam' --help", "budget-slam' -h", "budget-slam' run --help",
        "budget-slam' compare --help", "budget-slam' run -h", "budget-slam' localize --help",
        "budget-simulate' --help", "budget-convert' --help"}) {
    const auto p = run(c, cwd);
    EXPECT_EQ(p.exit_code, 0) << c;
    EXPECT_EQ(p.err, "") << c;
    EXPECT_EQ(count(p.out, "USAGE:"), 1u) << c << "\n" << p.out;
  }
  // Each command's own flags.
  EXPECT_NE(run("budget-slam' compare --help", cwd).out.find("--reducers"), std::string::npos);
  EXPECT_EQ(run("budget-slam' run --help", cwd).out.find("--reducers"), std::string::npos);
  EXPECT_NE(run("budget-slam' localize --help", cwd).out.find("--start-pose"), std::string::npos);
  EXPECT_NE(run("budget-slam' compare --help", cwd).out.find("--relocalize"), std::string::npos);
  EXPECT_NE(run("budget-slam' --help", cwd).out.find("coverage-mi"), std::string::npos);
  for (const std::string tool : {"budget-slam", "budget-simulate", "budget-convert"}) {
    const auto p = run(tool + "' --version", cwd);
    EXPECT_EQ(p.exit_code, 0) << tool;
    EXPECT_EQ(p.out, tool + " version 0.1\n");
  }
  EXPECT_TRUE(fs::is_empty(cwd));
}

TEST(CommandLine, ABadCommandLineIsOneLineNamingTheFlagAndExitTwo) {
  const auto cwd = freshDir("bad_command_lines");
  fs::create_directories(cwd);
  const std::string demo = "'" + kDemo + "'";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"budget-slam'",
       "budget-slam: expected a command, run, compare or localize; see budget-slam --help"},
      {"budget-slam' bogus",
       "budget-slam: unknown command 'bogus' (expected run, compare or localize); see budget-slam "
       "--help"},
      {"budget-slam' localize --map m -i " + demo + " -o out --start-pose 1,2",
       "budget-slam: --start-pose '1,2': expected x,y,yaw (metres, metres, degrees); see "
       "budget-slam localize --help"},
      {"budget-slam' run -i " + demo + " -o out --bogus",
       "budget-slam: Couldn't find match for argument (Argument: --bogus); see budget-slam run "
       "--help"},
      {"budget-slam' run -i " + demo + " -o out --cap",
       "budget-slam: Missing a value for this argument! (Argument: (--cap)); see budget-slam run "
       "--help"},
      {"budget-slam' run -i " + demo + " -o out --cap 0",
       "budget-slam: --cap 0: must be at least 1 (or none for no cap); see budget-slam run --help"},
      {"budget-slam' run -i " + demo + " -o out --backend gtsam",
       "budget-slam: --backend gtsam: must be one of ekf, graph; see budget-slam run --help"},
      {"budget-slam' compare -i " + demo + " -o out --reducers mi,mi",
       "budget-slam: --reducers: a reducer is listed twice; see budget-slam compare --help"},
      {"budget-slam' compare -i " + demo + " -o out --reducers none",
       "budget-slam: --reducers: 'none' is the reference run, always included; see budget-slam "
       "compare --help"},
      {"budget-slam' run -i " + demo + " -o out --set LandmarkBudget",
       "budget-slam: --set 'LandmarkBudget': expected Section.key=value; see budget-slam run "
       "--help"},
      {"budget-convert' --format utias --robot 6 mrclam -o out.rawlog",
       "budget-convert: Value '6' does not meet constraint: 1|2|3|4|5 (Argument: -r (--robot)); "
       "see budget-convert --help"},
      {"budget-convert' --format isam vp.txt --bogus -o out.rawlog",
       "budget-convert: unknown flag '--bogus'; see budget-convert --help"},
      {"budget-convert' --format isam vp.txt -o out.txt",
       "budget-convert: output 'out.txt': the rawlog name must end in .rawlog; see budget-convert "
       "--help"},
      {"budget-simulate' --scenario rooms --laps -1 -o out.rawlog",
       "budget-simulate: --laps -1: must be at least 1 (0: the scenario's default); see "
       "budget-simulate --help"},
      {"budget-simulate' --scenario rooms --odo-std-xy -3 -o out.rawlog",
       "budget-simulate: --odo-std-xy -3: must be a finite number >= 0; see budget-simulate "
       "--help"},
      {"budget-simulate' --scenario mars -o out.rawlog",
       "budget-simulate: Value 'mars' does not meet constraint: "
       "paper-synthetic|rooms|park|lifelong|corridors|clusters (Argument: -s (--scenario)); see "
       "budget-simulate "
       "--help"},
  };
  for (const auto& [c, message] : cases) {
    const auto p = run(c, cwd);
    EXPECT_EQ(p.exit_code, 2) << c;
    EXPECT_EQ(p.out, "") << c;
    EXPECT_EQ(p.err, message + "\n") << c;
    EXPECT_TRUE(fs::is_empty(cwd)) << c;  // nothing written
  }
}
