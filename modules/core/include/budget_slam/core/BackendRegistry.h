#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/NameKeyedRegistry.h"
#include "budget_slam/core/OptionSection.h"

namespace budget_slam {

/// What a run asks of any backend beyond its own ini sections.
struct BackendSettings {
  /// false: trajectory() need hold only the latest pose (flat memory on lifelong runs; the
  /// per-step poses are in steps.csv). A backend whose estimate is the trajectory ignores it.
  bool keep_trajectory = true;
};

/// One registered backend: how it is named, documented, configured, checked and built (the one
/// list of a backend's facts, as ReducerEntry is a reducer's).
struct BackendEntry {
  using Factory = std::function<std::unique_ptr<Backend>(const mrpt::config::CConfigFileBase& ini,
                                                         const BackendSettings& settings)>;
  std::string name;     ///< as written in [MappingApplication] backend and after --backend
  std::string summary;  ///< one line for --help and --list
  /// The ini sections it reads, in the order it reads them.
  std::vector<OptionSection> sections;
  Factory factory;

  /// Checks every value it would read from `ini`, without building it (ReducerEntry::validate).
  void validate(const mrpt::config::CConfigFileBase& ini) const { checkSections(sections, ini); }
};

/// Name-keyed factory of backends, registered as reducers are (ReducerRegistry).
class BackendRegistry : public NameKeyedRegistry<BackendEntry> {
 public:
  using Factory = BackendEntry::Factory;

  BackendRegistry() : NameKeyedRegistry("backend") {}

  /// Throws UnknownNameError "unknown backend 'x' (registered: a, b)".
  std::unique_ptr<Backend> create(const std::string& name, const mrpt::config::CConfigFileBase& ini,
                                  const BackendSettings& settings = {}) const {
    return entry(name).factory(ini, settings);
  }
};

}  // namespace budget_slam
