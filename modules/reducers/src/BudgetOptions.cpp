#include "budget_slam/reducers/BudgetOptions.h"

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSection.h"

namespace budget_slam::reducers {
namespace {

const EnumNames<BudgetOptions::Protect>& protectNames() {
  static const EnumNames<BudgetOptions::Protect> n = {
      {"recently_seen", BudgetOptions::Protect::RecentlySeen},
      {"newly_added", BudgetOptions::Protect::NewlyAdded}};
  return n;
}

const EnumNames<BudgetOptions::Admission>& admissionNames() {
  static const EnumNames<BudgetOptions::Admission> n = {
      {"always", BudgetOptions::Admission::Always}, {"compete", BudgetOptions::Admission::Compete}};
  return n;
}

const EnumNames<BudgetOptions::NegativeEvidenceMode>& negativeEvidenceNames() {
  using M = BudgetOptions::NegativeEvidenceMode;
  static const EnumNames<M> n = {{"off", M::Off}, {"over_cap", M::OverCap}, {"always", M::Always}};
  return n;
}

const EnumNames<BudgetOptions::MovedMode>& movedNames() {
  using M = BudgetOptions::MovedMode;
  static const EnumNames<M> n = {{"off", M::Off}, {"split", M::Split}};
  return n;
}

/// `max_landmarks`: a count >= 1, or `none` for no cap.
OptionKey<BudgetOptions> capKey() {
  return {"max_landmarks",
          [](BudgetOptions& o, const IniSection& s) {
            if (s.readString("max_landmarks", "") == "none") {
              o.max_landmarks.reset();
            } else if (s.has("max_landmarks")) {
              try {
                o.max_landmarks = static_cast<std::size_t>(s.readInt("max_landmarks", 50, 1));
              } catch (const KeyError& e) {
                throw KeyError(e.section(), e.key(),
                               std::string(e.what()) + " (or none for no cap)");
              }
            }
          },
          [](const BudgetOptions& o) { return BudgetOptions::capText(o.max_landmarks); },
          "[landmarks], >= 1, or none"};
}

}  // namespace

const OptionTable<BudgetOptions>& BudgetOptions::table() {
  using O = BudgetOptions;
  static const OptionTable<O> t = {
      option::text("reducer", &O::reducer, "registry name; none = no cap"),
      capKey(),
      option::integer("protect_recent_steps", &O::protect_recent_steps, 0,
                      std::numeric_limits<long long>::max(), "[steps]"),
      option::choice("protect", &O::protect, protectNames()),
      option::choice("admission", &O::admission, admissionNames()),
      option::integer("retry_after_steps", &O::retry_after_steps, 1, 1000000000, "[steps]"),
      option::integer("refusal_memory", &O::refusal_memory, 1, 100000000, "[entries]"),
      option::flag("readmit_evicted", &O::readmit_evicted),
      option::list("shadow_reducers", &O::shadow_reducers, "comma-separated registry names"),
      option::integer("seed", &O::seed, 0),
      option::flag("dump_states", &O::dump_states),
      option::choice("negative_evidence", &O::negative_evidence, negativeEvidenceNames()),
      option::integer("misses_to_distrust", &O::misses_to_distrust, 1, 1000000, "[passes]"),
      option::integer("miss_min_view_steps", &O::miss_min_view_steps, 1, 1000000, "[steps]"),
      option::real("viewpoint_cell", &O::viewpoint_cell, 1e-3, 1e6, "[m]"),
      option::real("view_margin_range", &O::view_margin_range, 0, 1e6, "[m]"),
      option::real("view_margin_deg", &O::view_margin_deg, 0, 180, "[deg]"),
      option::choice("moved_landmarks", &O::moved_landmarks, movedNames()),
      option::real("moved_gate_chi2", &O::moved_gate_chi2, 1e-3, 1e6, "chi-square, 2 dof"),
      option::integer("moved_readings", &O::moved_readings, 1, 1000000, "[readings]"),
      option::real("moved_place_distance", &O::moved_place_distance, 0, 1e6, "[m]"),
      option::integer("moved_min_agreeing", &O::moved_min_agreeing, 1, 1000000, "[landmarks]"),
  };
  return t;
}

std::string BudgetOptions::toString(Protect p) { return nameOf(protectNames(), p); }

std::string BudgetOptions::toString(Admission a) { return nameOf(admissionNames(), a); }

std::string BudgetOptions::toString(NegativeEvidenceMode m) {
  return nameOf(negativeEvidenceNames(), m);
}

std::string BudgetOptions::toString(MovedMode m) { return nameOf(movedNames(), m); }

std::string BudgetOptions::capText(const std::optional<std::size_t>& cap) {
  return cap ? std::to_string(*cap) : "none";
}

}  // namespace budget_slam::reducers
