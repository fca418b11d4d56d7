// libFuzzer target fuzz_map_folder: a map folder as `budget-slam localize --map` reads it
// (landmarks.csv and summary.json, split at a separator line, fuzz/FuzzFiles.h), then, when it
// loads, the localization it starts: start pose and truth through the map's alignment, and MRPT's
// filter over the first steps of the kf-slam demo in that map. Allowed outcomes: the steps done,
// or one Error of one printable line. A finding is anything else: a crash, a sanitizer report,
// another exception, an allocation above -malloc_limit_mb, a hang (issue 23, case 4: an absurd
// map alignment once hung localize).
#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "FuzzFiles.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/localization/LocalizationOptions.h"
#include "budget_slam/localization/Localizer.h"
#include "budget_slam/localization/MapFolder.h"

namespace {

using namespace budget_slam;

constexpr std::size_t kSteps = 10;

struct Traversal {
  mrpt::config::CConfigFileMemory ini;
  runs::LocalizationOptions options;
  std::vector<Step> steps;
  std::size_t in_rawlog = 0;
  dataset::GroundTruth truth;
};

/// The demo's first steps, its ground truth and MRPT's ini: read once.
const Traversal& traversal() {
  static const Traversal t = [] {
    Traversal t;
    const std::string root = BUDGET_SLAM_SOURCE_DIR;
    std::ifstream in(root + "/tests/data/EKF-SLAM_test_2d.ini");
    std::stringstream text;
    text << in.rdbuf();
    loadIniText(t.ini, text.str(), "EKF-SLAM_test_2d.ini");
    const std::string rawlog = root + "/rawlogs/kf-slam_demo.rawlog";
    dataset::RawlogReader reader(rawlog);
    while (auto s = reader.next()) t.steps.push_back(std::move(*s));
    t.in_rawlog = t.steps.size();
    t.steps.resize(kSteps);
    t.truth = dataset::loadGroundTruth(rawlog);
    return t;
  }();
  return t;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fz = budget_slam::fuzz;
  const Traversal& t = traversal();
  const auto dir = fz::scratch("map_folder");
  const auto files = fz::splitFiles(std::string_view(reinterpret_cast<const char*>(data), size), 2);
  fz::writeFile(dir / "landmarks.csv", files[0]);
  if (!files[1].empty()) fz::writeFile(dir / "summary.json", files[1]);
  try {
    const auto map = runs::loadMapFolder(dir.string(), t.options.max_map_landmarks);
    // Without an alignment the command asks for --start-pose: the origin, as a user would give.
    const std::optional<Pose2> start = map.alignment ? std::nullopt : std::optional<Pose2>(Pose2());
    const auto inputs = runs::resolveLocalization(t.steps, t.in_rawlog, t.truth, map.alignment,
                                                  start, nullptr, "", t.options);
    runs::Localizer localizer(t.ini, t.options, 2,
                              report::OutputFolder((dir / "out").string(), false), map.landmarks,
                              inputs);
    for (const auto& s : t.steps) localizer.process(s);
  } catch (const budget_slam::Error& e) {
    fz::requireOneLine(e.what());
  }
  return 0;
}
