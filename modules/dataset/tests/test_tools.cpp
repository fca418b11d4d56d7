#include <gtest/gtest.h>
#include <cmath>
#include <map>
#include <sstream>

#include <mrpt/config/CConfigFileMemory.h>

#include "TestUtil.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/Sessions.h"

using namespace budget_slam::dataset::test;

TEST(Tools, ConvertWritesRawlogGroundTruthAndSidecar) {
  TempDir tmp;
  const std::string dir = datasetsDir() + "/freiburg_slam_course";
  const auto r = runTool(tmp, bin("budget-convert") + " --format freiburg '" + dir + "' -o '" +
                                  tmp.file("f.rawlog") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, tmp.file("f.rawlog") +
                       ": 331 steps, 1211 sightings of 9 landmarks, with "
                       "ground truth\n");
  EXPECT_TRUE(fileExists(tmp.file("f_ground_truth.txt")));
  EXPECT_FALSE(fileExists(tmp.file("f_ground_truth_robot_path.txt")));
  const auto ini = readFile(tmp.file("f.ini"));
  EXPECT_NE(ini.find("[RangeBearingKFSLAM]\nstd_sensor_range   = 0.1  // m, 1 sigma\n"
                     "std_sensor_yaw_deg = 5.72957795  // deg, 1 sigma\n"),
            std::string::npos)
      << ini;
  EXPECT_NE(ini.find("# Made by budget-convert --format freiburg from world.dat and "
                     "sensor_data.dat."),
            std::string::npos);
}

TEST(Tools, ConvertReportsBadInputOnOneLine) {
  TempDir tmp;
  const auto f = writeFile(tmp.file("vp.txt"),
                           "ODOMETRY 0 1 1 0 0 0.01 0 0 0.01 0 0.01\n"
                           "LANDMARK 1 5 1 oops 0.1 0 0.1\n");
  auto r = runTool(
      tmp, bin("budget-convert") + " --format isam '" + f + "' -o '" + tmp.file("o.rawlog") + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "budget-convert: " + f + ":2: y is not a number: 'oops'\n");
  EXPECT_FALSE(fileExists(tmp.file("o.rawlog")));
  // Bad command lines (wrong number of inputs, an output that is no .rawlog): exit 2.
  r = runTool(tmp, bin("budget-convert") + " --format isam a b -o '" + tmp.file("o.rawlog") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err,
            "budget-convert: --format isam takes one file (victoria_park.txt), got 2 "
            "input(s); see budget-convert --help\n");
  r = runTool(tmp,
              bin("budget-convert") + " --format isam '" + f + "' -o '" + tmp.file("o.txt") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "budget-convert: output '" + tmp.file("o.txt") +
                       "': the rawlog name must end in .rawlog; see budget-convert --help\n");
  r = runTool(tmp, bin("budget-convert") + " --format csv x -o y.rawlog");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(Tools, SimulateIsReproducibleAndChecksItsOptions) {
  TempDir tmp;
  const std::string cmd = bin("budget-simulate") + " --scenario paper-synthetic --seed 5 -o '";
  auto r = runTool(tmp, cmd + tmp.file("a.rawlog") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, tmp.file("a.rawlog") + ": 96 steps of scenario paper-synthetic\n");
  ASSERT_EQ(runTool(tmp, cmd + tmp.file("b.rawlog") + "'").status, 0);
  EXPECT_TRUE(readFile(tmp.file("a.rawlog")) == readFile(tmp.file("b.rawlog")));
  EXPECT_NE(readFile(tmp.file("a.ini"))
                .find("# Made by budget-simulate --scenario "
                      "paper-synthetic --seed 5."),
            std::string::npos);
  r = runTool(tmp, bin("budget-simulate") + " --scenario mars -o x.rawlog");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  r = runTool(tmp, bin("budget-simulate") + " --scenario rooms -o /nonexistent/x.rawlog");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err,
            "budget-simulate: cannot write '/nonexistent/x.rawlog' (No such file or directory)\n");
}

namespace {

/// Ground-truth landmark ids and positions of a simulated rawlog (x, y in columns 0-1, id in 6).
std::map<long, std::pair<double, double>> truthOf(const std::string& file) {
  std::map<long, std::pair<double, double>> out;
  std::istringstream in(readFile(file));
  double x, y, z, a, b, c, id;
  while (in >> x >> y >> z >> a >> b >> c >> id) out[static_cast<long>(id)] = {x, y};
  return out;
}

}  // namespace

TEST(Tools, SimulateSessionsChangeTheWorldAsTheChangesFileSays) {
  TempDir tmp;
  const std::string cmd = bin("budget-simulate") + " --scenario rooms --seed 4 --sessions 3 " +
                          "--change 0.1 -o '" + tmp.file("life.rawlog") + "'";
  auto r = runTool(tmp, cmd);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, tmp.file("life_s01.rawlog") + ": 424 steps of scenario rooms\n" +
                       tmp.file("life_s02.rawlog") + ": 424 steps of scenario rooms\n" +
                       tmp.file("life_s03.rawlog") + ": 424 steps of scenario rooms\n" +
                       tmp.file("life_changes.csv") + ": the changes\n");
  // Session 1 is the world and noise of a single run of the same options.
  ASSERT_EQ(runTool(tmp, bin("budget-simulate") + " --scenario rooms --seed 4 -o '" +
                             tmp.file("one.rawlog") + "'")
                .status,
            0);
  EXPECT_TRUE(readFile(tmp.file("one.rawlog")) == readFile(tmp.file("life_s01.rawlog")));
  EXPECT_FALSE(readFile(tmp.file("life_s02.rawlog")) == readFile(tmp.file("life_s01.rawlog")));
  // Each session's ground truth is the previous one with the listed changes applied: 10% of
  // the 155 landmarks (16, as 6 disappear, 5 move by 1 m, 5 appear) before sessions 2 and 3.
  std::istringstream changes(readFile(tmp.file("life_changes.csv")));
  std::string line;
  std::getline(changes, line);
  EXPECT_EQ(line, "session,change,id,x_before,y_before,x_after,y_after");
  auto truth = truthOf(tmp.file("life_s01_ground_truth.txt"));
  EXPECT_EQ(truth.size(), 155u);
  std::map<std::string, int> kinds;
  int session = 2;
  const auto checkSession = [&](int s) {
    const auto next = truthOf(tmp.file("life_s0" + std::to_string(s) + "_ground_truth.txt"));
    EXPECT_EQ(next.size(), truth.size()) << s;
    for (const auto& [id, p] : next) {
      ASSERT_TRUE(truth.count(id)) << "session " << s << ": landmark " << id << " not listed";
      EXPECT_NEAR(p.first, truth[id].first, 1e-9);
      EXPECT_NEAR(p.second, truth[id].second, 1e-9);
    }
  };
  while (std::getline(changes, line)) {
    std::istringstream row(line);
    std::string cell[7];
    for (auto& c : cell) std::getline(row, c, ',');
    const int s = std::stoi(cell[0]);
    if (s != session) checkSession(session), session = s;
    kinds[cell[1] + std::to_string(s)]++;
    const long id = std::stol(cell[2]);
    if (cell[1] != "appeared") {
      ASSERT_TRUE(truth.count(id)) << line;
      EXPECT_NEAR(truth[id].first, std::stod(cell[3]), 1e-9) << line;
    }
    if (cell[1] == "disappeared") truth.erase(id);
    if (cell[1] == "moved")
      EXPECT_NEAR(std::hypot(std::stod(cell[5]) - std::stod(cell[3]),
                             std::stod(cell[6]) - std::stod(cell[4])),
                  1.0, 1e-5)
          << line;
    if (cell[1] != "disappeared") truth[id] = {std::stod(cell[5]), std::stod(cell[6])};
  }
  checkSession(session);
  EXPECT_EQ(session, 3);
  EXPECT_EQ(kinds["disappeared2"], 6);
  EXPECT_EQ(kinds["moved2"], 5);
  EXPECT_EQ(kinds["appeared2"], 5);
  // The same command gives the same bytes, and writes over its own files.
  const std::string before = readFile(tmp.file("life_s03.rawlog"));
  ASSERT_EQ(runTool(tmp, cmd).status, 0);
  EXPECT_TRUE(before == readFile(tmp.file("life_s03.rawlog")));
  EXPECT_NE(readFile(tmp.file("life_s02.ini")).find("# Session 2 of 3 sessions, change 0.1"),
            std::string::npos);
}

TEST(Tools, SimulateSessionsNeverWriteOverAForeignFileAndCheckTheirOptions) {
  TempDir tmp;
  writeFile(tmp.file("mine_s02_ground_truth.txt"), "someone else's\n");
  auto r = runTool(tmp, bin("budget-simulate") + " --scenario rooms --sessions 2 -o '" +
                            tmp.file("mine.rawlog") + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "budget-simulate: '" + tmp.file("mine_s02_ground_truth.txt") +
                       "': exists and was not written by budget-simulate; not written over\n");
  EXPECT_FALSE(fileExists(tmp.file("mine_s01.rawlog")));  // nothing written before the check
  EXPECT_EQ(readFile(tmp.file("mine_s02_ground_truth.txt")), "someone else's\n");
  writeFile(tmp.file("x_changes.csv"), "a,b\n");
  r = runTool(tmp, bin("budget-simulate") + " --scenario rooms --sessions 2 -o '" +
                       tmp.file("x.rawlog") + "'");
  EXPECT_EQ(r.err, "budget-simulate: '" + tmp.file("x_changes.csv") +
                       "': exists and was not written by budget-simulate; not written over\n");
  writeFile(tmp.file("single.rawlog"), "not a rawlog\n");  // the single-run mode too
  r = runTool(tmp,
              bin("budget-simulate") + " --scenario rooms -o '" + tmp.file("single.rawlog") + "'");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(readFile(tmp.file("single.rawlog")), "not a rawlog\n");
  const std::string sim = bin("budget-simulate") + " --scenario rooms -o '" + tmp.file("y.rawlog");
  for (const auto& [args, error] : std::vector<std::pair<std::string, std::string>>{
           {"' --sessions 0", "--sessions 0: must be 1 to 999"},
           {"' --sessions 1000", "--sessions 1000: must be 1 to 999"},
           {"' --sessions 2 --change 1.5", "--change 1.5: must be a share in [0, 1]"},
           {"' --sessions 2 --change -0.1", "--change -0.1: must be a share in [0, 1]"},
           {"' --change 0.2", "--change needs --sessions N"},
           {"' --joined", "--joined needs --sessions N"},
           {"' --sessions 2 --change-split 1:x:1",
            "--change-split '1:x:1': expected three shares D:M:A (disappear, move, appear), "
            "each >= 0, not all 0"},
           {"' --sessions 2 --change-split 0:0:0",
            "--change-split '0:0:0': expected three shares D:M:A (disappear, move, appear), "
            "each >= 0, not all 0"},
           {"' --sessions 2 --move-distance 0", "--move-distance 0: must be a finite number > 0"},
       }) {
    r = runTool(tmp, sim + args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_EQ(r.err, "budget-simulate: " + error + "; see budget-simulate --help\n") << args;
  }
  r = runTool(tmp, bin("budget-simulate") + " --scenario lifelong --sessions 2 -o '" +
                       tmp.file("z.rawlog") + "'");
  EXPECT_EQ(r.err,
            "budget-simulate: --sessions: scenario lifelong changes between its laps already; "
            "use another scenario; see budget-simulate --help\n");
  EXPECT_FALSE(fileExists(tmp.file("y_s01.rawlog")));
}

TEST(Tools, SimulateSessionsJoinedIsOneTraversalEndingInTheLastWorld) {
  TempDir tmp;
  auto r = runTool(tmp, bin("budget-simulate") + " --scenario rooms --seed 2 --sessions 3 " +
                            "--change 0.2 --joined -o '" + tmp.file("j.rawlog") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  // One standing first step, then three times the 423 moving steps of a session.
  EXPECT_EQ(r.out, tmp.file("j.rawlog") + ": 1268 steps of scenario rooms\n" +
                       tmp.file("j_changes.csv") + ": the changes\n");
  ASSERT_EQ(runTool(tmp, bin("budget-simulate") + " --scenario rooms --seed 2 --sessions 3 " +
                             "--change 0.2 -o '" + tmp.file("s.rawlog") + "'")
                .status,
            0);
  EXPECT_EQ(readFile(tmp.file("j_changes.csv")), readFile(tmp.file("s_changes.csv")));
  EXPECT_EQ(truthOf(tmp.file("j_ground_truth.txt")), truthOf(tmp.file("s_s03_ground_truth.txt")));
}

TEST(Tools, SessionChangeOptionsLoadFromAnIniWithTheirChecks) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("SimulationSessions", "sessions", "20");
  ini.write("SimulationSessions", "change", "0.05");
  ini.write("SimulationSessions", "share_move", "0");
  budget_slam::dataset::SessionChangeOptions o;
  o.loadFromConfigFile(ini, "SimulationSessions");
  EXPECT_EQ(o.sessions, 20);
  EXPECT_EQ(o.change, 0.05);
  EXPECT_EQ(o.share_move, 0);
  EXPECT_EQ(o.share_appear, 1);
  ini.write("SimulationSessions", "change", "2");
  try {
    o.loadFromConfigFile(ini, "SimulationSessions");
    ADD_FAILURE() << "change = 2 accepted";
  } catch (const budget_slam::ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "[SimulationSessions] change = 2: must be at most 1");
  }
}
