#pragma once
// Values of budget-slam's flags that TCLAP cannot check by type (docs/OUTPUTS.md "Command line
// and exit codes"): each bad one is a UsageError naming the flag (exit 2, nothing written).
#include <tclap/ValueArg.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace budget_slam::app {

/// The most seeds one compare runs (--seeds): each is a run per reducer.
constexpr std::size_t kMaxSeeds = 1000;

/// --seeds: "A:B" (A to B, both included), "A,B,C" or "A"; non-negative integers, each once.
std::vector<std::uint64_t> parseSeeds(const std::string& text);

/// --max-steps N: a number of steps >= 0 (0: the whole rawlog).
/// --skip-steps N: a count of steps (0 skips none).
std::size_t parseSkipSteps(const std::string& text);
std::size_t parseMaxSteps(const std::string& text);

/// A string flag given with an empty value (`--backend ''`) is refused: it would silently mean
/// "not given".
void refuseEmptyValues(const std::vector<const TCLAP::ValueArg<std::string>*>& flags);

}  // namespace budget_slam::app
