#include "budget_slam/core/ReducerRegistry.h"

#include <stdexcept>

#include "budget_slam/core/Error.h"

namespace budget_slam {

void ReducerRegistry::add(Entry entry) {
  const std::string name = entry.name;
  if (!entries_.emplace(name, std::move(entry)).second)
    throw std::logic_error("reducer '" + name + "' registered twice");
}

bool ReducerRegistry::has(const std::string& name) const { return entries_.count(name) > 0; }

std::vector<std::string> ReducerRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, e] : entries_) out.push_back(name);
  return out;
}

std::vector<const ReducerRegistry::Entry*> ReducerRegistry::entries() const {
  std::vector<const Entry*> out;
  for (const auto& [name, e] : entries_) out.push_back(&e);
  return out;
}

const ReducerRegistry::Entry& ReducerRegistry::entry(const std::string& name) const {
  const auto it = entries_.find(name);
  if (it == entries_.end()) {
    std::string list;
    for (const auto& n : names()) list += (list.empty() ? "" : ", ") + n;
    throw ConfigError("unknown reducer '" + name + "' (registered: " + list + ")");
  }
  return it->second;
}

std::unique_ptr<Reducer> ReducerRegistry::create(const std::string& name,
                                                 const mrpt::config::CConfigFileBase& ini,
                                                 std::uint64_t seed) const {
  return entry(name).factory(ini, seed);
}

}  // namespace budget_slam
