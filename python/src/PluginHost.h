#pragma once
// `budget-slam ... --plugin FILE.py`: reducers written in Python, in the command line's process
// (docs/PYTHON.md "A reducer in Python"). The executable embeds Python only when this file is
// compiled into it (BUDGET_SLAM_WITH_PYTHON; python/CMakeLists.txt).
#include <string>
#include <vector>

namespace budget_slam::python {

/// Takes every `--plugin FILE` and `--plugin=FILE` out of `args` (whatever the command: run,
/// compare, --list) and returns the files in order.
std::vector<std::string> takePluginFlags(std::vector<std::string>& args);

/// Starts Python in this process (without its own signal handlers: the application's stop
/// request keeps SIGINT and SIGTERM), makes the budget_slam package importable (this build's
/// python/ folder beside bin/, else PYTHONPATH) with its C++ half built in, and runs each file
/// (budget_slam.load_plugin), whose register_reducer() calls register its reducers. Then gives the
/// GIL up for the runs, which take it back at each call into a plugin. A file that cannot be read
/// or raises throws UsageError "--plugin FILE: <the Python error's last line>". Python stays
/// up for the life of the process.
void loadPlugins(const std::vector<std::string>& files);

}  // namespace budget_slam::python
