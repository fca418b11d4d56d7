#include "ListCommand.h"

#include <nlohmann/json.hpp>

#include "budget_slam/core/Error.h"
#include "budget_slam/engine/BuiltinBackends.h"
#include "budget_slam/reducers/BuiltinReducers.h"

namespace budget_slam::app {
namespace {

/// One registry's entries (name, summary, sections) as --list shows them.
template <class Registry>
std::string listed(const Registry& registry, bool json) {
  if (json) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto* e : registry.entries()) {
      nlohmann::json options = nlohmann::json::array();
      for (const auto& s : e->sections)
        for (const auto& o : s.options)
          options.push_back({{"section", s.name},
                             {"key", o.key},
                             {"default", o.default_text ? nlohmann::json(*o.default_text)
                                                        : nlohmann::json(nullptr)},
                             {"doc", o.doc}});
      out.push_back({{"name", e->name}, {"summary", e->summary}, {"options", options}});
    }
    return out.dump(1) + "\n";
  }
  std::string text;
  for (const auto* e : registry.entries()) {
    text += e->name + ": " + e->summary + "\n";
    for (const auto& s : e->sections)
      for (const auto& o : s.options) {
        text += "    [" + s.name + "] " + o.key;
        if (o.default_text) text += " = " + *o.default_text;
        if (!o.doc.empty()) text += "  // " + o.doc;
        text += "\n";
      }
  }
  return text;
}

}  // namespace

std::string listCommand(const std::vector<std::string>& args) {
  const std::string usage = "--list: expected reducers or backends, then --json or nothing";
  if (args.size() < 3 || args.size() > 4) throw UsageError(usage);
  const bool json = args.size() == 4;
  if (json && args[3] != "--json") throw UsageError(usage);
  if (args[2] == "reducers") return listed(reducers::builtinReducers(), json);
  if (args[2] == "backends") return listed(runs::builtinBackends(), json);
  throw UsageError(usage);
}

}  // namespace budget_slam::app
