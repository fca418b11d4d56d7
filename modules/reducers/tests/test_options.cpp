#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/CoverageOptions.h"
#include "budget_slam/reducers/MutualInformationOptions.h"

using namespace budget_slam;
using namespace budget_slam::reducers;

namespace {

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MutualInformationOptions, DefaultsAreThePapers) {
  mrpt::config::CConfigFileMemory ini;
  MutualInformationOptions o;
  o.loadFromConfigFile(ini, MutualInformationOptions::kSection);
  EXPECT_EQ(o.mode, MutualInformationOptions::Mode::Cap);
  EXPECT_DOUBLE_EQ(o.lambda, 0.4);
  EXPECT_EQ(o.psi, 500u);
  EXPECT_EQ(o.pose_lag, 5u);
  std::ostringstream out;
  o.dumpToTextStream(out);
  EXPECT_NE(out.str().find("[MutualInformationReducer]"), std::string::npos);
  EXPECT_NE(out.str().find("mode                     = cap"), std::string::npos);
}

TEST(MutualInformationOptions, BadValuesNameTheKey) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("MutualInformationReducer", "lambda", "1.5");
  MutualInformationOptions o;
  EXPECT_EQ(errorOf([&] { o.loadFromConfigFile(ini, "MutualInformationReducer"); }),
            "[MutualInformationReducer] lambda = 1.5: must be at most 1");
  ini.write("MutualInformationReducer", "lambda", "-0.1");
  EXPECT_NE(errorOf([&] { o.loadFromConfigFile(ini, "MutualInformationReducer"); }).find("lambda"),
            std::string::npos);
  ini.write("MutualInformationReducer", "lambda", "1");
  ini.write("MutualInformationReducer", "mode", "greedy");
  EXPECT_EQ(
      errorOf([&] { o.loadFromConfigFile(ini, "MutualInformationReducer"); }),
      "[MutualInformationReducer] mode = 'greedy': must be one of cap, objective, incremental");
  ini.write("MutualInformationReducer", "mode", "objective");
  ini.write("MutualInformationReducer", "psi", "0");
  EXPECT_NE(errorOf([&] { o.loadFromConfigFile(ini, "MutualInformationReducer"); }).find("psi"),
            std::string::npos);
  ini.write("MutualInformationReducer", "psi", "30  // synthetic");
  o.loadFromConfigFile(ini, "MutualInformationReducer");
  EXPECT_EQ(o.psi, 30u);
  EXPECT_DOUBLE_EQ(o.lambda, 1.0);
  EXPECT_EQ(o.mode, MutualInformationOptions::Mode::Objective);
}

TEST(MutualInformationOptions, StopLoadsAndNamesBadValues) {
  mrpt::config::CConfigFileMemory ini;
  MutualInformationOptions o;
  o.loadFromConfigFile(ini, "MutualInformationReducer");
  EXPECT_EQ(o.stop, MutualInformationOptions::Stop::FirstIncrease);
  ini.write("MutualInformationReducer", "stop", "global_minimum");
  o.loadFromConfigFile(ini, "MutualInformationReducer");
  EXPECT_EQ(o.stop, MutualInformationOptions::Stop::GlobalMinimum);
  ini.write("MutualInformationReducer", "stop", "lowest");
  EXPECT_EQ(errorOf([&] { o.loadFromConfigFile(ini, "MutualInformationReducer"); }),
            "[MutualInformationReducer] stop = 'lowest': must be one of first_increase, "
            "global_minimum");
}

TEST(CoverageOptions, DefaultsAndBadValues) {
  mrpt::config::CConfigFileMemory ini;
  CoverageOptions o;
  o.loadFromConfigFile(ini, CoverageOptions::kSection);
  EXPECT_DOUBLE_EQ(o.cluster_ratio, 0.25);
  EXPECT_EQ(o.distance, KMeans::Distance::L1);
  ini.write("CoverageReducer", "distance", "L3");
  EXPECT_EQ(errorOf([&] { o.loadFromConfigFile(ini, "CoverageReducer"); }),
            "[CoverageReducer] distance = 'L3': must be one of L1, L2");
  ini.write("CoverageReducer", "distance", "L2");
  ini.write("CoverageReducer", "cluster_ratio", "0");
  EXPECT_NE(errorOf([&] { o.loadFromConfigFile(ini, "CoverageReducer"); }).find("cluster_ratio"),
            std::string::npos);
  ini.write("CoverageReducer", "cluster_ratio", "0.5");
  ini.write("CoverageReducer", "max_iterations", "0");
  EXPECT_NE(errorOf([&] { o.loadFromConfigFile(ini, "CoverageReducer"); }).find("max_iterations"),
            std::string::npos);
  ini.write("CoverageReducer", "max_iterations", "7");
  o.loadFromConfigFile(ini, "CoverageReducer");
  EXPECT_EQ(o.distance, KMeans::Distance::L2);
  EXPECT_EQ(o.max_iterations, 7u);
  EXPECT_EQ(o.kmeans(10).k, 5u);
}

TEST(BuiltinReducers, NewReducersAreRegisteredWithTheirSections) {
  const auto names = builtinReducers().names();
  for (const char* n : {"mi", "coverage", "coverage-mi"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  for (const char* n : {"coverage", "coverage-mi"}) {
    const auto& sections = builtinReducers().entry(n).sections;
    ASSERT_EQ(sections.size(), 1u) << n;
    EXPECT_EQ(sections[0].name, "CoverageReducer");
    EXPECT_EQ(sections[0].keys(), CoverageOptions::keys());
  }
  mrpt::config::CConfigFileMemory ini;
  for (const auto& n : names)  // every entry builds a reducer of its own name
    if (n != "none") EXPECT_EQ(builtinReducers().create(n, ini, 1)->name(), n);
}

TEST(BuiltinReducers, EachEntryChecksItsOwnSectionsWithoutBuilding) {
  // Every key an entry lists has a default of its options' table (for --list), and a bad value of
  // its section is the loader's KeyError, naming section and key.
  for (const auto* e : builtinReducers().entries())
    for (const auto& s : e->sections) {
      ASSERT_TRUE(s.check) << e->name << " [" << s.name << "]";
      for (const auto& o : s.options) EXPECT_TRUE(o.default_text) << e->name << " " << o.key;
    }
  mrpt::config::CConfigFileMemory ini;
  ini.write("CoverageReducer", "max_iterations", "0");
  try {
    builtinReducers().entry("coverage-mi").validate(ini);
    FAIL() << "a bad value passed";
  } catch (const KeyError& e) {
    EXPECT_EQ(e.section(), "CoverageReducer");
    EXPECT_EQ(e.key(), "max_iterations");
    EXPECT_EQ(e.kind(), ConfigErrorKind::BadValue);
    EXPECT_EQ(std::string(e.what()).rfind("[CoverageReducer] max_iterations = 0: ", 0), 0u);
  }
  builtinReducers().entry("mi").validate(ini);  // not mi's section
  ini.write("RangeBearingKFSLAM", "std_sensor_yaw_deg", "400");
  EXPECT_THROW(builtinReducers().entry("localization-information").validate(ini), KeyError);
}
