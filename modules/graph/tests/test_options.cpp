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
  EXPECT_EQ(b.options().solver.method, SolverSettings::Method::LevenbergMarquardt);
  EXPECT_EQ(b.options().relinearize_every, 25);
  EXPECT_DOUBLE_EQ(b.options().prior_std_yaw_deg, 0.5);
  EXPECT_EQ(b.options().incremental_iterations, GraphSlamOptions{}.incremental_iterations);
  EXPECT_DOUBLE_EQ(b.noise().std_sensor_range, 0.3);
  EXPECT_DOUBLE_EQ(b.noise().std_sensor_yaw_deg, 0.5);
  EXPECT_EQ(b.options().solver.max_iterations, 100);  // [GraphSLAM]'s default, not Solver's
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
  EXPECT_EQ(GraphSlamOptions::keys().size(), 22u);
  EXPECT_NE(out.str().find("\nsolver                   = gauss-newton"), std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("\ninformation_gain         = marginal"), std::string::npos)
      << out.str();
  std::ostringstream n;
  RangeBearingNoise{}.dumpToTextStream(n);
  for (const std::string& k : RangeBearingNoise::keys())
    EXPECT_NE(n.str().find(k), std::string::npos);
  EXPECT_EQ(RangeBearingNoise::keys(),
            (std::vector<std::string>{"std_sensor_range", "std_sensor_yaw_deg"}));
}

// One table: what saveToConfigFile writes loads back to the same options, the nested solver
// settings and the enums included.
TEST(GraphOptions, SaveLoadsBackTheSameOptions) {
  GraphSlamOptions o;
  o.solver.method = SolverSettings::Method::LevenbergMarquardt;
  o.solver.max_iterations = 7;
  o.solver.step_tolerance = 1.0 / 3.0;
  o.solver.lm_lambda_factor = 4;
  o.information_gain = GraphSlamOptions::InformationGain::Conditional;
  o.max_poses = 40;
  o.exact_pose_covariance = true;
  mrpt::config::CConfigFileMemory ini;
  o.saveToConfigFile(ini, GraphSlamOptions::kSection);
  GraphSlamOptions back;
  back.loadFromConfigFile(ini, GraphSlamOptions::kSection);
  EXPECT_EQ(back.solver.method, SolverSettings::Method::LevenbergMarquardt);
  EXPECT_EQ(back.solver.max_iterations, 7);
  EXPECT_EQ(back.solver.step_tolerance, 1.0 / 3.0);
  EXPECT_EQ(back.solver.lm_lambda_factor, 4.0);
  EXPECT_EQ(back.information_gain, GraphSlamOptions::InformationGain::Conditional);
  EXPECT_EQ(back.max_poses, 40);
  EXPECT_TRUE(back.exact_pose_covariance);
  EXPECT_EQ(ini.read_string("GraphSLAM", "information_gain", ""), "conditional");
}

TEST(GraphOptions, BadWordsListTheChoices) {
  const auto message = [](const char* text) {
    mrpt::config::CConfigFileMemory bad(text);
    try {
      GraphBackend g(bad);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("[GraphSLAM]\nsolver = newton\n"),
            "[GraphSLAM] solver = 'newton': must be one of gauss-newton, levenberg-marquardt");
  EXPECT_EQ(message("[GraphSLAM]\ninformation_gain = joint\n"),
            "[GraphSLAM] information_gain = 'joint': must be one of marginal, conditional");
  EXPECT_EQ(message("[GraphSLAM]\nmax_iterations = 0\n"),
            "[GraphSLAM] max_iterations = 0: must be at least 1");
}
