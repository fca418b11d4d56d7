#include "CommandLineFlags.h"

namespace budget_slam::app {

void refuseEmptyValues(const std::vector<const TCLAP::ValueArg<std::string>*>& flags) {
  for (const auto* f : flags)
    if (f->isSet()) runs::refuseEmptyValue(f->getName(), f->getValue());
}

}  // namespace budget_slam::app
