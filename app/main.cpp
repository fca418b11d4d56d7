// budget-slam: landmark SLAM under a landmark budget. Exit codes: runs::exitCode
// (runs/RunStatus.h).
#include <iostream>
#include <string>
#include <vector>

#include "BudgetSlamApp.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/HeapRelease.h"
#include "budget_slam/core/StopSignals.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/engine/ProcessProbes.h"
#include "budget_slam/engine/RunStatus.h"
#ifdef BUDGET_SLAM_WITH_PYTHON
#include "PluginHost.h"  // --plugin FILE.py (python/src/PluginHost.cpp)
#endif

int main(int argc, char** argv) {
  namespace runs = budget_slam::runs;
  // For the life of the process: a signal during start-up or exit ends it like one during a run.
  const budget_slam::StopSignals signals(false);
  budget_slam::runs::fitMallocToAddressSpaceLimit();
  budget_slam::holdMemoryReserve(std::size_t{16} << 20);  // for ending well when memory runs out
  budget_slam::app::BudgetSlamApp app;
  try {
    std::vector<std::string> args(argv, argv + argc);
#ifdef BUDGET_SLAM_WITH_PYTHON
    // Reducers written in Python register before the command line is read (--reducer, --list).
    budget_slam::python::loadPlugins(budget_slam::python::takePluginFlags(args));
#endif
    app.initialize(args);
  } catch (const budget_slam::Error& e) {
    // A bad command line or an unreadable -c file: nothing was written.
    std::cerr << "budget-slam: " << e.what() << std::endl;
    return runs::exitCode(runs::RunStatus::Failed, runs::ErrorKind::CommandLine);
  } catch (const std::exception& e) {
    std::cerr << "budget-slam: error: " << budget_slam::failureLine(e) << std::endl;
    return runs::exitCode(runs::RunStatus::Failed, runs::ErrorKind::Internal);
  }
  return app.run();
}
