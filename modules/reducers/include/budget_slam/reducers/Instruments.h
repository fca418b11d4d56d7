#pragma once
#include <string>
#include <vector>

namespace budget_slam::reducers {

/// The registry names of the reducers that are no rules but instruments of the benchmark's bounds
/// (`hindsight`, `known-set`; docs/EXPERIMENTS.md "Bounds"): run only when named, left out of
/// compare's default list of every reducer.
std::vector<std::string> instrumentNames();
bool isInstrument(const std::string& name);

}  // namespace budget_slam::reducers
