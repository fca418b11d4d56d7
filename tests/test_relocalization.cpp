// Relocalization: the coverage of a final map (counted by hand on a made-up rawlog), budget-slam
// localize on the shipped second traversals, and compare --relocalize (docs/OUTPUTS.md).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>

#include "AppTestUtil.h"
#include "budget_slam/dataset/RawlogWriter.h"
#include "budget_slam/dataset/StepToMrpt.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

const std::string kRooms = kRoot + "/rawlogs/rooms.rawlog";
const std::string kRoomsRevisit = kRoot + "/rawlogs/rooms_revisit.rawlog";
const std::string kConfig = kRoot + "/config.ini";

/// Three places 20 m apart, three landmarks each (A: 1-3, B: 4-6, C: 7-9), visited A x4, B x3,
/// C x5, A x2 (14 steps), with exact readings. With a cap of 6 and the `oldest` reducer (nothing
/// protected past its step), C drives A out and A's return drives B out: the final map holds A
/// and C. Counted by hand, k = 2: the 6 steps at A and the 5 at C see 3 final-map landmarks, the
/// 3 at B none: coverage 11 / 14, mean 33 / 14.
std::string writeThreePlaces(const fs::path& dir, bool with_ids) {
  fs::create_directories(dir);
  const std::string path = (dir / (with_ids ? "places.rawlog" : "places_noids.rawlog")).string();
  const std::vector<std::vector<Eigen::Vector2d>> offsets = {
      {{1.0, 0.5}, {1.5, -0.6}, {2.2, 0.2}},
      {{0.8, -0.4}, {1.7, 0.7}, {2.4, -0.3}},
      {{1.2, 0.9}, {1.9, -0.2}, {0.9, -0.8}}};
  const double place_x[3] = {0, 20, 40};
  const int visits[][2] = {{0, 4}, {1, 3}, {2, 5}, {0, 2}};
  std::vector<Step> steps;
  double x = 0;
  for (const auto& [place, count] : visits)
    for (int i = 0; i < count; ++i) {
      OdometryIncrement odo;
      odo.mean = Pose2(i == 0 ? place_x[place] - x : 0, 0, 0);
      odo.cov = Eigen::Vector3d(1e-4, 1e-4, 1e-6).asDiagonal();
      x = place_x[place];
      RangeBearingScan scan;
      scan.min_range = 0.1;
      scan.max_range = 3;
      scan.fov_yaw = M_PI;
      scan.std_range = 0.01;
      scan.std_yaw = 0.01;
      for (int l = 0; l < 3; ++l) {
        const Eigen::Vector2d d = offsets[place][l];
        scan.readings.push_back(
            {with_ids ? 3 * place + l + 1 : kNoLandmarkId, d.norm(), std::atan2(d.y(), d.x()), 0});
      }
      steps.push_back(dataset::makeStep(steps.size(), steps.size() + 1.0, odo, scan));
    }
  dataset::writeRawlog(path, steps);
  return path;
}

const std::vector<std::string> kThreePlacesSets = {
    "--set", "LandmarkBudget.protect_recent_steps=1",
    "--set", "RangeBearingKFSLAM.std_sensor_range=0.01",
    "--set", "RangeBearingKFSLAM.std_sensor_yaw_deg=0.5"};

std::vector<std::string> withSets(std::vector<std::string> args) {
  args.insert(args.end(), kThreePlacesSets.begin(), kThreePlacesSets.end());
  return args;
}

/// Column `name` of every row of a CSV file.
std::vector<std::string> column(const fs::path& csv, const std::string& name) {
  std::istringstream in(slurp(csv));
  std::string header;
  std::getline(in, header);
  std::vector<std::string> names;
  std::stringstream hs(header);
  for (std::string c; std::getline(hs, c, ',');) names.push_back(c);
  const auto at = std::find(names.begin(), names.end(), name) - names.begin();
  std::vector<std::string> out;
  for (const auto& row : readCsv(csv)) out.push_back(at < long(row.size()) ? row[at] : "");
  return out;
}

/// The unreduced EKF map of rooms, made once for the localize tests.
const fs::path& roomsMap() {
  // One folder per process: ctest runs each test in its own process, in parallel, and two
  // processes sharing one folder would delete each other's map.
  static const fs::path dir = [] {
    const auto d = freshDir("reloc_rooms_map_" + std::to_string(::getpid()));
    const auto r = runApp(
        {"run", "-c", kConfig, "-i", kRooms, "-o", d.string(), "--reducer", "none", "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return d;
  }();
  return dir;
}

nlohmann::json localize(const std::string& name, const fs::path& map,
                        std::vector<std::string> extra = {}) {
  const auto out = freshDir(name);
  std::vector<std::string> args = {"localize", "-c",          kConfig, "--map",      map.string(),
                                   "-i",       kRoomsRevisit, "-o",    out.string(), "--quiet"};
  args.insert(args.end(), extra.begin(), extra.end());
  const auto r = runApp(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return readJson(out / "summary.json");
}

}  // namespace

TEST(Relocalization, CoverageOfThreePlacesCountedByHand) {
  const auto dir = freshDir("reloc_places");
  const auto rawlog = writeThreePlaces(dir / "data", true);
  const auto out = dir / "run";
  const auto r = runApp(withSets({"run", "-c", kConfig, "-i", rawlog, "-o", out.string(),
                                  "--reducer", "oldest", "--cap", "6", "--quiet"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["counts"]["landmarks_final"], 6);
  const auto& c = s["relocalization"];
  EXPECT_EQ(c["source"], "landmark_ids");
  EXPECT_EQ(c["steps"], 14);
  EXPECT_EQ(c["steps_covered"], 11);
  EXPECT_DOUBLE_EQ(c["coverage_pct"].get<double>(), 100.0 * 11 / 14);
  EXPECT_DOUBLE_EQ(c["mean_landmarks"].get<double>(), 33.0 / 14);
  // Over time: the map held at step t against the steps up to t. Step 7 (first at C): A is out,
  // 4 of 8 steps covered; step 12 (back at A, same ids): 10 of 13; step 13: 11 of 14.
  const auto so_far = column(out / "steps.csv", "reloc_coverage_so_far_pct");
  const auto seen = column(out / "steps.csv", "reloc_landmarks");
  ASSERT_EQ(so_far.size(), 14u);
  EXPECT_DOUBLE_EQ(std::stod(so_far[6]), 100.0);
  EXPECT_DOUBLE_EQ(std::stod(so_far[7]), 50.0);
  EXPECT_DOUBLE_EQ(std::stod(so_far[12]), 100.0 * 10 / 13);
  EXPECT_DOUBLE_EQ(std::stod(so_far[13]), 100.0 * 11 / 14);
  for (const auto& n : seen) EXPECT_EQ(n, "3");  // every step sees the map of its own time
  EXPECT_TRUE(fs::exists(out / "map.png"));

  // k = 4: no step sees four.
  const auto out4 = dir / "run_k4";
  ASSERT_EQ(runApp(withSets({"run", "-c", kConfig, "-i", rawlog, "-o", out4.string(), "--reducer",
                             "oldest", "--cap", "6", "--quiet", "--set",
                             "Metrics.reloc_min_landmarks=4"}))
                .exit_code,
            0);
  EXPECT_EQ(readJson(out4 / "summary.json")["relocalization"]["steps_covered"], 0);
}

// Without sensor IDs a landmark seen again after its drop is a new landmark: the run's own
// association no longer links A's first four steps to the final map (7 of 14 covered), while the
// reference run's association does (compare: 11 of 14, as with IDs).
TEST(Relocalization, IdLessRawlogGoesThroughTheReferenceAssociation) {
  const auto dir = freshDir("reloc_places_noids");
  const auto rawlog = writeThreePlaces(dir / "data", false);
  const auto run_out = dir / "run";
  ASSERT_EQ(runApp(withSets({"run", "-c", kConfig, "-i", rawlog, "-o", run_out.string(),
                             "--reducer", "oldest", "--cap", "6", "--quiet"}))
                .exit_code,
            0);
  const auto own = readJson(run_out / "summary.json")["relocalization"];
  EXPECT_EQ(own["source"], "own_association");
  EXPECT_EQ(own["steps_covered"], 7);

  const auto cmp = dir / "compare";
  const auto r = runApp(withSets({"compare", "-c", kConfig, "-i", rawlog, "-o", cmp.string(),
                                  "--reducers", "oldest", "--cap", "6", "--quiet"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto c = readJson(cmp / "oldest" / "summary.json")["relocalization"];
  EXPECT_EQ(c["source"], "reference_association");
  EXPECT_EQ(c["landmarks_matched_to_reference"], 6);
  EXPECT_EQ(c["steps_covered"], 11);
  EXPECT_DOUBLE_EQ(c["coverage_pct"].get<double>(), 100.0 * 11 / 14);
  const auto ref = readJson(cmp / "reference" / "summary.json")["relocalization"];
  EXPECT_EQ(ref["steps_covered"], 14);
  const auto pct = column(cmp / "comparison.csv", "reloc_coverage_pct");
  ASSERT_EQ(pct.size(), 2u);
  EXPECT_DOUBLE_EQ(std::stod(pct[0]), 100.0);
  EXPECT_DOUBLE_EQ(std::stod(pct[1]), 100.0 * 11 / 14);
}

// The unreduced map of rooms localizes the revisit (another start, another path through the three
// rooms, other noise) from the ground truth's start brought into the map's frame. Bounds: 0.2 m
// RMSE and 0.5 m at worst (about 7 and 17 times the 0.03 m range noise; measured 0.09 and 0.20 m)
// and no step lost; the map covers 74% of the revisit's steps with 2 landmarks (measured).
TEST(Relocalization, LocalizeRoomsRevisitInTheUnreducedMap) {
  const auto s = localize("reloc_localize_rooms", roomsMap());
  EXPECT_EQ(s["status"], "ok");
  EXPECT_EQ(s["start_pose"]["source"], "ground truth");
  EXPECT_EQ(s["counts"]["steps"], 318);
  const auto& l = s["localization"];
  EXPECT_EQ(l["error_against"], "ground_truth");
  EXPECT_LT(l["rmse_m"].get<double>(), 0.2);
  EXPECT_LT(l["max_m"].get<double>(), 0.5);
  EXPECT_EQ(l["lost_pct"].get<double>(), 0.0);
  EXPECT_GT(l["coverage_pct"].get<double>(), 60.0);
  EXPECT_GT(l["readings_used"].get<int>(), 1500);
  EXPECT_TRUE(l["nees_mean"].is_number());
  const auto out = fs::temp_directory_path() / "budget_slam_tests" / "reloc_localize_rooms";
  for (const char* f : {"trajectory.tum", "ground_truth.tum", "steps.csv", "landmarks.csv",
                        "map.png", "config_used.ini"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_EQ(readCsv(out / "steps.csv").size(), 318u);
}

// An empty map: the robot dead-reckons from its true start and loses its place.
TEST(Relocalization, EmptyMapReportsTheShareLost) {
  const auto empty = freshDir("reloc_empty_map");
  fs::create_directories(empty);
  std::ofstream(empty / "landmarks.csv")
      << slurp(roomsMap() / "landmarks.csv")
             .substr(0, slurp(roomsMap() / "landmarks.csv").find('\n') + 1);
  fs::copy_file(roomsMap() / "summary.json", empty / "summary.json");
  const auto s = localize("reloc_localize_empty", empty);
  const auto& l = s["localization"];
  EXPECT_EQ(s["counts"]["map_landmarks"], 0);
  EXPECT_EQ(l["coverage_pct"].get<double>(), 0.0);
  EXPECT_EQ(l["readings_used"], 0);
  EXPECT_GT(l["lost_pct"].get<double>(), 20.0);
  EXPECT_LT(l["lost_pct"].get<double>(), 100.0);  // the first steps are still near the start
  EXPECT_EQ(l["steps_compared"], 318);
}

// A start 6 m and 150 deg off. Without the innovation gate MRPT's filter is dragged by the
// first readings and loses steps; with the gate and no recovery the readings are never trusted
// again and every step is lost; with the default recovery the pose is solved afresh from the
// rejected readings within a few steps. Never a crash.
TEST(Relocalization, WrongStartPoseIsRecoveredNotACrash) {
  const auto s = localize("reloc_localize_wrong_start", roomsMap(),
                          {"--start-pose", "5,-2,150", "--set", "Localization.gate_chi2=0"});
  EXPECT_EQ(s["status"], "ok");
  EXPECT_EQ(s["start_pose"]["source"], "--start-pose");
  EXPECT_GT(s["localization"]["steps_lost"].get<int>(), 0);
  const auto out = fs::temp_directory_path() / "budget_slam_tests" / "reloc_localize_wrong_start";
  EXPECT_EQ(column(out / "steps.csv", "lost")[0], "1");
  const auto gated =
      localize("reloc_localize_wrong_start_gate", roomsMap(),
               {"--start-pose", "5,-2,150", "--set", "Localization.recover_after_steps=0"});
  EXPECT_EQ(gated["status"], "ok");
  EXPECT_EQ(gated["localization"]["lost_pct"].get<double>(), 100.0);
  EXPECT_GT(gated["localization"]["readings_gated"].get<int>(), 1000);
  EXPECT_EQ(gated["localization"]["recoveries"], 0);
  const auto recovered =
      localize("reloc_localize_wrong_start_recovered", roomsMap(), {"--start-pose", "5,-2,150"});
  EXPECT_EQ(recovered["status"], "ok");
  EXPECT_GE(recovered["localization"]["recoveries"].get<int>(), 1);
  EXPECT_LT(recovered["localization"]["lost_pct"].get<double>(), 5.0);
  const auto rec =
      fs::temp_directory_path() / "budget_slam_tests" / "reloc_localize_wrong_start_recovered";
  const auto flags = column(rec / "steps.csv", "recovered");
  const auto first = std::find(flags.begin(), flags.end(), "1") - flags.begin();
  EXPECT_LT(first, 20) << "recovered at step " << first;
  EXPECT_EQ(column(rec / "steps.csv", "lost")[first + 1], "0");
}

TEST(Relocalization, MapFolderWithoutLandmarksIsOneLineError) {
  const auto map = freshDir("reloc_no_landmarks");
  fs::create_directories(map);
  const auto out = freshDir("reloc_no_landmarks_out");
  const auto r = runApp({"localize", "-c", kConfig, "--map", map.string(), "-i", kRoomsRevisit,
                         "-o", out.string(), "--quiet"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(
      isErrorLine(r.err, (map / "landmarks.csv").string() + ": cannot open (no such file)"));
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["status"], "failed");
  EXPECT_EQ(s["error"], (map / "landmarks.csv").string() + ": cannot open (no such file)");

  std::ofstream(map / "landmarks.csv") << "id,x,y\n1,2,3\n";
  const auto bad = runApp({"localize", "-c", kConfig, "--map", map.string(), "-i", kRoomsRevisit,
                           "-o", out.string(), "--quiet", "--force"});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_TRUE(isErrorLine(bad.err, (map / "landmarks.csv").string() +
                                       ":1: not a budget-slam landmarks.csv header: 'id,x,y'"));
  EXPECT_EQ(runApp({"localize", "-c", kConfig, "--map", map.string(), "-i", kRoomsRevisit,
                    "--start-pose", "1,2", "-o", out.string()})
                .err,
            "budget-slam: --start-pose '1,2': expected x,y,yaw (metres, metres, degrees); see "
            "budget-slam localize --help\n");
}

// compare --relocalize: the reference's final map and every reducer's localize the revisit;
// every row has the new columns, the reference's ratios are 1, and each localization has its
// folder under its run's.
TEST(Relocalization, CompareRelocalizeFillsEveryRowTheReferenceIncluded) {
  const auto out = freshDir("reloc_compare");
  const auto r =
      runApp({"compare", "-c", kConfig, "-i", kRooms, "-o", out.string(), "--reducers",
              "oldest,coverage", "--cap", "50", "--relocalize", kRoomsRevisit, "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto runs = column(out / "comparison.csv", "run");
  ASSERT_EQ(runs, (std::vector<std::string>{"reference", "oldest", "coverage"}));
  for (const char* c :
       {"reloc_coverage_pct", "reloc_mean_landmarks", "reloc_rmse_m", "reloc_max_m",
        "reloc_lost_pct", "reloc_traversal_coverage_pct", "reloc_rmse_ratio", "reloc_lost_ratio"}) {
    const auto v = column(out / "comparison.csv", c);
    ASSERT_EQ(v.size(), 3u) << c;
    for (std::size_t i = 0; i < v.size(); ++i) {
      // The lost ratio of a map that loses steps where the reference's lost none is undefined.
      if (std::string(c) == "reloc_lost_ratio" && i > 0) continue;
      ASSERT_FALSE(v[i].empty()) << c << " of " << runs[i];
      EXPECT_TRUE(std::isfinite(std::stod(v[i]))) << c << " of " << runs[i] << ": " << v[i];
    }
  }
  const auto lost = column(out / "comparison.csv", "reloc_lost_pct");
  const auto lost_ratio = column(out / "comparison.csv", "reloc_lost_ratio");
  const auto rmse = column(out / "comparison.csv", "reloc_rmse_m");
  const auto rmse_ratio = column(out / "comparison.csv", "reloc_rmse_ratio");
  EXPECT_EQ(std::stod(rmse_ratio[0]), 1.0);
  EXPECT_EQ(std::stod(lost_ratio[0]), 1.0);
  for (std::size_t i = 1; i < 3; ++i) {
    EXPECT_NEAR(std::stod(rmse_ratio[i]), std::stod(rmse[i]) / std::stod(rmse[0]), 1e-12);
    if (std::stod(lost[0]) > 0)
      EXPECT_NEAR(std::stod(lost_ratio[i]), std::stod(lost[i]) / std::stod(lost[0]), 1e-12);
    else if (std::stod(lost[i]) > 0)
      EXPECT_TRUE(lost_ratio[i].empty() || lost_ratio[i] == "nan") << lost_ratio[i];
  }
  // The capped maps keep a share of the rooms: they cover fewer steps than the reference's.
  const auto cov = column(out / "comparison.csv", "reloc_traversal_coverage_pct");
  EXPECT_GT(std::stod(cov[0]), std::stod(cov[1]));
  EXPECT_GT(std::stod(cov[0]), std::stod(cov[2]));

  const auto rows = readCsv(out / "relocalization.csv");
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& row : rows) EXPECT_EQ(row[1], "rooms_revisit");
  for (const auto& run : runs) {
    const auto s = readJson(out / run / "relocalize" / "rooms_revisit" / "summary.json");
    EXPECT_EQ(s["status"], "ok") << run;
    EXPECT_EQ(s["run"], run);
  }
  EXPECT_NE(slurp(out / "comparison.md").find("reloc RMSE (m)"), std::string::npos);
}
