#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/NameKeyedRegistry.h"
#include "budget_slam/core/Reducer.h"

namespace budget_slam {

/// One registered reducer: how it is named, documented, configured and built.
struct ReducerEntry {
  /// Builds a reducer from the ini (its own section) and the run's seed.
  using Factory = std::function<std::unique_ptr<Reducer>(const mrpt::config::CConfigFileBase& ini,
                                                         std::uint64_t seed)>;
  std::string name;               ///< as written in the ini and on the command line
  std::string summary;            ///< one line for --help and docs
  std::string section;            ///< its ini section, empty when it has no options
  std::vector<std::string> keys;  ///< the keys of that section (for unknown-key checks)
  Factory factory;
};

/// Name-keyed factory of reducers (MOLA modules, g2o's type registry).
class ReducerRegistry : public NameKeyedRegistry<ReducerEntry> {
 public:
  using Factory = ReducerEntry::Factory;

  ReducerRegistry() : NameKeyedRegistry("reducer") {}

  /// Throws ConfigError "unknown reducer 'x' (registered: a, b, c)".
  std::unique_ptr<Reducer> create(const std::string& name, const mrpt::config::CConfigFileBase& ini,
                                  std::uint64_t seed) const {
    return entry(name).factory(ini, seed);
  }
};

}  // namespace budget_slam
