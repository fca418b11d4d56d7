#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSchema.h"
#include "budget_slam/core/IniSection.h"

using namespace budget_slam;

namespace {
std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST(IniSection, ReadsValuesWithMrptTrailingComments) {
  mrpt::config::CConfigFileMemory ini(
      "[S]\na = 2   // degs\nb = 7\nc = true\nd = mi, coverage oldest\n");
  IniSection s(ini, "S");
  EXPECT_DOUBLE_EQ(s.readDouble("a", 0), 2.0);
  EXPECT_EQ(s.readInt("b", 0), 7);
  EXPECT_TRUE(s.readBool("c", false));
  EXPECT_EQ(s.readList("d"), (std::vector<std::string>{"mi", "coverage", "oldest"}));
  EXPECT_EQ(s.readInt("absent", 42), 42);
  EXPECT_FALSE(s.has("absent"));
}

TEST(IniSection, ErrorsNameSectionKeyAndValue) {
  mrpt::config::CConfigFileMemory ini("[LandmarkBudget]\nmax_landmarks = 0\nx = abc\nb = maybe\n");
  IniSection s(ini, "LandmarkBudget");
  EXPECT_EQ(errorOf([&] { s.readInt("max_landmarks", 50, 1); }),
            "[LandmarkBudget] max_landmarks = 0: must be at least 1");
  EXPECT_EQ(errorOf([&] { s.readDouble("x", 0); }), "[LandmarkBudget] x = 'abc': not a number");
  EXPECT_EQ(errorOf([&] { s.readBool("b", true); }),
            "[LandmarkBudget] b = 'maybe': not a boolean (true or false)");
  EXPECT_EQ(errorOf([&] {
              s.readChoice("x", "a", {"ekf", "graph"});
            }),
            "[LandmarkBudget] x = 'abc': must be one of ekf, graph");
}

TEST(IniSchema, RejectsUnknownKeyWithClosestSuggestion) {
  IniSchema schema;
  schema.addSection("LandmarkBudget", {"reducer", "max_landmarks", "protect_recent_steps"});
  schema.addForeignSection("Params");
  schema.addForeignSection("RANDOMSET_*");
  mrpt::config::CConfigFileMemory ok(
      "[LandmarkBudget]\nmax_landmarks=3\n[Params]\nfoo=1\n[RANDOMSET_2]\nn=3\n");
  EXPECT_NO_THROW(schema.validate(ok));
  // Sections nobody reads are errors (a kf-slam ini shared with simul-landmarks still passes).
  mrpt::config::CConfigFileMemory other("[LandmarkBudget]\nmax_landmarks=3\n[Other]\nfoo=1\n");
  EXPECT_EQ(errorOf([&] { schema.validate(other); }),
            "unknown section [Other] (neither budget-slam nor another MRPT application reads it)");
  mrpt::config::CConfigFileMemory param("[Param]\nfoo=1\n");
  EXPECT_EQ(errorOf([&] { schema.validate(param); }),
            "unknown section [Param] (did you mean [Params]?)");
  EXPECT_TRUE(schema.isForeign("randomset_17"));
  EXPECT_FALSE(schema.isForeign("RANDOMSET_"));
  mrpt::config::CConfigFileMemory typo("[LandmarkBudget]\nmax_landmark=3\n");
  EXPECT_EQ(errorOf([&] { schema.validate(typo); }),
            "unknown key [LandmarkBudget] max_landmark (did you mean max_landmarks?)");
  mrpt::config::CConfigFileMemory far("[LandmarkBudget]\nzzzzzzzzzz=3\n");
  EXPECT_EQ(errorOf([&] { schema.validate(far); }),
            "unknown key [LandmarkBudget] zzzzzzzzzz (no similar key in this section)");
  mrpt::config::CConfigFileMemory badSection("[LandmarkBuget]\nmax_landmarks=3\n");
  EXPECT_EQ(errorOf([&] { schema.validate(badSection); }),
            "unknown section [LandmarkBuget] (did you mean [LandmarkBudget]?)");
}

TEST(IniSchema, ListsEveryUnknownKeyAtOnceBounded) {
  // A foreign ini was refused one unknown key a try (issue 35): the first with its suggestion,
  // then every other, at most 12 named in all.
  IniSchema schema;
  schema.addSection("LandmarkBudget", {"reducer", "max_landmarks"});
  mrpt::config::CConfigFileMemory three(
      "[LandmarkBudget]\nmax_landmark=3\nreducer=none\nfoo=1\n[Other]\nx=1\n");
  const std::string e = errorOf([&] { schema.validate(three); });
  EXPECT_EQ(e.find("\n"), std::string::npos);
  EXPECT_EQ(e.find("2 more unknown: "), e.find(';') + 2) << e;
  for (const char* named : {"max_landmark", "foo", "[Other] (the section)"})
    EXPECT_NE(e.find(named), std::string::npos) << named << " in " << e;
  std::string many = "[LandmarkBudget]\n";
  for (int k = 0; k < 500; ++k) many += "unknown_" + std::to_string(k) + "=1\n";
  mrpt::config::CConfigFileMemory hostile(many);
  const std::string h = errorOf([&] { schema.validate(hostile); });
  EXPECT_NE(h.find("499 more unknown: "), std::string::npos) << h;
  EXPECT_NE(h.find("(488 not listed)"), std::string::npos) << h;
  EXPECT_LT(h.size(), 600u) << h;
}

TEST(IniSchema, EditDistance) {
  EXPECT_EQ(editDistance("kitten", "sitting"), 3u);
  EXPECT_EQ(editDistance("ABC", "abc"), 0u);
  EXPECT_EQ(closestMatch("reducr", {"reducer", "seed"}), "reducer");
  EXPECT_EQ(closestMatch("qqqqqqqq", {"reducer", "seed"}), "");
}
