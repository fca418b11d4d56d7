// The configuration errors whose wording once came from parsing another error's message: each is
// now worded from the error's data (ConfigErrorKind, KeyError::why, the origin), and reads as
// before, byte for byte.
#include <gtest/gtest.h>

#include "AppTestUtil.h"

using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

const std::string kNeedsCap =
    "drops landmarks only to keep the map under a cap, so it needs a number (no cap suits reducer "
    "none, and mi in objective or incremental mode)";

AppResult runWith(const std::string& name, const std::string& ini_text,
                  const std::vector<std::string>& flags) {
  const auto dir = freshDir(name);
  fs::create_directories(dir);
  const auto ini = dir / "settings.ini";
  std::ofstream(ini) << ini_text;
  std::vector<std::string> args = {"run", "-c", ini.string(),           "-i",
                                   kDemo, "-o", (dir / "out").string(), "--quiet"};
  args.insert(args.end(), flags.begin(), flags.end());
  return runApp(args);
}

}  // namespace

TEST(RegistryErrors, NoCapIsNamedWhereTheNoneCameFrom) {
  const auto ini_dir = fs::temp_directory_path() / "budget_slam_tests" / "cap_none_ini";
  const auto by_ini =
      runWith("cap_none_ini", "[LandmarkBudget]\nmax_landmarks = none\n", {"--reducer", "oldest"});
  EXPECT_EQ(by_ini.exit_code, 1);
  EXPECT_EQ(by_ini.err, "budget-slam: error: " + (ini_dir / "settings.ini").string() +
                            ": [LandmarkBudget] max_landmarks = none: reducer 'oldest' " +
                            kNeedsCap + "\n");
  const auto by_flag = runWith("cap_none_flag", "[LandmarkBudget]\nseed = 1\n",
                               {"--reducer", "info-content", "--cap", "none"});
  EXPECT_EQ(by_flag.exit_code, 1);
  EXPECT_EQ(by_flag.err,
            "budget-slam: error: --cap none: reducer 'info-content' " + kNeedsCap + "\n");
  // mi sizes the map itself in incremental mode: no cap is fine.
  const auto mi = runWith("cap_none_mi", "[MutualInformationReducer]\nmode = incremental\n",
                          {"--reducer", "mi", "--cap", "none", "--max-steps", "30"});
  EXPECT_EQ(mi.exit_code, 0) << mi.err;
}

TEST(RegistryErrors, AnUnknownReducerNameSpeaksForItselfAndOthersNameTheirFile) {
  const auto shadow =
      runWith("unknown_shadow", "[LandmarkBudget]\nshadow_reducers = oldest, nope\n",
              {"--reducer", "oldest"});
  EXPECT_EQ(shadow.exit_code, 1);
  EXPECT_EQ(
      shadow.err.rfind("budget-slam: error: unknown reducer 'nope' (registered: coverage, ", 0), 0u)
      << shadow.err;
  const auto set = runWith("bad_set_value", "[LandmarkBudget]\nseed = 1\n",
                           {"--set", "CoverageReducer.max_iterations=0"});
  EXPECT_EQ(set.err,
            "budget-slam: error: --set 'CoverageReducer.max_iterations=0': [CoverageReducer] "
            "max_iterations = 0: must be at least 1\n");
  // Two bad values in two registry entries' sections: the backends' are checked first.
  const auto two =
      runWith("two_bad_values",
              "[CoverageReducer]\nmax_iterations = 0\n[GraphSLAM]\nmax_iterations = -1\n", {});
  EXPECT_NE(two.err.find(": [GraphSLAM] max_iterations = -1: must be at least 1\n"),
            std::string::npos)
      << two.err;
}
