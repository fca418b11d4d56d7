#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <limits>
#include <string>
#include <vector>

namespace budget_slam {

/// Typed, checked reading of one section of an MRPT ini file. Every failure is a ConfigError
/// whose message names the section and key, e.g.
///   "[LandmarkBudget] max_landmarks = 0: must be at least 1".
/// Values may carry MRPT's trailing comments ("2  // degs").
class IniSection {
 public:
  IniSection(const mrpt::config::CConfigFileBase& ini, std::string section);

  const std::string& name() const { return section_; }
  bool has(const std::string& key) const;

  std::string readString(const std::string& key, const std::string& def) const;
  /// A finite number in [lo, hi] (NaN and infinities are refused whatever the bounds).
  double readDouble(const std::string& key, double def,
                    double lo = -std::numeric_limits<double>::infinity(),
                    double hi = std::numeric_limits<double>::infinity()) const;
  /// A standard deviation: finite and > 0, and within [kMinStd, kMaxStd] so that its square
  /// (and MRPT's 32-bit float copy of it) stays a normal, invertible number.
  double readStd(const std::string& key, double def) const;
  static constexpr double kMinStd = 1e-12, kMaxStd = 1e12;
  long long readInt(const std::string& key, long long def,
                    long long lo = std::numeric_limits<long long>::min(),
                    long long hi = std::numeric_limits<long long>::max()) const;
  bool readBool(const std::string& key, bool def) const;
  /// One of `allowed` (case-sensitive).
  std::string readChoice(const std::string& key, const std::string& def,
                         const std::vector<std::string>& allowed) const;
  /// Comma- or space-separated list; empty when the key is absent or blank.
  std::vector<std::string> readList(const std::string& key) const;

 private:
  std::string raw(const std::string& key) const;  ///< trimmed value without trailing comment
  [[noreturn]] void fail(const std::string& key, const std::string& value,
                         const std::string& why) const;

  const mrpt::config::CConfigFileBase& ini_;
  std::string section_;
};

}  // namespace budget_slam
