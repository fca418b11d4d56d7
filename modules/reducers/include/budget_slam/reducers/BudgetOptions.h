#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"

namespace budget_slam::reducers {

/// [LandmarkBudget]: how many landmarks the map may hold, who decides which one goes, which
/// landmarks may not go yet and how a newcomer gets in (docs/ALGORITHMS.md "Common to every
/// reducer").
struct BudgetOptions : public TabledOptions<BudgetOptions> {
  static constexpr const char* kSection = "LandmarkBudget";

  /// Which landmarks `protect_recent_steps` shields from a cap decision.
  enum class Protect {
    RecentlySeen,  ///< recently_seen: every landmark seen in the last P steps (all in view)
    NewlyAdded,    ///< newly_added: a landmark only during its first P steps in the map
  };
  /// How a landmark first observed while the map is full gets in.
  enum class Admission {
    Always,   ///< always: it enters; the cap then drops among the unprotected landmarks
    Compete,  ///< compete: it is a candidate of that same cap decision and stays only if the
              ///< reducer would rather drop a kept landmark; refused ids wait before a retry
  };

  /// What the budget does with a landmark it distrusts: one missed in view, pass after pass
  /// (NegativeEvidence.h; docs/ALGORITHMS.md "Negative evidence").
  enum class NegativeEvidenceMode {
    Off,      ///< off: no record, no effect
    OverCap,  ///< over_cap: over the cap, a distrusted landmark goes before the reducer is asked
    Always,   ///< always: a distrusted landmark goes at once, under the cap too
  };
  /// What the budget does with a landmark whose readings persistently disagree with its estimate
  /// while the rest of the view agrees (MovedLandmarks.h; docs/ALGORITHMS.md "Moved landmarks").
  enum class MovedMode {
    Off,    ///< off: every reading is fused
    Split,  ///< split: its readings are held; once it has moved, the old estimate leaves the map
            ///< (reason moved) and the readings start a new landmark
  };

  std::string reducer = "none";  ///< active reducer by registry name; none = no cap
  /// The cap: landmarks in the map after every step, >= 1 [landmarks]. Empty (ini and --cap:
  /// `none`) = unbounded, valid only for reducer `none` and for reducers that decide the map's
  /// size themselves (Reducer::decidesMapSize; checkCap).
  std::optional<std::size_t> max_landmarks = 50;
  std::size_t protect_recent_steps = 5;     ///< P: landmarks protected by `protect` [steps]
  Protect protect = Protect::RecentlySeen;  ///< recently_seen | newly_added
  Admission admission = Admission::Always;  ///< always | compete
  std::size_t retry_after_steps = 10;       ///< compete: a refused id's readings are left out for
                                            ///< this many steps, doubled at each further refusal of
                                            ///< the same id (at most 64 times) [steps], >= 1
  std::size_t refusal_memory = 1024;        ///< compete: refused ids remembered at most; the oldest
                                            ///< refusal is forgotten first [entries], >= 1
  bool readmit_evicted = true;              ///< a dropped landmark seen again comes back as new
  std::vector<std::string> shadow_reducers;  ///< asked at every drop, only logged
  std::uint64_t seed = 1;                    ///< seed of every randomized reducer
  bool dump_states = false;                  ///< write states/step_<k>.txt before each drop event
  NegativeEvidenceMode negative_evidence = NegativeEvidenceMode::Off;  ///< off | over_cap | always
  std::size_t misses_to_distrust = 2;   ///< K: passes through view without a sighting that make a
                                        ///< landmark distrusted [passes], >= 1
  std::size_t miss_min_view_steps = 2;  ///< steps of a pass in view without a sighting that make
                                        ///< the pass a miss [steps], >= 1
  double viewpoint_cell = 0.5;     ///< side of the place cells a landmark is expected from [m], > 0
  double view_margin_range = 0.5;  ///< a landmark is in view this far inside the sensor's range
                                   ///< limits [m], >= 0
  double view_margin_deg = 5;      ///< ... and this far inside its field of view's edges [deg]
  MovedMode moved_landmarks = MovedMode::Off;  ///< off | split
  double moved_gate_chi2 = 13.8155;    ///< innovation gate of a reading, chi-square 2 dof (99.9%)
  std::size_t moved_readings = 3;      ///< readings outside the gate, from distinct places, that
                                       ///< make a landmark moved [readings], >= 1
  double moved_place_distance = 0.5;   ///< robot positions of two such readings at least [m], >= 0
  std::size_t moved_min_agreeing = 2;  ///< other landmarks of the step inside their gates (and
                                       ///< more than those outside) for a reading to count, >= 1

  /// Every key: name, field, check and unit (the defaults are the initializers above).
  static const OptionTable<BudgetOptions>& table();
  /// The cap as written in the ini and on the command line: a number, or `none`.
  static std::string capText(const std::optional<std::size_t>& cap);

  static std::string toString(Protect p);
  static std::string toString(Admission a);
  static std::string toString(NegativeEvidenceMode m);
  static std::string toString(MovedMode m);
};

}  // namespace budget_slam::reducers
