#pragma once
// What `budget-slam --list reducers|backends` shows and budget_slam.reducers() / backends()
// return: every registered reducer or backend with its one-line summary and its options, read
// from the registries (the one list of them).
#include <nlohmann/json.hpp>
#include <string>

namespace budget_slam::runs {

/// The program's version ("budget-slam <version>" is the session state's writer).
inline constexpr const char* kVersion = "0.1";

/// The registry `kind` names ("reducers" or "backends") as a JSON array:
///   [{"name": "mi", "summary": "...", "options": [{"section": "MutualInformationReducer",
///     "key": "mode", "default": "cap", "doc": "..."}, ...]}, ...]
/// ("default" is null for the keys MRPT's kf-slam defines). Throws UsageError for another kind.
nlohmann::json registryEntries(const std::string& kind);

/// The same as text: a line "name: summary" an entry, then a line "    [Section] key = default
/// // doc" an option.
std::string registryText(const std::string& kind);

}  // namespace budget_slam::runs
