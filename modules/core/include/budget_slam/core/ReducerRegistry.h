#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/Reducer.h"

namespace budget_slam {

/// Name-keyed factory of reducers (MOLA modules, g2o's type registry).
class ReducerRegistry {
 public:
  /// Builds a reducer from the ini (its own section) and the run's seed.
  using Factory = std::function<std::unique_ptr<Reducer>(const mrpt::config::CConfigFileBase& ini,
                                                         std::uint64_t seed)>;
  struct Entry {
    std::string name;               ///< as written in the ini and on the command line
    std::string summary;            ///< one line for --help and docs
    std::string section;            ///< its ini section, empty when it has no options
    std::vector<std::string> keys;  ///< the keys of that section (for unknown-key checks)
    Factory factory;
  };

  /// Throws std::logic_error on a duplicate name (a programming error).
  void add(Entry entry);

  bool has(const std::string& name) const;
  const Entry& entry(const std::string& name) const;  ///< throws ConfigError if unknown
  std::vector<std::string> names() const;             ///< sorted
  std::vector<const Entry*> entries() const;          ///< sorted by name

  /// Throws ConfigError "unknown reducer 'x' (registered: a, b, c)".
  std::unique_ptr<Reducer> create(const std::string& name, const mrpt::config::CConfigFileBase& ini,
                                  std::uint64_t seed) const;

 private:
  std::map<std::string, Entry> entries_;
};

}  // namespace budget_slam
