#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "budget_slam/core/OptionTable.h"

namespace budget_slam {

/// One ini section a registered part (a reducer, a backend) reads: its keys, which the unknown-key
/// check accepts and `budget-slam --list ... --json` shows with their defaults, and the check of
/// its values, which a run makes before its first step whichever part it will build.
struct OptionSection {
  std::string name;  ///< e.g. "MutualInformationReducer"
  std::vector<OptionInfo> options;
  /// Reads every value of the section the part reads, as the part reads it; the first bad one
  /// throws its KeyError (section, key, value and why). Empty when another section's check
  /// covers this one.
  std::function<void(const mrpt::config::CConfigFileBase&)> check;

  std::vector<std::string> keys() const {
    std::vector<std::string> out;
    for (const auto& o : options) out.push_back(o.key);
    return out;
  }
};

/// The section of a tabled options struct O (TabledOptions: O::kSection, O::table()): keys,
/// defaults and comments from its table, checked by loading it.
template <class O>
OptionSection tabledSection() {
  return {O::kSection, O::describe(), [](const mrpt::config::CConfigFileBase& ini) {
            O().loadFromConfigFile(ini, O::kSection);
          }};
}

/// A section of keys another program defines (MRPT's kf-slam): accepted, with no default of ours.
inline std::vector<OptionInfo> keysOnly(const std::vector<std::string>& keys) {
  std::vector<OptionInfo> out;
  for (const auto& k : keys) out.push_back({k, std::nullopt, ""});
  return out;
}

/// Runs the check of every section in `sections`, in order.
inline void checkSections(const std::vector<OptionSection>& sections,
                          const mrpt::config::CConfigFileBase& ini) {
  for (const auto& s : sections)
    if (s.check) s.check(ini);
}

}  // namespace budget_slam
