#include <gtest/gtest.h>

#include "AppTestUtil.h"

using namespace budget_slam::testing;

// compare --offline-optimum on rooms (Hochdorfer's layout) at cap 50: the bound row is there,
// no capped map beats it, and place-coverage under newly_added/compete comes within 10 % of it.
TEST(OfflineOptimum, CompareAddsTheBoundRowAboveEveryCappedMap) {
  const auto dir = freshDir("offline_optimum");
  const auto r = runApp({"compare",
                         "-c",
                         kRoot + "/config.ini",
                         "-i",
                         kRoot + "/rawlogs/rooms.rawlog",
                         "-o",
                         dir.string(),
                         "--cap",
                         "50",
                         "--reducers",
                         "random,place-coverage",
                         "--offline-optimum",
                         "--quiet",
                         "--threads",
                         "2",
                         "--set",
                         "LandmarkBudget.shadow_reducers=",
                         "--set",
                         "LandmarkBudget.protect=newly_added",
                         "--set",
                         "LandmarkBudget.admission=compete",
                         "--set",
                         "MappingApplication.save_3d_scene=false"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = readCsv(dir / "offline_optimum.csv");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0][0], "reference");
  EXPECT_EQ(rows[1][0], "random");
  EXPECT_EQ(rows[2][0], "place-coverage");
  EXPECT_EQ(rows[3][0], "offline optimum");
  const double best = std::stod(rows[3][2]);
  EXPECT_LE(std::stoul(rows[3][1]), 50u);
  EXPECT_GT(best, 0);
  EXPECT_GE(std::stod(rows[0][2]), best);  // the unreduced map holds every selection
  for (std::size_t i = 1; i <= 2; ++i) {
    EXPECT_EQ(std::stoul(rows[i][1]), 50u);
    EXPECT_LE(std::stod(rows[i][2]), best);
  }
  EXPECT_GE(std::stod(rows[2][3]), 90.0);
  EXPECT_GT(std::stod(rows[2][2]), std::stod(rows[1][2]));
  EXPECT_NE(slurp(dir / "comparison.md").find("| offline optimum |"), std::string::npos);
}

TEST(OfflineOptimum, OnlyCompareTakesTheFlag) {
  const auto dir = freshDir("offline_optimum_run");
  const auto r =
      runApp({"run", "-c", kRoot + "/config.ini", "-o", dir.string(), "--offline-optimum"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("offline-optimum"), std::string::npos) << r.err;
}
