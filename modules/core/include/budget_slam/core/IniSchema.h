#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <map>
#include <string>
#include <vector>

namespace budget_slam {

/// The sections and keys a run understands, to reject typos (unknown key or section: say which
/// and suggest the closest). MRPT ini files may also hold sections of MRPT's other applications
/// (an ini shared with simul-landmarks, icp-slam, pf-localization...): those are declared
/// foreign, accepted and not read; any other section is an error.
class IniSchema {
 public:
  void addSection(const std::string& section, const std::vector<std::string>& keys);
  /// A section another application reads; a name ending in '*' declares every section starting
  /// with what precedes it (e.g. "RANDOMSET_*").
  void addForeignSection(const std::string& section);
  /// A section budget-slam reads (case-insensitive, as MRPT).
  bool hasSection(const std::string& section) const;
  bool isForeign(const std::string& section) const;

  /// Throws ConfigError for the first unknown section or key, e.g.
  ///   "unknown section [LandmarkBuget] (did you mean [LandmarkBudget]?)",
  ///   "unknown key [LandmarkBudget] max_landmark (did you mean max_landmarks?)".
  void validate(const mrpt::config::CConfigFileBase& ini) const;
  /// The message for an unknown section, with the closest known name when there is one.
  std::string unknownSection(const std::string& section) const;

 private:
  std::map<std::string, std::vector<std::string>> sections_;
  std::vector<std::string> foreign_, foreign_prefixes_;
};

/// Levenshtein distance, case-insensitive.
std::size_t editDistance(const std::string& a, const std::string& b);

/// The candidate closest to `word`, or "" when none is within a useful distance.
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace budget_slam
