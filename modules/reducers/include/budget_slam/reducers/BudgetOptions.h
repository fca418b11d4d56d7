#pragma once
#include <mrpt/config/CLoadableOptions.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace budget_slam::reducers {

/// [LandmarkBudget]: how many landmarks the map may hold and who decides which one goes
/// (DESIGN.md "Reducers").
struct BudgetOptions : public mrpt::config::CLoadableOptions {
  static constexpr const char* kSection = "LandmarkBudget";

  std::string reducer = "none";  ///< active reducer by registry name; none = no cap
  /// The cap: landmarks in the map after every step, >= 1 [landmarks]. Empty (ini and --cap:
  /// `none`) = unbounded, valid only for reducer `none` and for reducers that decide the map's
  /// size themselves (Reducer::decidesMapSize; checkCap).
  std::optional<std::size_t> max_landmarks = 50;
  std::size_t protect_recent_steps = 5;  ///< P: landmarks seen in the last P steps are kept [steps]
  bool readmit_evicted = true;           ///< a dropped landmark seen again comes back as new
  std::vector<std::string> shadow_reducers;  ///< asked at every drop, only logged
  std::uint64_t seed = 1;                    ///< seed of every randomized reducer
  bool dump_states = false;                  ///< write states/step_<k>.txt before each drop event

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                          const std::string& section) override;
  void dumpToTextStream(std::ostream& out) const override;

  /// Keys of the section, for unknown-key checks.
  static std::vector<std::string> keys();
  /// The cap as written in the ini and on the command line: a number, or `none`.
  static std::string capText(const std::optional<std::size_t>& cap);
};

}  // namespace budget_slam::reducers
