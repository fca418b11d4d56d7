// budget-slam: landmark SLAM under a landmark budget. See DESIGN.md "Command line".
#include <iostream>

#include "BudgetSlamApp.h"
#include "budget_slam/core/Error.h"

int main(int argc, char** argv) {
  budget_slam::app::BudgetSlamApp app;
  try {
    app.initialize(argc, argv);
  } catch (const budget_slam::Error& e) {
    std::cerr << "budget-slam: " << e.what() << std::endl;
    return 2;
  }
  return app.run();
}
