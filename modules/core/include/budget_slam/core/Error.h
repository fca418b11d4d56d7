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

/// What a ConfigError is about, as data: a caller that words the error for its user (adds the
/// file or flag the setting came from) asks this, never the message.
enum class ConfigErrorKind {
  Invalid,         ///< any other bad setting
  BadValue,        ///< a value out of range, not of its type or not one of its choices
  UnknownSection,  ///< a section no part reads
  UnknownKey,      ///< a key its section does not have
  UnknownName,     ///< a name no registry holds (UnknownNameError)
  NeedsCap,        ///< max_landmarks = none with a reducer that drops only to keep a cap
};

/// A bad configuration value, key or name (ini file, --set, command line). `origin` is the file
/// or flag the message already names ("" when the caller is to say where the setting came from).
class ConfigError : public Error {
 public:
  explicit ConfigError(const std::string& message, ConfigErrorKind kind = ConfigErrorKind::Invalid,
                       std::string origin = "")
      : Error(message), kind_(kind), origin_(std::move(origin)) {}
  ConfigErrorKind kind() const { return kind_; }
  const std::string& origin() const { return origin_; }

 private:
  ConfigErrorKind kind_;
  std::string origin_;
};

/// A name no registry holds: "unknown reducer 'x' (registered: a, b, c)". registryKind() is what
/// the registry holds ("reducer", "backend"), name() the name asked for.
class UnknownNameError : public ConfigError {
 public:
  UnknownNameError(std::string registry_kind, std::string name, const std::string& message)
      : ConfigError(message, ConfigErrorKind::UnknownName),
        registry_kind_(std::move(registry_kind)),
        name_(std::move(name)) {}
  const std::string& registryKind() const { return registry_kind_; }
  const std::string& name() const { return name_; }

 private:
  std::string registry_kind_, name_;
};

/// A bad value, or an unknown key, of one ini key: the message names section, key and value, and
/// section() and key() name them as data, so that the caller can say where the value came from
/// (the -c file, a rawlog's sidecar, --set) without reading it back out of the message.
/// key() is "" for an unknown section.
class KeyError : public ConfigError {
 public:
  KeyError(std::string section, std::string key, const std::string& message,
           ConfigErrorKind kind = ConfigErrorKind::BadValue)
      : ConfigError(message, kind), section_(std::move(section)), key_(std::move(key)) {}
  /// "[section] key = value: why", with why() kept as data (a flag that gave the value says
  /// "--flag value: why" instead).
  static KeyError ofValue(const std::string& section, const std::string& key,
                          const std::string& value, const std::string& why,
                          ConfigErrorKind kind = ConfigErrorKind::BadValue) {
    KeyError e(section, key, "[" + section + "] " + key + " = " + value + ": " + why, kind);
    e.why_ = why;
    return e;
  }
  const std::string& section() const { return section_; }
  const std::string& key() const { return key_; }
  /// What is wrong with the value, without section, key and value ("" when not given apart).
  const std::string& why() const { return why_; }

 private:
  std::string section_, key_, why_;
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
