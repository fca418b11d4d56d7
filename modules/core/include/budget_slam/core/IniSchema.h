#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <map>
#include <string>
#include <vector>

namespace budget_slam {

/// The sections and keys a run understands, to reject typos (docs/ARCHITECTURE.md "Bad input": an
/// unknown key is named with the closest known one). Sections outside the schema are left alone
/// unless their name is a near miss of a known one (MRPT ini files hold other apps' sections too).
class IniSchema {
 public:
  void addSection(const std::string& section, const std::vector<std::string>& keys);
  bool hasSection(const std::string& section) const;

  /// Throws ConfigError for the first unknown key or misspelt section, e.g.
  ///   "unknown key [LandmarkBudget] max_landmark (did you mean max_landmarks?)".
  void validate(const mrpt::config::CConfigFileBase& ini) const;

 private:
  std::map<std::string, std::vector<std::string>> sections_;
};

/// Levenshtein distance, case-insensitive.
std::size_t editDistance(const std::string& a, const std::string& b);

/// The candidate closest to `word`, or "" when none is within a useful distance.
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace budget_slam
