#pragma once
#include <stdexcept>
#include <string>

namespace budget_slam {

/// A user-facing failure: its what() is one line that names the file, step or key at fault
/// (DESIGN.md "Bad input"). Anything else escaping a run is a bug.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A bad configuration value, key or name (ini file, --set, command line).
class ConfigError : public Error {
 public:
  using Error::Error;
};

/// A bad command line: an unknown flag, or a flag value that is not of the flag's type, not one
/// of its choices or out of its range. The executables exit with 2 (core/CommandLine.h).
class UsageError : public ConfigError {
 public:
  using ConfigError::ConfigError;
};

/// Bad input data: a missing, unreadable, truncated or malformed rawlog or data file.
class InputError : public Error {
 public:
  using Error::Error;
};

}  // namespace budget_slam
