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
