// budget-slam: landmark SLAM under a landmark budget. Exit codes: core/CommandLine.h.
#include <iostream>

#include "BudgetSlamApp.h"
#include "budget_slam/core/CommandLine.h"
#include "budget_slam/core/Error.h"

int main(int argc, char** argv) {
  budget_slam::app::BudgetSlamApp app;
  try {
    app.initialize(argc, argv);
  } catch (const budget_slam::Error& e) {
    // A bad command line or an unreadable -c file: nothing was written.
    std::cerr << "budget-slam: " << e.what() << std::endl;
    return budget_slam::kExitBadCommandLine;
  }
  return app.run();
}
