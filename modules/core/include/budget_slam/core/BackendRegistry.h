#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/NameKeyedRegistry.h"

namespace budget_slam {

/// What a run asks of any backend beyond its own ini sections.
struct BackendSettings {
  /// false: trajectory() need hold only the latest pose (flat memory on lifelong runs; the
  /// per-step poses are in steps.csv). A backend whose estimate is the trajectory ignores it.
  bool keep_trajectory = true;
};

/// One registered backend: how it is named, documented, configured and built.
struct BackendEntry {
  using Factory = std::function<std::unique_ptr<Backend>(const mrpt::config::CConfigFileBase& ini,
                                                         const BackendSettings& settings)>;
  std::string name;     ///< as written in [MappingApplication] backend and after --backend
  std::string summary;  ///< one line for --help and docs
  /// The ini sections it reads and their keys (for unknown-key checks).
  std::map<std::string, std::vector<std::string>> sections;
  Factory factory;
};

/// Name-keyed factory of backends, registered as reducers are (ReducerRegistry).
class BackendRegistry : public NameKeyedRegistry<BackendEntry> {
 public:
  using Factory = BackendEntry::Factory;

  BackendRegistry() : NameKeyedRegistry("backend") {}

  /// Throws ConfigError "unknown backend 'x' (registered: a, b)".
  std::unique_ptr<Backend> create(const std::string& name, const mrpt::config::CConfigFileBase& ini,
                                  const BackendSettings& settings = {}) const {
    return entry(name).factory(ini, settings);
  }
};

}  // namespace budget_slam
