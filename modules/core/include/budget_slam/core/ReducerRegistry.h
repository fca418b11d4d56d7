#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/NameKeyedRegistry.h"
#include "budget_slam/core/OptionSection.h"
#include "budget_slam/core/Reducer.h"

namespace budget_slam {

/// What a registered reducer is for. The experiments take their candidates from the registry:
/// every rule (`budget-slam --list reducers --json`, "role").
enum class ReducerRole {
  Rule,       ///< chooses what to drop under a cap: a candidate of the benchmark and the tables
  Reference,  ///< `none`: no cap, the reference run
  Bound,      ///< an instrument of the benchmark's bounds (hindsight, known-set), not a rule
};

/// "rule", "reference" or "bound": the role's name in `--list reducers --json`.
inline const char* reducerRoleName(ReducerRole role) {
  switch (role) {
    case ReducerRole::Reference:
      return "reference";
    case ReducerRole::Bound:
      return "bound";
    case ReducerRole::Rule:
      break;
  }
  return "rule";
}

/// One registered reducer: how it is named, documented, configured, checked and built. The one
/// list of a reducer's facts: the command line, `--help`, `--list reducers`, the unknown-key check
/// and the value check before a run all read it.
struct ReducerEntry {
  /// Builds a reducer from the ini (its own sections) and the run's seed.
  using Factory = std::function<std::unique_ptr<Reducer>(const mrpt::config::CConfigFileBase& ini,
                                                         std::uint64_t seed)>;
  std::string name;     ///< as written in the ini and on the command line
  std::string summary;  ///< one line for --help and --list
  /// The ini sections it reads, in the order it reads them (none: no options).
  std::vector<OptionSection> sections;
  Factory factory;
  ReducerRole role = ReducerRole::Rule;  ///< what it is for (a rule unless the entry says so)

  /// Checks every value it would read from `ini`, without building it: the first bad one throws
  /// its KeyError naming section, key and value.
  void validate(const mrpt::config::CConfigFileBase& ini) const { checkSections(sections, ini); }
};

/// Name-keyed factory of reducers (MOLA modules, g2o's type registry).
class ReducerRegistry : public NameKeyedRegistry<ReducerEntry> {
 public:
  using Factory = ReducerEntry::Factory;

  ReducerRegistry() : NameKeyedRegistry("reducer") {}

  /// Throws UnknownNameError "unknown reducer 'x' (registered: a, b, c)".
  std::unique_ptr<Reducer> create(const std::string& name, const mrpt::config::CConfigFileBase& ini,
                                  std::uint64_t seed) const {
    return entry(name).factory(ini, seed);
  }
};

}  // namespace budget_slam
