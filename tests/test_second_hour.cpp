// Issue 35, "the researcher's second hour": the points a test of this file covers (point 1 is in
// test_cap, 6 in test_failures, 12 in test_bad_rawlogs, 8 in readme_commands, 9 in figures_pdf,
// 10 in the core's test_ini, 14 in test_limits and full_disk).
#include <gtest/gtest.h>

#include "AppTestUtil.h"

using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

const std::string kConfig = kRoot + "/config.ini";

}  // namespace

// Point 4: a rawlog without its sidecar ran on default sensor noise that config_used.ini did not
// hold. Every value a run used is in config_used.ini, which runs the same run again.
TEST(SecondHour, ConfigUsedHoldsEveryValueTheRunUsed) {
  const auto dir = freshDir("config_used_defaults");
  const auto rawlog = dir.parent_path() / "config_used_defaults_nosidecar.rawlog";
  fs::copy_file(kDemo, rawlog, fs::copy_options::overwrite_existing);
  const auto first = dir / "first";
  auto r = runApp({"run", "-c", kConfig, "-i", rawlog.string(), "-o", first.string(), "--quiet",
                   "--max-steps", "80"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(readJson(first / "summary.json")["sidecar_ini"], "");  // none read
  const std::string used = slurp(first / "config_used.ini");
  for (const char* line : {"std_sensor_range = 0.1", "std_sensor_yaw_deg = 0.5",
                           "progress_every_s = 5", "reloc_min_landmarks = "})
    EXPECT_NE(used.find(line), std::string::npos) << line << " in\n" << used;
  // The outputs reproduce the run: config_used.ini as -c gives the same trajectory, silently.
  const auto again = dir / "again";
  r = runApp({"run", "-c", (first / "config_used.ini").string(), "-i", rawlog.string(), "-o",
              again.string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(slurp(again / "trajectory.tum"), slurp(first / "trajectory.tum"));
  EXPECT_EQ(slurp(again / "landmarks.csv"), slurp(first / "landmarks.csv"));
  // With a sidecar, its file is recorded and its values are those written.
  const auto shipped = dir / "shipped";
  r = runApp(
      {"run", "-c", kConfig, "-i", kDemo, "-o", shipped.string(), "--quiet", "--max-steps", "10"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(readJson(shipped / "summary.json")["sidecar_ini"], kRoot + "/rawlogs/kf-slam_demo.ini");
}

// Point 11: --help lists every exit code, localize's 3 too.
TEST(SecondHour, HelpListsEveryExitCode) {
  const auto cwd = freshDir("second_hour_help");
  fs::create_directories(cwd);
  const auto p = runBinary("budget-slam' --help", cwd);
  EXPECT_EQ(p.exit_code, 0);
  EXPECT_NE(p.out.find("Exit codes: 0 ok, 1 failed run, 2 bad command line, 3 not found on the "
                       "map (localize\n--wake-up), 130 interrupted."),
            std::string::npos)
      << p.out;
}

// Point 11: [Report] figure_title = false draws the figures without their title (a paper's
// caption says it); the SVG's <text> elements show it.
TEST(SecondHour, FiguresWithoutTitle) {
  const auto dir = freshDir("figure_title");
  for (const std::string title : {"true", "false"}) {
    const auto out = dir / title;
    const auto r = runApp({"run", "-c", kConfig, "-i", kDemo, "-o", out.string(), "--quiet",
                           "--max-steps", "40", "--set", "Report.figure_format=svg", "--set",
                           "Report.figure_title=" + title});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string svg = slurp(out / "map.svg");
    EXPECT_EQ(svg.find(">kf-slam_demo.rawlog: ekf, reducer") != std::string::npos, title == "true")
        << svg.substr(0, 2000);
    EXPECT_NE(svg.find(">x [m]</text>"), std::string::npos);  // the axes keep their labels
  }
}
