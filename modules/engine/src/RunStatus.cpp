#include "budget_slam/engine/RunStatus.h"

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/CommandLine.h"
#include "budget_slam/core/Error.h"

namespace budget_slam::runs {

const char* statusName(RunStatus s) {
  switch (s) {
    case RunStatus::Ok:
      return "ok";
    case RunStatus::Failed:
      return "failed";
    case RunStatus::Interrupted:
      return "interrupted";
    case RunStatus::NotFound:
      return "not_found";
  }
  return "failed";
}

std::optional<RunStatus> parseStatus(const std::string& text) {
  for (const auto s :
       {RunStatus::Ok, RunStatus::Failed, RunStatus::Interrupted, RunStatus::NotFound})
    if (text == statusName(s)) return s;
  return std::nullopt;
}

const char* errorKindName(ErrorKind k) {
  switch (k) {
    case ErrorKind::None:
      return "none";
    case ErrorKind::CommandLine:
      return "command_line";
    case ErrorKind::Config:
      return "config";
    case ErrorKind::Input:
      return "input";
    case ErrorKind::Diverged:
      return "diverged";
    case ErrorKind::Output:
      return "output";
    case ErrorKind::Stopped:
      return "stopped";
    case ErrorKind::Internal:
      return "internal";
  }
  return "internal";
}

ErrorKind errorKindOf(const std::exception& e) {
  if (dynamic_cast<const Interrupted*>(&e)) return ErrorKind::Stopped;
  if (dynamic_cast<const UsageError*>(&e)) return ErrorKind::CommandLine;
  if (dynamic_cast<const ConfigError*>(&e)) return ErrorKind::Config;
  if (dynamic_cast<const InputError*>(&e)) return ErrorKind::Input;
  if (dynamic_cast<const Error*>(&e)) return ErrorKind::Input;  // bad data met while running
  return ErrorKind::Internal;
}

int exitCode(RunStatus status, ErrorKind kind) {
  switch (status) {
    case RunStatus::Ok:
      return kExitOk;
    case RunStatus::Interrupted:
      return kExitInterrupted;
    case RunStatus::NotFound:
      return kExitNotFound;
    case RunStatus::Failed:
      return kind == ErrorKind::CommandLine ? kExitBadCommandLine : kExitFailed;
  }
  return kExitFailed;
}

}  // namespace budget_slam::runs
