#include "budget_slam/engine/RegistryListing.h"

#include <type_traits>

#include "budget_slam/core/Error.h"
#include "budget_slam/engine/BuiltinBackends.h"
#include "budget_slam/reducers/BuiltinReducers.h"

namespace budget_slam::runs {
namespace {

template <class Registry>
nlohmann::json entriesOf(const Registry& registry) {
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
    if constexpr (std::is_same_v<std::decay_t<decltype(*e)>, ReducerEntry>)
      out.back()["role"] = reducerRoleName(e->role);
  }
  return out;
}

template <class Registry>
std::string textOf(const Registry& registry) {
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

[[noreturn]] void unknownKind(const std::string& kind) {
  throw UsageError("--list " + kind + ": expected reducers or backends");
}

}  // namespace

nlohmann::json registryEntries(const std::string& kind) {
  if (kind == "reducers") return entriesOf(reducers::builtinReducers());
  if (kind == "backends") return entriesOf(builtinBackends());
  unknownKind(kind);
}

std::string registryText(const std::string& kind) {
  if (kind == "reducers") return textOf(reducers::builtinReducers());
  if (kind == "backends") return textOf(builtinBackends());
  unknownKind(kind);
}

}  // namespace budget_slam::runs
