#include "ListCommand.h"

#include "budget_slam/core/Error.h"
#include "budget_slam/engine/RegistryListing.h"

namespace budget_slam::app {

std::string listCommand(const std::vector<std::string>& args) {
  const std::string usage = "--list: expected reducers or backends, then --json or nothing";
  if (args.size() < 3 || args.size() > 4) throw UsageError(usage);
  const bool json = args.size() == 4;
  if (json && args[3] != "--json") throw UsageError(usage);
  if (args[2] != "reducers" && args[2] != "backends") throw UsageError(usage);
  return json ? runs::registryEntries(args[2]).dump(1) + "\n" : runs::registryText(args[2]);
}

}  // namespace budget_slam::app
