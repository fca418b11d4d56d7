// budget-slam compare: the request to runs::compare (modules/runs/src/CompareCommand.cpp), then
// its table on stdout, its lines on stderr and its exit code (docs/ARCHITECTURE.md "A compare").
#include <iostream>

#include "BudgetSlamApp.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/runs/Commands.h"

namespace budget_slam::app {

int BudgetSlamApp::runCompare(const runs::CompareRequest& request) {
  const runs::CompareReport r = runs::compare(request, requestContext(), requestHooks());
  const runs::CompareOutcome& outcome = r.outcome;
  if (r.started && !request.common.quiet && !r.markdown.empty())
    *out << r.markdown << "outputs in " << r.folder << "/\n";
  for (const auto& line : outcome.lines)
    *err << "budget-slam: " << printable(line.shown()) << std::endl;
  if (r.started && !stdoutWritten(r.folder) && outcome.status == runs::RunStatus::Ok)
    return runs::exitCode(runs::RunStatus::Failed, runs::ErrorKind::Output);
  return outcome.exitCode();
}

}  // namespace budget_slam::app
