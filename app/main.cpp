// budget-slam: landmark SLAM under a landmark budget. Exit codes: core/CommandLine.h.
#include <iostream>

#include "BudgetSlamApp.h"
#include "ProcessProbes.h"
#include "budget_slam/core/CommandLine.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/HeapRelease.h"
#include "budget_slam/core/StopSignals.h"
#include "budget_slam/core/Text.h"

int main(int argc, char** argv) {
  // For the life of the process: a signal during start-up or exit ends it like one during a run.
  const budget_slam::StopSignals signals(false);
  budget_slam::app::fitMallocToAddressSpaceLimit();
  budget_slam::holdMemoryReserve(std::size_t{16} << 20);  // for ending well when memory runs out
  budget_slam::app::BudgetSlamApp app;
  try {
    app.initialize(argc, argv);
  } catch (const budget_slam::Error& e) {
    // A bad command line or an unreadable -c file: nothing was written.
    std::cerr << "budget-slam: " << e.what() << std::endl;
    return budget_slam::kExitBadCommandLine;
  } catch (const std::exception& e) {
    std::cerr << "budget-slam: error: " << budget_slam::failureLine(e) << std::endl;
    return budget_slam::kExitFailed;
  }
  return app.run();
}
