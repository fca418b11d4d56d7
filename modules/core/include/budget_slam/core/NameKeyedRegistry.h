#pragma once
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "budget_slam/core/Error.h"

namespace budget_slam {

/// The lookup half shared by every name-keyed factory of a pluggable kind (ReducerRegistry,
/// BackendRegistry; as MOLA's module registry and g2o's type factory): entries kept sorted by
/// name, a duplicate name is a programming error, an unknown one a ConfigError that lists the
/// registered names. `EntryT` has a `std::string name` member.
template <class EntryT>
class NameKeyedRegistry {
 public:
  using Entry = EntryT;

  /// `kind` names what is registered in error messages ("reducer", "backend").
  explicit NameKeyedRegistry(std::string kind) : kind_(std::move(kind)) {}

  /// Throws std::logic_error on a duplicate name.
  void add(Entry entry) {
    const std::string name = entry.name;
    if (!entries_.emplace(name, std::move(entry)).second)
      throw std::logic_error(kind_ + " '" + name + "' registered twice");
  }

  bool has(const std::string& name) const { return entries_.count(name) > 0; }

  /// Throws ConfigError "unknown <kind> 'x' (registered: a, b, c)".
  const Entry& entry(const std::string& name) const {
    const auto it = entries_.find(name);
    if (it == entries_.end())
      throw UnknownNameError(
          kind_, name,
          "unknown " + kind_ + " '" + name + "' (registered: " + joinedNames(", ") + ")");
    return it->second;
  }

  /// Sorted.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& [name, e] : entries_) out.push_back(name);
    return out;
  }

  /// The sorted names joined by `separator` ("ekf|graph" for a usage line).
  std::string joinedNames(const std::string& separator) const {
    std::string out;
    for (const auto& [name, e] : entries_) out += (out.empty() ? "" : separator) + name;
    return out;
  }

  /// Sorted by name.
  std::vector<const Entry*> entries() const {
    std::vector<const Entry*> out;
    for (const auto& [name, e] : entries_) out.push_back(&e);
    return out;
  }

 private:
  std::string kind_;
  std::map<std::string, Entry> entries_;
};

}  // namespace budget_slam
