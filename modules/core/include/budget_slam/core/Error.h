#pragma once
#include <stdexcept>
#include <string>

namespace budget_slam {

/// A user-facing failure: its what() is one line that names the file, step or key at fault
/// (docs/ARCHITECTURE.md "Bad input"). Anything else escaping a run is a bug.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A bad configuration value, key or name (ini file, --set, command line).
class ConfigError : public Error {
 public:
  using Error::Error;
};

/// A bad value, or an unknown key, of one ini key: the message names section, key and value, and
/// section() and key() name them as data, so that the caller can say where the value came from
/// (the -c file, a rawlog's sidecar, --set) without reading it back out of the message.
/// key() is "" for an unknown section.
class KeyError : public ConfigError {
 public:
  KeyError(std::string section, std::string key, const std::string& message)
      : ConfigError(message), section_(std::move(section)), key_(std::move(key)) {}
  const std::string& section() const { return section_; }
  const std::string& key() const { return key_; }

 private:
  std::string section_, key_;
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
