#pragma once
// The values of a request that its type cannot check (docs/OUTPUTS.md "Command line and exit
// codes"), whoever filled it: the command line and the Python module call the same checks, and a
// bad value is a UsageError naming the flag (exit 2, nothing written).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/Error.h"
#include "budget_slam/runs/Request.h"

namespace budget_slam::runs {

/// The most seeds one compare runs (--seeds): each is a run per reducer.
constexpr std::size_t kMaxSeeds = 1000;

/// --seeds: "A:B" (A to B, both included), "A,B,C" or "A"; non-negative integers, each once.
std::vector<std::uint64_t> parseSeeds(const std::string& text);

/// --max-steps N: a number of steps >= 0 (0: the whole rawlog).
std::size_t parseMaxSteps(const std::string& text);
/// --skip-steps N: a count of steps (0 skips none).
std::size_t parseSkipSteps(const std::string& text);

/// --cap: a number of landmarks >= 1, or none. Throws UsageError naming the flag.
Cap parseCap(const std::string& text);

/// The values of run's and compare's flags: --backend and --reducer (registered names),
/// --reducers (registered, each once, never none), every --set (Section.key=value). Throws
/// UsageError naming the flag; a malformed --set is a ConfigError (the command line adds
/// "; see budget-slam <command> --help" to either).
void checkRequest(const RunRequest& request);
void checkRequest(const CompareRequest& request);
/// What a localize request must hold before anything runs (the command line's checks beyond
/// TCLAP's): a start pose that parses (parseStartPose), and not both a start pose and wake_up.
/// Throws ConfigError.
void checkRequest(const LocalizeRequest& request);

/// A flag given with an empty value (`--backend ''`) is refused: it would silently mean "not
/// given". Throws UsageError "--<flag> '': an empty value (leave the flag out instead)".
void refuseEmptyValue(const std::string& flag, const std::optional<std::string>& value);

/// What a refused value says to whoever filled the request: the check's line and where the
/// command's flags are explained ("...; see budget-slam <command> --help").
UsageError withHelpHint(const std::string& command, const ConfigError& e);

/// Throws UsageError "--wake-up: needs --resume RUN_DIR (...)" when the request wakes up on no
/// saved map (the command line says it as it is, without the --help hint).
void checkWakeUp(const RunRequest& request);

}  // namespace budget_slam::runs
