// A reducer added by one file and one registration line (tests/IdOrderReducer.cpp) is a reducer
// like the shipped ones: --list shows it, an ini that chooses it is checked (its own section, its
// keys), a run with it ends ok and logs its decisions, and a shadow of it is logged too.
#include <gtest/gtest.h>

#include <algorithm>

#include "AppTestUtil.h"

using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

const nlohmann::json* listed(const nlohmann::json& list, const std::string& name) {
  for (const auto& e : list)
    if (e["name"] == name) return &e;
  return nullptr;
}

}  // namespace

TEST(AddedReducer, ListedWithItsOptionAndDefault) {
  const auto r = runApp({"--list", "reducers", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto list = nlohmann::json::parse(r.out);
  const auto* e = listed(list, "id-order");
  ASSERT_NE(e, nullptr) << r.out;
  EXPECT_EQ((*e)["summary"], "the candidate of lowest (or highest) landmark id (a test's reducer)");
  ASSERT_EQ((*e)["options"].size(), 1u);
  EXPECT_EQ((*e)["options"][0]["section"], "IdOrderReducer");
  EXPECT_EQ((*e)["options"][0]["key"], "order");
  EXPECT_EQ((*e)["options"][0]["default"], "lowest");
  // The shipped reducers are all there too, in name order.
  std::vector<std::string> names;
  for (const auto& x : list) names.push_back(x["name"]);
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  for (const char* n : {"none", "mi", "place-coverage", "localization-information"})
    EXPECT_NE(listed(list, n), nullptr) << n;
  // Each says what it is for: the experiments' candidates are the rules (an added reducer is one).
  for (const auto& [n, role] :
       std::vector<std::pair<const char*, const char*>>{{"id-order", "rule"},
                                                        {"random", "rule"},
                                                        {"localization-information", "rule"},
                                                        {"none", "reference"},
                                                        {"hindsight", "bound"},
                                                        {"known-set", "bound"}})
    EXPECT_EQ((*listed(list, n))["role"], role) << n;
}

TEST(AddedReducer, ARunWithItEndsOkAndLogsItsDecisions) {
  const auto out = freshDir("added_reducer_run");
  const auto r =
      runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", out.string(), "--quiet", "--reducer",
              "id-order", "--cap", "10", "--set", "IdOrderReducer.order=highest", "--set",
              "LandmarkBudget.shadow_reducers=oldest"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(readJson(out / "summary.json")["status"], "ok");
  EXPECT_NE(slurp(out / "config_used.ini").find("order = highest"), std::string::npos);
  const auto evictions = readCsvTable(out / "evictions.csv");
  ASSERT_GT(evictions.rows.size(), 5u);
  for (std::size_t i = 0; i < evictions.rows.size(); ++i) {
    EXPECT_EQ(evictions.at(i, "reducer"), "id-order");
    // Its score is the id it dropped.
    EXPECT_EQ(std::stod(evictions.at(i, "score")), std::stod(evictions.at(i, "landmark_id")));
    EXPECT_NE(evictions.at(i, "shadow_choices").find("oldest"), std::string::npos);
  }
}

TEST(AddedReducer, ItsSectionIsCheckedBeforeTheRun) {
  const auto bad = freshDir("added_reducer_bad_value");
  const auto r =
      runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", bad.string(), "--quiet", "--reducer",
              "id-order", "--cap", "10", "--set", "IdOrderReducer.order=middle"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(
      r.err.find("--set 'IdOrderReducer.order=middle': [IdOrderReducer] order = 'middle': must "
                 "be one of lowest, highest"),
      std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(bad / "steps.csv"));
  // An unknown key of its section, whichever reducer runs.
  const auto typo = freshDir("added_reducer_unknown_key");
  const auto t =
      runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", typo.string(), "--quiet", "--reducer",
              "oldest", "--cap", "10", "--set", "IdOrderReducer.ordr=lowest"});
  EXPECT_NE(t.exit_code, 0);
  EXPECT_NE(t.err.find("unknown key [IdOrderReducer] ordr (did you mean order?)"),
            std::string::npos)
      << t.err;
}
