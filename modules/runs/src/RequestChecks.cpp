#include "budget_slam/runs/RequestChecks.h"

#include <cerrno>
#include <cstdlib>
#include <set>

#include "budget_slam/core/Error.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/runs/Localize.h"
#include "budget_slam/runs/RunConfig.h"

namespace budget_slam::runs {
namespace {

/// A non-negative integer, the whole text; false otherwise.
bool parseCount(const std::string& text, unsigned long long& value) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
  errno = 0;
  char* end = nullptr;
  value = std::strtoull(text.c_str(), &end, 10);
  return errno != ERANGE && end == text.c_str() + text.size();
}

/// --reducer and --reducers name registered reducers; compare's list holds each once and never
/// `none` (its reference run is always there).
void checkReducerFlags(const std::string& reducer, const std::vector<std::string>& compared) {
  const auto known = [](const std::string& flag, const std::string& name) {
    try {
      reducers::builtinReducers().entry(name);
    } catch (const ConfigError& e) {
      throw UsageError(flag + ": " + e.what());
    }
  };
  if (!reducer.empty()) known("--reducer", reducer);
  for (const auto& n : compared) {
    known("--reducers", n);
    if (n == "none") throw UsageError("--reducers: 'none' is the reference run, always included");
  }
  if (std::set<std::string>(compared.begin(), compared.end()).size() != compared.size())
    throw UsageError("--reducers: a reducer is listed twice");
}

}  // namespace

Cap parseCap(const std::string& v) {
  if (v == "none") return Cap{};
  char* end = nullptr;
  errno = 0;
  const long long n = std::strtoll(v.c_str(), &end, 10);
  if (v.empty() || end != v.c_str() + v.size() || errno == ERANGE)
    throw UsageError("--cap '" + v + "': not a number of landmarks, nor none");
  if (n < 1) throw UsageError("--cap " + v + ": must be at least 1 (or none for no cap)");
  return Cap{static_cast<std::size_t>(n)};
}

std::vector<std::uint64_t> parseSeeds(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return UsageError("--seeds '" + text + "': " + why);
  };
  std::vector<std::uint64_t> seeds;
  const auto colon = text.find(':');
  if (colon != std::string::npos) {
    unsigned long long a = 0, b = 0;
    if (!parseCount(text.substr(0, colon), a) || !parseCount(text.substr(colon + 1), b))
      throw bad("expected A:B, two seeds (integers >= 0)");
    if (b < a) throw bad("the last seed is before the first");
    if (b - a >= kMaxSeeds) throw bad("more than " + std::to_string(kMaxSeeds) + " seeds");
    for (unsigned long long s = a; s <= b; ++s) seeds.push_back(s);
    return seeds;
  }
  std::set<unsigned long long> seen;
  std::size_t start = 0;
  while (start <= text.size()) {
    const auto comma = text.find(',', start);
    const std::string item =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    unsigned long long s = 0;
    if (!parseCount(item, s))
      throw bad("expected A:B, or seeds separated by commas (integers >= 0)");
    if (!seen.insert(s).second) throw bad("seed " + item + " is listed twice");
    seeds.push_back(s);
    if (seeds.size() > kMaxSeeds) throw bad("more than " + std::to_string(kMaxSeeds) + " seeds");
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return seeds;
}

std::size_t parseMaxSteps(const std::string& text) {
  unsigned long long n = 0;
  if (!parseCount(text, n))
    throw UsageError("--max-steps '" + text + "': not a number of steps (0: the whole rawlog)");
  return static_cast<std::size_t>(n);
}

std::size_t parseSkipSteps(const std::string& text) {
  unsigned long long n = 0;
  if (!parseCount(text, n)) throw UsageError("--skip-steps '" + text + "': not a number of steps");
  // Step indices are written as int64 and must stay exact as doubles (a session state's bound).
  constexpr unsigned long long kMaxSkip = 1ULL << 53;
  if (n > kMaxSkip)
    throw UsageError("--skip-steps '" + text + "': more steps than a rawlog can hold (at most " +
                     std::to_string(kMaxSkip) + ")");
  return static_cast<std::size_t>(n);
}

void checkRequest(const RunRequest& request) {
  if (!request.backend.empty()) checkBackendFlag(request.backend);
  checkReducerFlags(request.reducer, {});
  for (const auto& set : request.common.sets) checkSet(set);
}

void checkRequest(const CompareRequest& request) {
  if (!request.backend.empty()) checkBackendFlag(request.backend);
  checkReducerFlags("", request.reducers);
  for (const auto& set : request.common.sets) checkSet(set);
}

void checkRequest(const LocalizeRequest& request) {
  if (request.start_pose) parseStartPose(*request.start_pose);
  if (request.start_pose && request.wake_up)
    throw ConfigError("--wake-up: not with --start-pose (a start pose is not looked for)");
}

void checkWakeUp(const RunRequest& request) {
  if (request.wake_up && request.resume.empty())
    throw UsageError("--wake-up: needs --resume RUN_DIR (the saved map to wake up on)");
}

void refuseEmptyValue(const std::string& flag, const std::optional<std::string>& value) {
  if (value && value->empty())
    throw UsageError("--" + flag + " '': an empty value (leave the flag out instead)");
}

UsageError withHelpHint(const std::string& command, const ConfigError& e) {
  return UsageError(e.what() + std::string("; see budget-slam ") + command + " --help");
}

}  // namespace budget_slam::runs
