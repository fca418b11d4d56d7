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

/// Bad input data: a missing, unreadable, truncated or malformed rawlog or data file.
class InputError : public Error {
 public:
  using Error::Error;
};

}  // namespace budget_slam
