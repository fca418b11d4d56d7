#include "budget_slam/reducers/Instruments.h"

#include <algorithm>

#include "budget_slam/reducers/HindsightReducer.h"
#include "budget_slam/reducers/KnownSetReducer.h"

namespace budget_slam::reducers {

std::vector<std::string> instrumentNames() {
  return {HindsightReducer::kName, KnownSetReducer::kName};
}

bool isInstrument(const std::string& name) {
  const auto names = instrumentNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace budget_slam::reducers
