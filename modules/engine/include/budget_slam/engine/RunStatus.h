#pragma once
#include <exception>
#include <optional>
#include <string>

namespace budget_slam::runs {

/// How a run, a comparison or a localization ended: summary.json "status" (docs/OUTPUTS.md).
enum class RunStatus {
  Ok,           ///< "ok": every step and every output done
  Failed,       ///< "failed": bad input, a bad value, a diverged estimate, an output not written
  Interrupted,  ///< "interrupted": a stop request (Ctrl-C, SIGTERM)
  NotFound,     ///< "not_found": localize woke up and found the robot nowhere on the map
};

/// Where a failure came from, decided where it was caught (by the exception's type or the check
/// that failed), never by reading its message.
enum class ErrorKind {
  None,         ///< no failure
  CommandLine,  ///< a bad command line (core/Error.h UsageError) before anything ran
  Config,       ///< a bad ini value, key, section or name (ConfigError)
  Input,        ///< a missing, unreadable, truncated or malformed file (InputError)
  Diverged,     ///< the estimate is not finite
  Output,       ///< an output file could not be written
  Stopped,      ///< a stop request
  Internal,     ///< anything else (a bug, out of memory)
};

/// summary.json's word for `s`: ok, failed, interrupted, not_found.
const char* statusName(RunStatus s);
/// The status summary.json's `text` names; none for another text.
std::optional<RunStatus> parseStatus(const std::string& text);
/// A name for `k` (tests and the Python module): none, command_line, config, input, ...
const char* errorKindName(ErrorKind k);

/// The kind of a failure caught as `e` (by its type: UsageError, ConfigError, InputError, the
/// stop request's Interrupted; anything else is internal).
ErrorKind errorKindOf(const std::exception& e);

/// The one mapping from how something ended to the process exit code (docs/OUTPUTS.md "Command
/// line and exit codes"): 0 ok, 2 a bad command line, 3 not found on the map, 130 interrupted, 1
/// any other failure.
int exitCode(RunStatus status, ErrorKind kind = ErrorKind::None);

}  // namespace budget_slam::runs
