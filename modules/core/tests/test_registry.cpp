#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/ReducerRegistry.h"

using namespace budget_slam;

namespace {
class FirstCandidate : public Reducer {
 public:
  std::string name() const override { return "first"; }
  ReducerChoice choose(const DropContext& ctx) override {
    return {ctx.landmarks[ctx.candidates.front()].id, 0.0};
  }
};
}  // namespace

TEST(ReducerRegistry, CreatesByNameAndListsRegisteredOnUnknown) {
  ReducerRegistry reg;
  reg.add({"first",
           "drops the first candidate",
           "",
           {},
           [](const mrpt::config::CConfigFileBase&, std::uint64_t) {
             return std::make_unique<FirstCandidate>();
           }});
  reg.add({"alpha", "", "", {}, [](const mrpt::config::CConfigFileBase&, std::uint64_t) {
             return std::make_unique<FirstCandidate>();
           }});
  mrpt::config::CConfigFileMemory ini;
  EXPECT_EQ(reg.create("first", ini, 1)->name(), "first");
  EXPECT_EQ(reg.names(), (std::vector<std::string>{"alpha", "first"}));
  try {
    reg.create("nope", ini, 1);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "unknown reducer 'nope' (registered: alpha, first)");
  }
  EXPECT_THROW(reg.add({"first", "", "", {}, nullptr}), std::logic_error);
}
