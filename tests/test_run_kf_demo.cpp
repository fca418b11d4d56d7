// The foundation's end-to-end checks on MRPT's kf-slam demo rawlog (issue 2 "Done when").
#include <gtest/gtest.h>

#include <cstdlib>
#include <set>

#include <Eigen/Dense>

#include "AppTestUtil.h"
#include "budget_slam/reducers/BuiltinReducers.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {
/// Last row of trajectory.tum as x, y, yaw.
std::array<double, 3> lastTumPose(const fs::path& tum) {
  std::istringstream in(slurp(tum));
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  std::istringstream ls(last);
  double t, x, y, z, qx, qy, qz, qw;
  ls >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
  return {x, y, 2 * std::atan2(qz, qw)};
}

/// Runs MRPT's kf-slam app and `budget-slam run --reducer none` (plus `extra` arguments) on the
/// demo with MRPT's EKF-SLAM_test_2d.ini: the last poses agree to 1e-6 (kf-slam writes them
/// with 6 decimals), and the run is unreduced and accurate.
void expectLastPoseOfKfSlamApp(const std::string& name, const std::vector<std::string>& extra) {
  const auto dir = freshDir(name);
  fs::create_directories(dir);
  // kf-slam saves robot_pose_<step>.txt every SAVE_LOG_FREQUENCY steps; 1 gives the last step.
  std::string ini = slurp(kMrptIni);
  ini +=
      "\n[MappingApplication]\nSHOW_3D_LIVE=false\nSAVE_LOG_FREQUENCY=1\nSAVE_3D_SCENES=false\n"
      "logOutput_dir=" +
      (dir / "kf").string() + "\n";
  std::ofstream(dir / "kf.ini") << ini;
  const std::string cmd = "kf-slam " + (dir / "kf.ini").string() + " " + kDemo + " > " +
                          (dir / "kf.log").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "kf.log");
  std::istringstream pose(slurp(dir / "kf" / "robot_pose_00248.txt"));
  double kx, ky, kyaw;
  pose >> kx >> ky >> kyaw;
  ASSERT_TRUE(pose) << "kf-slam wrote no pose for step 248";

  std::vector<std::string> args = {
      "run",       "-c",   kMrptIni, "-i", kDemo, "-o", (dir / "ours").string(),
      "--reducer", "none", "--quiet"};
  args.insert(args.end(), extra.begin(), extra.end());
  const auto r = runApp(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto p = lastTumPose(dir / "ours" / "trajectory.tum");
  EXPECT_NEAR(p[0], kx, 1e-6);
  EXPECT_NEAR(p[1], ky, 1e-6);
  EXPECT_NEAR(std::remainder(p[2] - kyaw, 2 * M_PI), 0.0, 1e-6);
  const auto summary = readJson(dir / "ours" / "summary.json");
  EXPECT_EQ(summary["status"], "ok");
  EXPECT_EQ(summary["counts"]["steps"], 249);
  EXPECT_EQ(summary["counts"]["landmarks_final"], 70);
  EXPECT_EQ(summary["counts"]["evictions"], 0);
  // Unreduced EKF against simul-landmarks' ground truth: sub-decimetre on this easy set.
  EXPECT_LT(summary["ground_truth"]["trajectory_rmse_m"].get<double>(), 0.05);
  EXPECT_LT(summary["ground_truth"]["landmark_rmse_m"].get<double>(), 0.05);
}
}  // namespace

// Issue 2: with --reducer none and MRPT's EKF-SLAM_test_2d.ini, the last pose equals the one
// MRPT's kf-slam app writes in its robot_pose_*.txt, to 1e-6 (the default, sparse update).
TEST(RunKfDemo, NoReducerMatchesMrptKfSlamApp) { expectLastPoseOfKfSlamApp("kfslam_app", {}); }

// Issue 38: the exact mode, MRPT's own Kalman iteration ([EkfSLAM] update = mrpt), against kf-slam.
TEST(RunKfDemo, MrptUpdateMatchesMrptKfSlamApp) {
  expectLastPoseOfKfSlamApp("kfslam_app_mrpt_update", {"--set", "EkfSLAM.update=mrpt"});
}

// Issue 2: every step of steps.csv is at or under the cap, for every baseline; evictions.csv
// agrees with the counts; summary says ok.
TEST(RunKfDemo, EveryBaselineKeepsEveryStepUnderTheCap) {
  for (const std::string reducer : {"info-content", "random", "oldest"}) {
    const auto dir = freshDir("cap_" + reducer);
    const auto r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--reducer",
                           reducer, "--cap", "20", "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto steps = readCsv(dir / "steps.csv");
    ASSERT_EQ(steps.size(), 249u);
    std::size_t dropped = 0;
    for (const auto& row : steps) {
      EXPECT_LE(std::stoul(row[2]), 20u) << reducer << " step " << row[0];
      dropped += std::stoul(row[4]);
    }
    const auto evictions = readCsv(dir / "evictions.csv");
    EXPECT_EQ(evictions.size(), dropped);
    EXPECT_GT(dropped, 49u) << reducer;
    for (const auto& e : evictions) EXPECT_EQ(e[2], reducer);
    const auto summary = readJson(dir / "summary.json");
    EXPECT_EQ(summary["status"], "ok");
    EXPECT_EQ(summary["counts"]["landmarks_final"], 20);
  }
}

// Issue 2: readmission on: an evicted sensor ID seen again comes back as a new landmark;
// off: it never comes back.
TEST(RunKfDemo, ReadmissionOnAndOff) {
  for (const bool readmit : {true, false}) {
    const auto dir = freshDir(readmit ? "readmit_on" : "readmit_off");
    const auto r =
        runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--reducer", "oldest",
                "--cap", "15", "--quiet", "--set",
                std::string("LandmarkBudget.readmit_evicted=") + (readmit ? "true" : "false")});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::map<long, std::size_t> evicted_at;
    for (const auto& e : readCsv(dir / "evictions.csv"))
      evicted_at.emplace(std::stol(e[1]), std::stoul(e[0]));
    std::size_t came_back = 0;
    for (const auto& l : readCsv(dir / "landmarks.csv")) {
      const auto it = evicted_at.find(std::stol(l[0]));
      if (it == evicted_at.end()) continue;
      ++came_back;
      EXPECT_GT(std::stoul(l[9]), it->second) << "readmitted landmark keeps its old first_step";
    }
    const auto summary = readJson(dir / "summary.json");
    const std::size_t added = summary["counts"]["landmarks_added"];
    if (readmit) {
      EXPECT_GT(came_back, 0u);
      EXPECT_GT(added, 70u);  // re-sightings re-enter as new landmarks
    } else {
      EXPECT_EQ(came_back, 0u);
      EXPECT_EQ(added, 70u);  // each sensor ID enters the map once
    }
  }
}

TEST(RunKfDemo, ShadowReducersAreLoggedWithAgreement) {
  const auto dir = freshDir("shadows");
  const auto r =
      runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--reducer", "info-content",
              "--cap", "25", "--quiet", "--set", "LandmarkBudget.shadow_reducers=oldest,random"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto evictions = readCsv(dir / "evictions.csv");
  ASSERT_FALSE(evictions.empty());
  for (const auto& e : evictions) {
    ASSERT_EQ(e.size(), 9u);
    EXPECT_EQ(e[7].rfind("oldest:", 0), 0u) << e[7];
    EXPECT_NE(e[7].find(";random:"), std::string::npos) << e[7];
    EXPECT_EQ(e[8], "");  // no shadow failed
  }
  const auto summary = readJson(dir / "summary.json");
  ASSERT_EQ(summary["agreement"].size(), 3u);
  EXPECT_EQ(summary["agreement"][0]["a"], "info-content");
  EXPECT_EQ(summary["agreement"][0]["b"], "oldest");
  EXPECT_EQ(summary["agreement"][0]["total"], evictions.size());
}

// compare: the reference plus one row a reducer, every metric filled, one folder a run.
TEST(CompareKfDemo, WritesTableWithReferenceAndEveryReducer) {
  const auto dir = freshDir("compare_baselines");
  const std::vector<std::string> reducers = {"info-content", "random", "oldest"};
  const auto r = runApp({"compare", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--cap", "30",
                         "--reducers", "info-content,random,oldest", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto t = readCsvTable(dir / "comparison.csv");
  ASSERT_EQ(t.rows.size(), 1 + reducers.size());
  EXPECT_EQ(t.at(0, "run"), "reference");
  // Every column is filled but those of compare --relocalize; the error against ground truth leads.
  EXPECT_EQ(t.header[6], "gt_trajectory_rmse_aligned_m");
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    ASSERT_EQ(t.rows[i].size(), t.header.size());
    if (i > 0) {
      EXPECT_EQ(t.at(i, "run"), reducers[i - 1]);
    }
    EXPECT_EQ(t.at(i, "status"), "ok");
    for (std::size_t c = 0; c < t.header.size(); ++c) {
      if ((t.header[c] != "cap" && t.header[c].rfind("reloc_", 0) != 0) ||
          t.header[c] == "reloc_coverage_pct" || t.header[c] == "reloc_mean_landmarks") {
        EXPECT_FALSE(t.rows[i][c].empty() || t.rows[i][c] == "nan")
            << t.rows[i][0] << " column " << t.header[c];
      }
    }
    EXPECT_TRUE(fs::exists(dir / t.rows[i][0] / "summary.json"));
    EXPECT_TRUE(fs::exists(dir / t.rows[i][0] / "map.png"));
  }
  // The reference against itself is exact; a capped run keeps 30 of the 70 landmarks.
  EXPECT_EQ(std::stod(t.at(0, "ref_ate_m")), 0.0);
  EXPECT_EQ(t.at(0, "cap"), "");
  EXPECT_EQ(t.at(1, "landmarks"), "30");
  EXPECT_NEAR(std::stod(t.at(1, "landmarks_reduction_pct")), 100.0 * (1 - 30.0 / 70.0), 1e-9);
  EXPECT_GT(std::stod(t.at(1, "ref_ate_m")), 0.0);
  EXPECT_TRUE(fs::exists(dir / "comparison.md"));
  EXPECT_TRUE(fs::exists(dir / "comparison.png"));

  // Each run equals a plain `run` with the same reducer: same final map.
  const auto single = freshDir("compare_single_oldest");
  ASSERT_EQ(runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", single.string(), "--cap", "30",
                    "--reducer", "oldest", "--quiet"})
                .exit_code,
            0);
  EXPECT_EQ(slurp(single / "landmarks.csv"), slurp(dir / "oldest" / "landmarks.csv"));
  EXPECT_EQ(slurp(single / "trajectory.tum"), slurp(dir / "oldest" / "trajectory.tum"));
}

// Issue 3: compare with the six reducers writes the reference plus six rows, every metric filled.
TEST(CompareKfDemo, SixReducersEveryMetricFilled) {
  const auto dir = freshDir("compare_six");
  const std::vector<std::string> reducers = {"mi",           "coverage", "coverage-mi",
                                             "info-content", "random",   "oldest"};
  const auto r =
      runApp({"compare", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--reducers",
              "mi,coverage,coverage-mi,info-content,random,oldest", "--cap", "30", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto t = readCsvTable(dir / "comparison.csv");
  ASSERT_EQ(t.rows.size(), 7u);
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    EXPECT_EQ(t.at(i, "run"), i == 0 ? "reference" : reducers[i - 1]);
    for (const char* column :
         {"gt_trajectory_rmse_aligned_m", "gt_trajectory_rpe_10m_m", "landmarks", "evictions",
          "refused", "ref_ate_m", "ref_ale_m", "ref_are_deg", "ref_ud_pct", "ref_ud_std_factor",
          "ref_eig_min", "ref_eig_max", "gt_trajectory_rmse_m", "gt_landmark_rmse_aligned_m",
          "nees_mean", "time_s", "reloc_coverage_pct"})
      EXPECT_FALSE(t.at(i, column).empty() || t.at(i, column) == "nan")
          << t.at(i, "run") << " column " << column;
    if (i > 0) {
      EXPECT_EQ(t.at(i, "landmarks"), "30");
    }
  }
}

// Choudhary et al.'s active minimization (mi objective mode) runs once after the last step; at
// lambda = 0.95 and without a cap it drops 32 of the demo's 70 landmarks, as Algorithm 3 on the
// final EKF state says (the reducers' brute-force test checks the same number).
TEST(RunKfDemo, MiObjectiveModeRunsAlgorithm3AtTheEnd) {
  const auto dir = freshDir("mi_objective");
  const auto r =
      runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--reducer", "mi", "--cap",
              "none", "--quiet", "--set", "MutualInformationReducer.mode=objective", "--set",
              "MutualInformationReducer.lambda=0.95"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto evictions = readCsv(dir / "evictions.csv");
  ASSERT_EQ(evictions.size(), 32u);
  for (const auto& e : evictions) {
    EXPECT_EQ(e[6], "objective");
    EXPECT_EQ(e[0], "248");  // after the last step
  }
  const auto s = readJson(dir / "summary.json");
  EXPECT_EQ(s["counts"]["landmarks_final"], 38);
  EXPECT_TRUE(s["cap"].is_null());
}

namespace {
/// states/step_<k>.txt: ids, mean and covariance as the dump writes them.
struct DumpedState {
  std::vector<long> ids;
  Eigen::VectorXd mean;
  Eigen::MatrixXd cov;
};
DumpedState readState(const fs::path& p) {
  DumpedState s;
  std::istringstream in(slurp(p));
  std::string line;
  std::vector<std::vector<double>> rows;
  std::string section;
  while (std::getline(in, line)) {
    if (line.rfind("# ids:", 0) == 0) {
      std::istringstream ls(line.substr(6));
      for (long id; ls >> id;) s.ids.push_back(id);
    } else if (line.rfind("# ", 0) == 0) {
      section = line.substr(2);
    } else {
      std::istringstream ls(line);
      std::vector<double> v;
      for (double x; ls >> x;) v.push_back(x);
      if (section == "mean") s.mean = Eigen::Map<Eigen::VectorXd>(v.data(), v.size());
      if (section == "covariance") rows.push_back(v);
    }
  }
  s.cov.resize(rows.size(), rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < rows.size(); ++c) s.cov(r, c) = rows[r][c];
  return s;
}
}  // namespace

// dump_states: every drop event's state is on disk, and the mi score of its first victim can be
// recomputed by hand from it: 1/2 log2(det P_LL det (P^-1)_LL).
TEST(RunKfDemo, DumpedStatesReproduceTheMiScores) {
  const auto dir = freshDir("dump_states");
  const auto r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--reducer", "mi",
                         "--cap", "25", "--quiet", "--set", "LandmarkBudget.dump_states=true"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::size_t checked = 0;
  std::string last_step;
  for (const auto& e : readCsv(dir / "evictions.csv")) {
    if (e[0] == last_step) continue;  // only the first drop of each event
    last_step = e[0];
    const auto state = readState(dir / "states" / ("step_" + e[0] + ".txt"));
    ASSERT_EQ(state.cov.rows(), static_cast<Eigen::Index>(3 + 2 * state.ids.size()));
    ASSERT_EQ(state.mean.size(), state.cov.rows());
    if (state.cov(0, 0) == 0) continue;  // before the first motion P is singular
    const long victim = std::stol(e[1]);
    const auto it = std::find(state.ids.begin(), state.ids.end(), victim);
    ASSERT_NE(it, state.ids.end());
    const Eigen::Index row = 3 + 2 * (it - state.ids.begin());
    const Eigen::MatrixXd lambda = state.cov.inverse();
    const double ig = 0.5 * std::log2(state.cov.block(row, row, 2, 2).determinant() *
                                      lambda.block(row, row, 2, 2).determinant());
    EXPECT_NEAR(std::stod(e[3]), ig, 1e-6 * std::max(1.0, ig)) << "step " << e[0];
    ++checked;
  }
  EXPECT_GT(checked, 20u);
}

// keep_history = false (lifelong runs): the same map and the same NEES, no per-step records in
// memory; trajectory.tum then holds the last pose (every pose is in steps.csv).
TEST(RunKfDemo, WithoutHistoryTheResultsAreTheSame) {
  const auto with = freshDir("history_on"), without = freshDir("history_off");
  for (const auto& [dir, keep] : {std::pair{with, "true"}, std::pair{without, "false"}}) {
    const auto r = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", dir.string(), "--reducer",
                           "coverage", "--cap", "20", "--quiet", "--set",
                           std::string("MappingApplication.keep_history=") + keep});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_EQ(slurp(with / "landmarks.csv"), slurp(without / "landmarks.csv"));
  const auto a = readJson(with / "summary.json")["ground_truth"];
  const auto b = readJson(without / "summary.json")["ground_truth"];
  EXPECT_EQ(a["nees_mean"], b["nees_mean"]);
  EXPECT_EQ(a["nees_samples"], b["nees_samples"]);
  EXPECT_EQ(a["landmark_rmse_m"], b["landmark_rmse_m"]);
  std::istringstream tum(slurp(without / "trajectory.tum"));
  std::string line;
  int lines = 0;
  while (std::getline(tum, line)) ++lines;
  EXPECT_EQ(lines, 1);
}
