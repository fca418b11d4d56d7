#include "budget_slam/reducers/MutualInformationOptions.h"

#include <ostream>

#include "budget_slam/core/IniSection.h"

namespace budget_slam::reducers {

void MutualInformationOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                                                  const std::string& section) {
  const IniSection s(ini, section);
  const std::string m = s.readChoice("mode", modeName(mode), {"cap", "objective", "incremental"});
  mode = m == "cap" ? Mode::Cap : m == "objective" ? Mode::Objective : Mode::Incremental;
  // IniSection names the key in the error: "[MutualInformationReducer] lambda = 1.5: must be at
  // most 1".
  lambda = s.readDouble("lambda", lambda, 0.0, 1.0);
  psi = static_cast<std::size_t>(s.readInt("psi", static_cast<long long>(psi), 1));
  pose_lag = static_cast<std::size_t>(s.readInt("pose_lag", static_cast<long long>(pose_lag), 0));
  const std::string st = s.readChoice(
      "stop", stopName(stop), {stopName(Stop::FirstIncrease), stopName(Stop::GlobalMinimum)});
  stop = st == stopName(Stop::FirstIncrease) ? Stop::FirstIncrease : Stop::GlobalMinimum;
}

void MutualInformationOptions::dumpToTextStream(std::ostream& out) const {
  out << "\n----------- [" << kSection << "] ------------\n";
  out << "mode                     = " << modeName(mode) << "\n";
  out << "lambda                   = " << lambda << "\n";
  out << "psi                      = " << psi << "  // [steps]\n";
  out << "pose_lag                 = " << pose_lag << "  // [steps]\n";
  out << "stop                     = " << stopName(stop)
      << "  // first_increase | global_minimum\n";
}

std::vector<std::string> MutualInformationOptions::keys() {
  return {"mode", "lambda", "psi", "pose_lag", "stop"};
}

std::string MutualInformationOptions::stopName(Stop s) {
  return s == Stop::FirstIncrease ? "first_increase" : "global_minimum";
}

std::string MutualInformationOptions::modeName(Mode m) {
  switch (m) {
    case Mode::Cap:
      return "cap";
    case Mode::Objective:
      return "objective";
    case Mode::Incremental:
      return "incremental";
  }
  return "cap";
}

}  // namespace budget_slam::reducers
