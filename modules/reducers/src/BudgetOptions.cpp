#include "budget_slam/reducers/BudgetOptions.h"

#include <ostream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"

namespace budget_slam::reducers {

std::string BudgetOptions::toString(Protect p) {
  return p == Protect::RecentlySeen ? "recently_seen" : "newly_added";
}

std::string BudgetOptions::toString(Admission a) {
  return a == Admission::Always ? "always" : "compete";
}

void BudgetOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                                       const std::string& section) {
  const IniSection s(ini, section);
  reducer = s.readString("reducer", reducer);
  if (s.readString("max_landmarks", "") == "none") {
    max_landmarks.reset();
  } else if (s.has("max_landmarks")) {
    try {
      max_landmarks = static_cast<std::size_t>(s.readInt("max_landmarks", 50, 1));
    } catch (const ConfigError& e) {
      throw ConfigError(std::string(e.what()) + " (or none for no cap)");
    }
  }
  protect_recent_steps = static_cast<std::size_t>(
      s.readInt("protect_recent_steps", static_cast<long long>(protect_recent_steps), 0));
  protect = s.readChoice("protect", toString(protect), {"recently_seen", "newly_added"}) ==
                    "recently_seen"
                ? Protect::RecentlySeen
                : Protect::NewlyAdded;
  admission = s.readChoice("admission", toString(admission), {"always", "compete"}) == "always"
                  ? Admission::Always
                  : Admission::Compete;
  retry_after_steps = static_cast<std::size_t>(
      s.readInt("retry_after_steps", static_cast<long long>(retry_after_steps), 1, 1000000000));
  refusal_memory = static_cast<std::size_t>(
      s.readInt("refusal_memory", static_cast<long long>(refusal_memory), 1, 100000000));
  readmit_evicted = s.readBool("readmit_evicted", readmit_evicted);
  if (s.has("shadow_reducers")) shadow_reducers = s.readList("shadow_reducers");
  seed = static_cast<std::uint64_t>(s.readInt("seed", static_cast<long long>(seed), 0));
  dump_states = s.readBool("dump_states", dump_states);
}

void BudgetOptions::dumpToTextStream(std::ostream& out) const {
  out << "\n----------- [" << kSection << "] ------------\n";
  out << "reducer                  = " << reducer << "\n";
  out << "max_landmarks            = " << capText(max_landmarks) << "\n";
  out << "protect_recent_steps     = " << protect_recent_steps << "\n";
  out << "protect                  = " << toString(protect) << "\n";
  out << "admission                = " << toString(admission) << "\n";
  out << "retry_after_steps        = " << retry_after_steps << "\n";
  out << "refusal_memory           = " << refusal_memory << "\n";
  out << "readmit_evicted          = " << (readmit_evicted ? "true" : "false") << "\n";
  out << "shadow_reducers          = ";
  for (std::size_t i = 0; i < shadow_reducers.size(); ++i)
    out << (i ? "," : "") << shadow_reducers[i];
  out << "\nseed                     = " << seed << "\n";
  out << "dump_states              = " << (dump_states ? "true" : "false") << "\n";
}

std::string BudgetOptions::capText(const std::optional<std::size_t>& cap) {
  return cap ? std::to_string(*cap) : "none";
}

std::vector<std::string> BudgetOptions::keys() {
  return {"reducer",        "max_landmarks",   "protect_recent_steps",
          "protect",        "admission",       "retry_after_steps",
          "refusal_memory", "readmit_evicted", "shadow_reducers",
          "seed",           "dump_states"};
}

}  // namespace budget_slam::reducers
