#pragma once
#include "budget_slam/core/ReducerRegistry.h"
#include "budget_slam/reducers/MutualInformationOptions.h"
#include "budget_slam/session/SessionStateOwner.h"

namespace budget_slam::reducers {

/// `mi` (Choudhary et al. ICRA 2015, Alg. 2-5; docs/ALGORITHMS.md "mi"). At a cap decision: the
/// candidate with the lowest information gain Backend::informationGain [bits] (Alg. 4), ties to the
/// lowest id; score = that gain. Modes `objective` and `incremental` add the drop events of Alg. 3
/// and Alg. 5 through its DropScheduler capability (see MutualInformationOptions).
class MutualInformationReducer : public Reducer,
                                 public DropScheduler,
                                 public session::SessionStateOwner {
 public:
  explicit MutualInformationReducer(const MutualInformationOptions& options);

  static constexpr const char* kName = "mi";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override;
  void dumpOptions(std::ostream& out) const override { options_.dumpToTextStream(out); }
  /// objective: Alg. 3 once, on the final call (after the last step, before the outputs; the
  /// paper's "active minimization" of its Table II). incremental: Alg. 3 after every `psi` steps
  /// counted from the previous minimization (Alg. 5). cap: nothing.
  ScheduledDrops scheduled(const ScheduleContext& ctx) override;
  /// In objective and incremental modes the objective rho decides how many stay (Alg. 3); a cap,
  /// when one is given, still holds after every step.
  bool decidesMapSize() const override {
    return options_.mode != MutualInformationOptions::Mode::Cap;
  }
  /// Alg. 5: "dropped landmarks are not re-admitted" in incremental mode.
  bool readmitsEvicted() const override {
    return options_.mode != MutualInformationOptions::Mode::Incremental;
  }

  const MutualInformationOptions& options() const { return options_; }
  static ReducerRegistry::Entry entry();
  /// Section `reducer.mi`: the steps since the last minimization (Alg. 5's schedule).
  void saveSession(session::SessionState& state) const override;
  void restoreSession(const session::SessionState& state) override;

 private:
  MutualInformationOptions options_;
  std::size_t steps_since_minimization_ = 0;
  bool look_ahead_checked_ = false;  ///< objective/incremental: Alg. 3 can run on this backend
};

}  // namespace budget_slam::reducers
