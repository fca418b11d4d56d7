#pragma once
#include <string>
#include <vector>

namespace budget_slam::app {

/// `budget-slam --list reducers|backends [--json]`: every registered reducer or backend with its
/// one-line summary and its options (section, key, default, comment), read from the registries
/// (the one list of them). With --json, one JSON array for scripts and the Python package:
///   [{"name": "mi", "summary": "...", "options": [{"section": "MutualInformationReducer",
///     "key": "mode", "default": "cap", "doc": "..."}, ...]}, ...]
/// ("default" is null for the keys MRPT's kf-slam defines). `args` is the whole command line
/// (args[1] == "--list"). Throws UsageError on anything else.
std::string listCommand(const std::vector<std::string>& args);

}  // namespace budget_slam::app
