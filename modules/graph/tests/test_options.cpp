#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/graph/GraphBackend.h"

using namespace budget_slam;
using namespace budget_slam::graph;

TEST(GraphOptions, DefaultsAndValues) {
  mrpt::config::CConfigFileMemory ini(
      "[GraphSLAM]\nsolver = levenberg-marquardt\nrelinearize_every = 25  // poses\n"
      "prior_std_yaw_deg = 0.5\n[RangeBearingKFSLAM]\nstd_sensor_range = 0.3\n");
  GraphBackend b(ini);
  EXPECT_EQ(b.options().solver, "levenberg-marquardt");
  EXPECT_EQ(b.options().relinearize_every, 25);
  EXPECT_DOUBLE_EQ(b.options().prior_std_yaw_deg, 0.5);
  EXPECT_EQ(b.options().incremental_iterations, GraphSlamOptions{}.incremental_iterations);
  EXPECT_DOUBLE_EQ(b.noise().std_sensor_range, 0.3);
  EXPECT_DOUBLE_EQ(b.noise().std_sensor_yaw_deg, 0.5);
  EXPECT_EQ(b.options().solverSettings().method, SolverSettings::Method::LevenbergMarquardt);
}

TEST(GraphOptions, BadValuesNameTheKey) {
  mrpt::config::CConfigFileMemory bad_solver("[GraphSLAM]\nsolver = newton\n");
  try {
    GraphBackend b(bad_solver);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("solver"), std::string::npos) << e.what();
  }
  mrpt::config::CConfigFileMemory negative("[RangeBearingKFSLAM]\nstd_sensor_range = -1\n");
  EXPECT_THROW(GraphBackend b(negative), ConfigError);
  mrpt::config::CConfigFileMemory iters("[GraphSLAM]\nmax_iterations = 0\n");
  EXPECT_THROW(GraphBackend b(iters), ConfigError);
}

TEST(GraphOptions, IncrementalAndBoundedGraphKeys) {
  mrpt::config::CConfigFileMemory ini(
      "[GraphSLAM]\nrelinearize_threshold = 0.01\nreorder_fill_ratio = 2\nmax_poses = 500\n");
  GraphBackend b(ini);
  EXPECT_DOUBLE_EQ(b.options().relinearize_threshold, 0.01);
  EXPECT_DOUBLE_EQ(b.options().reorder_fill_ratio, 2.0);
  EXPECT_EQ(b.options().max_poses, 500);
  EXPECT_DOUBLE_EQ(b.solverOrdering().refreshFill(), 2.0);
  const auto message = [](const char* text) {
    mrpt::config::CConfigFileMemory bad(text);
    try {
      GraphBackend g(bad);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("[GraphSLAM]\nmax_poses = 1\n"),
            "[GraphSLAM] max_poses = 1: must be 0 (unbounded) or at least 2");
  EXPECT_NE(message("[GraphSLAM]\nmax_poses = -3\n").find("max_poses"), std::string::npos);
  EXPECT_NE(message("[GraphSLAM]\nrelinearize_threshold = -1\n").find("relinearize_threshold"),
            std::string::npos);
  EXPECT_NE(message("[GraphSLAM]\nreorder_fill_ratio = x\n").find("reorder_fill_ratio"),
            std::string::npos);
}

TEST(GraphOptions, DumpListsEveryKey) {
  std::ostringstream out;
  GraphSlamOptions{}.dumpToTextStream(out);
  for (const std::string& k : GraphSlamOptions::keys())
    EXPECT_NE(out.str().find("\n" + k + " "), std::string::npos) << k;
  EXPECT_EQ(GraphSlamOptions::keys().size(), 21u);
  std::ostringstream n;
  RangeBearingNoise{}.dumpToTextStream(n);
  for (const std::string& k : RangeBearingNoise::keys())
    EXPECT_NE(n.str().find(k), std::string::npos);
}
