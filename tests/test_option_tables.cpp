// Every options struct of the run keeps a value the ini does not set (max_steps used to fall
// back to 0 instead), and what its table saves loads back to the same options.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <sstream>

#include "budget_slam/engine/MappingOptions.h"
#include "budget_slam/localization/LocalizationOptions.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/reducers/BudgetOptions.h"
#include "budget_slam/reducers/CoverageOptions.h"
#include "budget_slam/reducers/MutualInformationOptions.h"
#include "budget_slam/reducers/PlaceCoverageReducer.h"

using namespace budget_slam;

namespace {

template <class O>
std::string dumpOf(const O& o) {
  std::ostringstream out;
  o.dumpToTextStream(out);
  return out.str();
}

/// `o` saved with its table and loaded into default options gives the same dump, and the saved
/// section holds exactly keys().
template <class O>
void expectRoundTrip(const O& o) {
  mrpt::config::CConfigFileMemory ini;
  o.saveToConfigFile(ini, O::kSection);
  std::vector<std::string> saved;
  ini.getAllKeys(O::kSection, saved);
  auto keys = O::keys();
  std::sort(keys.begin(), keys.end());
  std::sort(saved.begin(), saved.end());
  EXPECT_EQ(saved, keys) << O::kSection;
  O back;
  back.loadFromConfigFile(ini, O::kSection);
  EXPECT_EQ(dumpOf(back), dumpOf(o)) << O::kSection;
  for (const auto& k : O::keys())
    EXPECT_NE(dumpOf(o).find("\n" + k + " "), std::string::npos) << O::kSection << " " << k;
}

}  // namespace

TEST(OptionTables, MaxStepsKeepsTheCurrentValueWhenAbsent) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("MappingApplication", "backend", "ekf");
  runs::MappingOptions m;
  m.max_steps = 40;
  m.loadFromConfigFile(ini, runs::MappingOptions::kSection);
  EXPECT_EQ(m.max_steps, 40u);
  runs::LocalizationOptions l;
  l.max_steps = 12;
  l.loadFromConfigFile(ini, runs::LocalizationOptions::kSection);
  EXPECT_EQ(l.max_steps, 12u);
  ini.write("MappingApplication", "max_steps", "5");
  m.loadFromConfigFile(ini, runs::MappingOptions::kSection);
  EXPECT_EQ(m.max_steps, 5u);
}

TEST(OptionTables, SavedOptionsLoadBackTheSame) {
  runs::MappingOptions m;
  m.max_steps = 9;
  m.backend = "graph";
  m.scene_every_steps = 4;
  expectRoundTrip(m);
  expectRoundTrip(runs::MappingOptions{});
  runs::LocalizationOptions l;
  l.gate_chi2 = 13.8;
  expectRoundTrip(l);
  reducers::BudgetOptions b;
  b.max_landmarks.reset();
  b.protect = reducers::BudgetOptions::Protect::NewlyAdded;
  b.admission = reducers::BudgetOptions::Admission::Compete;
  b.shadow_reducers = {"random", "oldest"};
  expectRoundTrip(b);
  expectRoundTrip(reducers::BudgetOptions{});
  reducers::MutualInformationOptions mi;
  mi.mode = reducers::MutualInformationOptions::Mode::Incremental;
  mi.stop = reducers::MutualInformationOptions::Stop::GlobalMinimum;
  mi.lambda = 0.125;
  expectRoundTrip(mi);
  reducers::CoverageOptions c;
  c.distance = reducers::KMeans::Distance::L2;
  c.seed = 77;
  expectRoundTrip(c);
  reducers::PlaceCoverageOptions p;
  p.place_size = 2.5;
  expectRoundTrip(p);
  metrics::MetricsOptions mo;
  mo.reloc_match_chi2 = 9.21;
  expectRoundTrip(mo);
}

TEST(OptionTables, ErrorMessagesNameSectionKeyAndValue) {
  mrpt::config::CConfigFileMemory ini;
  ini.write("LandmarkBudget", "max_landmarks", "0");
  reducers::BudgetOptions b;
  try {
    b.loadFromConfigFile(ini, reducers::BudgetOptions::kSection);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "[LandmarkBudget] max_landmarks = 0: must be at least 1 (or none for no cap)");
  }
  ini.write("MappingApplication", "kf_implementation", "CRangeBearingKFSLAM");
  try {
    runs::MappingOptions().loadFromConfigFile(ini, runs::MappingOptions::kSection);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "[MappingApplication] kf_implementation = CRangeBearingKFSLAM: budget-slam runs "
                 "the 2D filter, CRangeBearingKFSLAM2D");
  }
}
