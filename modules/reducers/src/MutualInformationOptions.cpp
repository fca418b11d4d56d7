#include "budget_slam/reducers/MutualInformationOptions.h"

namespace budget_slam::reducers {
namespace {

const EnumNames<MutualInformationOptions::Mode>& modeNames() {
  using Mode = MutualInformationOptions::Mode;
  static const EnumNames<Mode> n = {
      {"cap", Mode::Cap}, {"objective", Mode::Objective}, {"incremental", Mode::Incremental}};
  return n;
}

const EnumNames<MutualInformationOptions::Stop>& stopNames() {
  using Stop = MutualInformationOptions::Stop;
  static const EnumNames<Stop> n = {{"first_increase", Stop::FirstIncrease},
                                    {"global_minimum", Stop::GlobalMinimum}};
  return n;
}

}  // namespace

const OptionTable<MutualInformationOptions>& MutualInformationOptions::table() {
  using O = MutualInformationOptions;
  // IniSection names the key in the error: "[MutualInformationReducer] lambda = 1.5: must be at
  // most 1".
  static const OptionTable<O> t = {
      option::choice("mode", &O::mode, modeNames()),
      option::real("lambda", &O::lambda, 0.0, 1.0, "rho's weight of memory, Eq. 4"),
      option::integer("psi", &O::psi, 1, std::numeric_limits<long long>::max(), "[steps]"),
      option::integer("pose_lag", &O::pose_lag, 0, std::numeric_limits<long long>::max(),
                      "[steps]"),
      option::choice("stop", &O::stop, stopNames()),
  };
  return t;
}

std::string MutualInformationOptions::stopName(Stop s) { return nameOf(stopNames(), s); }

std::string MutualInformationOptions::modeName(Mode m) { return nameOf(modeNames(), m); }

}  // namespace budget_slam::reducers
