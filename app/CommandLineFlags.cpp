#include "CommandLineFlags.h"

#include "budget_slam/core/Error.h"

namespace budget_slam::app {

void refuseEmptyValues(const std::vector<const TCLAP::ValueArg<std::string>*>& flags) {
  for (const auto* f : flags)
    if (f->isSet() && f->getValue().empty())
      throw UsageError("--" + f->getName() + " '': an empty value (leave the flag out instead)");
}

}  // namespace budget_slam::app
