// The instruments of the benchmark's bounds on a real filter: EkfBackend over
// rawlogs/kf-slam_demo.rawlog (70 landmarks with sensor IDs, a ground-truth path).
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <random>
#include <set>

#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/ekf/EkfBackend.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/reducers/HindsightReducer.h"

using namespace budget_slam;
using namespace budget_slam::reducers;

namespace {

const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;
const std::string kDemo = kRoot + "/rawlogs/kf-slam_demo.rawlog";
const std::string kIni = kRoot + "/tests/data/EKF-SLAM_test_2d.ini";

const std::vector<Step>& demoSteps() {
  static const std::vector<Step> steps = dataset::readAllSteps(kDemo);
  return steps;
}

std::set<LandmarkId> idsOf(const Backend& b) {
  std::set<LandmarkId> out;
  for (const auto& l : b.landmarks()) out.insert(l.id);
  return out;
}

/// The final map of the demo run under `reducer` (options in `extra`) and `cap` (none: unbounded);
/// `each_step` is called after every step's drops, `at_end` with the reducer after the last step's
/// (the manager owns the reducer and ends with this call: nothing may keep a pointer to it).
std::set<LandmarkId> runDemo(const std::string& reducer, std::optional<std::size_t> cap,
                             const mrpt::config::CConfigFileBase& extra,
                             const std::function<void(const Step&, const Backend&)>& each_step = {},
                             const std::function<void(const Reducer&)>& at_end = {}) {
  mrpt::config::CConfigFile ini(kIni);
  ekf::EkfBackend backend(ini);
  BudgetOptions o;
  o.max_landmarks = cap;
  auto active = builtinReducers().create(reducer, extra, 1);
  const Reducer& r = *active;
  BudgetManager manager(o, std::move(active));
  for (const Step& s : demoSteps()) {
    backend.process(s);
    manager.enforce(backend, s);
    if (each_step) each_step(s, backend);
  }
  manager.finish(backend, demoSteps().back().index);
  if (at_end) at_end(r);
  return idsOf(backend);
}

/// `k` distinct ids of `from`, drawn uniformly by a partial Fisher-Yates shuffle on `rng`'s raw
/// output (the same draws with every standard library).
std::vector<LandmarkId> drawSubset(std::vector<LandmarkId> from, std::size_t k,
                                   std::mt19937_64& rng) {
  for (std::size_t i = 0; i < k; ++i) std::swap(from[i], from[i + rng() % (from.size() - i)]);
  from.resize(k);
  return from;
}

}  // namespace

TEST(BoundsOnEkf, HindsightKeepsItsSelectionOfTheUnreducedMap) {
  mrpt::config::CConfigFileMemory none;
  const std::set<LandmarkId> unreduced = runDemo("none", std::nullopt, none);
  ASSERT_EQ(unreduced.size(), 70u);
  mrpt::config::CConfigFileMemory extra;
  extra.write("HindsightReducer", "keep", "20%");
  std::size_t most = 0;
  LogDetSelection selection;
  std::vector<PlaceReadings> offered, after;
  Eigen::Matrix3d prior;
  const auto kept = runDemo(
      "hindsight", std::nullopt, extra,
      [&](const Step&, const Backend& b) { most = std::max(most, b.landmarkCount()); },
      [&](const Reducer& r) {
        const auto& h = dynamic_cast<const HindsightReducer&>(r);
        selection = h.selection();
        offered = h.selectionPlaces();
        after = h.places();
        prior = h.prior();
      });
  EXPECT_EQ(most, 70u);  // nothing dropped while mapping
  ASSERT_EQ(kept.size(), 14u);
  EXPECT_EQ(kept, std::set<LandmarkId>(selection.selection.begin(), selection.selection.end()));
  for (const LandmarkId id : kept) EXPECT_TRUE(unreduced.count(id)) << id;
  // Its objective is the value of the set over the places it was chosen over: every place the
  // unreduced map was read from, with all 70 landmarks' readings.
  std::set<LandmarkId> read;
  for (const auto& p : offered) read.insert(p.ids.begin(), p.ids.end());
  EXPECT_EQ(read, unreduced);
  EXPECT_NEAR(selection.objective, logDetObjective(offered, prior, selection.selection),
              1e-9 * std::abs(selection.objective));
  // Once the other 56 are dropped, the record holds the kept landmarks' readings alone: another
  // set's value is read on selectionPlaces(), not on places() after the run.
  std::set<LandmarkId> still;
  for (const auto& p : after) still.insert(p.ids.begin(), p.ids.end());
  EXPECT_EQ(still, kept);
  // Greedy against other 14-subsets of the same map on the same places: the first 14 ids and 200
  // uniform draws; none is better.
  const std::vector<LandmarkId> all(unreduced.begin(), unreduced.end());
  const std::vector<LandmarkId> first14(all.begin(), all.begin() + 14);
  EXPECT_GE(selection.objective, logDetObjective(offered, prior, first14));
  std::mt19937_64 rng(34);
  for (int draw = 0; draw < 200; ++draw) {
    const auto other = drawSubset(all, 14, rng);
    EXPECT_GE(selection.objective, logDetObjective(offered, prior, other)) << "draw " << draw;
  }

  // The same chosen over the places of a traversal read at its ground-truth path (here the
  // demo itself): a selection of the same size from the same map.
  extra.write("HindsightReducer", "places_rawlogs", kDemo);
  const auto ceiling = runDemo("hindsight", std::nullopt, extra);
  EXPECT_EQ(ceiling.size(), 14u);
  for (const LandmarkId id : ceiling) EXPECT_TRUE(unreduced.count(id)) << id;
}

TEST(BoundsOnEkf, KnownSetRunKeepsExactlyTheSetAtEveryStep) {
  mrpt::config::CConfigFileMemory none;
  const std::set<LandmarkId> unreduced = runDemo("none", std::nullopt, none);
  // The set: every third landmark of the unreduced map.
  std::set<LandmarkId> set;
  std::string text;
  std::size_t i = 0;
  for (const LandmarkId id : unreduced)
    if (i++ % 3 == 0) set.insert(id), text += std::to_string(id) + " ";
  mrpt::config::CConfigFileMemory extra;
  extra.write("KnownSetReducer", "ids", text);
  std::set<LandmarkId> seen;  // sensor IDs read so far
  std::size_t steps = 0;
  const auto final_map =
      runDemo("known-set", set.size(), extra, [&](const Step& s, const Backend& b) {
        if (s.scan)
          for (const auto& r : s.scan->readings) seen.insert(r.id);
        std::set<LandmarkId> expected;
        for (const LandmarkId id : set)
          if (seen.count(id)) expected.insert(id);
        ASSERT_EQ(idsOf(b), expected) << "step " << s.index;
        ++steps;
      });
  EXPECT_EQ(steps, demoSteps().size());
  EXPECT_EQ(final_map, set);
}
