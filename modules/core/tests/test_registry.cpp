#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include "budget_slam/core/BackendRegistry.h"
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
           {},
           [](const mrpt::config::CConfigFileBase&, std::uint64_t) {
             return std::make_unique<FirstCandidate>();
           }});
  reg.add({"alpha", "", {}, [](const mrpt::config::CConfigFileBase&, std::uint64_t) {
             return std::make_unique<FirstCandidate>();
           }});
  mrpt::config::CConfigFileMemory ini;
  EXPECT_EQ(reg.create("first", ini, 1)->name(), "first");
  EXPECT_EQ(reg.names(), (std::vector<std::string>{"alpha", "first"}));
  try {
    reg.create("nope", ini, 1);
    FAIL();
  } catch (const UnknownNameError& e) {
    EXPECT_STREQ(e.what(), "unknown reducer 'nope' (registered: alpha, first)");
    EXPECT_EQ(e.kind(), ConfigErrorKind::UnknownName);
    EXPECT_EQ(e.registryKind(), "reducer");
    EXPECT_EQ(e.name(), "nope");
  }
  EXPECT_THROW(reg.add({"first", "", {}, nullptr}), std::logic_error);
}

namespace {
class NamedBackend : public Backend {
 public:
  explicit NamedBackend(bool keep) : keep_(keep) {}
  std::string name() const override { return keep_ ? "keeps" : "latest-only"; }
  void process(const Step&) override {}
  std::vector<LandmarkView> landmarks() const override { return {}; }
  std::size_t landmarkCount() const override { return 0; }
  PoseEstimate robotPose() const override { return {}; }
  std::vector<TrajectoryPoint> trajectory() const override { return {}; }
  std::size_t poseCount() const override { return 0; }
  void removeLandmark(LandmarkId) override {}
  std::vector<double> informationGain(const std::vector<LandmarkId>&) const override { return {}; }
  Eigen::Matrix2d landmarkCovariance(LandmarkId) const override { return {}; }
  Eigen::MatrixXd jointCovariance(const std::vector<VariableKey>&) const override { return {}; }

 private:
  bool keep_;
};
}  // namespace

TEST(BackendRegistry, CreatesByNamePassesSettingsAndListsRegisteredOnUnknown) {
  BackendRegistry reg;
  const auto factory = [](const mrpt::config::CConfigFileBase&, const BackendSettings& s) {
    return std::unique_ptr<Backend>(std::make_unique<NamedBackend>(s.keep_trajectory));
  };
  reg.add({"zeta", "", {{"Zeta", keysOnly({"a", "b"}), {}}}, factory});
  reg.add({"alpha", "", {}, factory});
  mrpt::config::CConfigFileMemory ini;
  EXPECT_EQ(reg.create("zeta", ini)->name(), "keeps");
  EXPECT_EQ(reg.create("zeta", ini, BackendSettings{false})->name(), "latest-only");
  EXPECT_EQ(reg.names(), (std::vector<std::string>{"alpha", "zeta"}));
  EXPECT_EQ(reg.joinedNames("|"), "alpha|zeta");
  EXPECT_EQ(reg.entry("zeta").sections.at(0).name, "Zeta");
  EXPECT_EQ(reg.entry("zeta").sections.at(0).keys(), (std::vector<std::string>{"a", "b"}));
  try {
    reg.create("gtsam", ini);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "unknown backend 'gtsam' (registered: alpha, zeta)");
  }
  EXPECT_THROW(reg.add({"alpha", "", {}, nullptr}), std::logic_error);
}
