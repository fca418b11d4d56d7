#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/Reducer.h"
#include "budget_slam/reducers/BudgetOptions.h"
#include "budget_slam/reducers/MovedLandmarks.h"
#include "budget_slam/reducers/NegativeEvidence.h"
#include "budget_slam/reducers/RefusalMemory.h"
#include "budget_slam/session/SessionStateOwner.h"

namespace budget_slam::reducers {

/// One landmark dropped (a row of evictions.csv).
struct Eviction {
  StepIndex step = 0;
  LandmarkId id = kNoLandmarkId;
  std::string reducer;
  double score = 0;
  std::size_t n_before = 0, n_after = 0;
  /// over_cap: an unprotected landmark went; over_cap_all_protected: every landmark was protected
  /// (see BudgetOptions::protect) so the lowest-scored protected one went; moved: its readings
  /// put it elsewhere, pass after pass (MovedLandmarks; its readings start a new landmark, the
  /// score is the evidence's mean normalized innovation squared); refused: a newcomer
  /// lost its admission (admission = compete) and left the map in the step it entered;
  /// otherwise the reason of a drop event the reducer scheduled itself (ScheduledDrops::reason:
  /// objective, incremental).
  std::string reason;
  /// Where the landmark was when dropped [m] (for map pictures).
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  /// What each shadow reducer would have dropped at this decision, in the order of
  /// [LandmarkBudget] shadow_reducers; a shadow that failed here has id kNoLandmarkId and a NaN
  /// score, and its error is in `shadow_errors`.
  std::vector<std::pair<std::string, ReducerChoice>> shadow;
  /// The shadows that failed at this decision and why (one line each). The active reducer's drop
  /// stands: shadows are only logged.
  std::vector<std::pair<std::string, std::string>> shadow_errors;
};

/// How one shadow reducer failed over a run (summary.json "shadow_failures").
struct ShadowFailures {
  std::string shadow;
  std::size_t failures = 0;  ///< drop decisions at which it failed
  StepIndex first_step = 0, last_step = 0;
  std::string first_error;  ///< the error at first_step
};

/// How often two reducers picked the same landmark over all drop decisions.
struct Agreement {
  std::string a, b;
  std::size_t agree = 0, total = 0;
  double rate() const { return total ? static_cast<double>(agree) / total : 0.0; }
};

/// Throws the ConfigError of a cap that cannot go with the active reducer: no cap
/// (max_landmarks = none) with a reducer that drops landmarks only to keep the map under a cap.
/// `active` null is reducer `none`.
void checkCap(const BudgetOptions& options, const Reducer* active);

/// Keeps the map within [LandmarkBudget] max_landmarks after every step (docs/ALGORITHMS.md
/// "Common to every reducer"). Its memory (ids dropped for good, refusals, poses marginalized)
/// and that of every reducer that keeps one (session::SessionStateOwner) go into a session state
/// and come back on `run --resume`.
class BudgetManager : public session::SessionStateOwner {
 public:
  /// `active` may be null: reducer `none`, the unreduced reference run (nothing is dropped).
  /// Throws ConfigError when the cap and the reducer cannot go together (checkCap).
  BudgetManager(const BudgetOptions& options, std::unique_ptr<Reducer> active,
                std::vector<std::unique_ptr<Reducer>> shadows = {});

  /// Called after backend.process(step): first the drop event the active reducer schedules
  /// itself, if any (DropScheduler::scheduled; e.g. mi incremental every psi steps), then the cap,
  /// in every mode: while the map holds more than max_landmarks, asks the active reducer for a
  /// victim among the candidates and removes it. Returns the drops made, in order.
  std::vector<Eviction> enforce(Backend& backend, StepIndex step);
  /// The same, told the step itself (its sensor's range and field of view reach the reducers
  /// that keep a record of where landmarks were observed from; ObservationKeeper::observe).
  std::vector<Eviction> enforce(Backend& backend, const Step& step);
  /// The same, told also the step as read (`raw`, before admissible()): the readings the map did
  /// not take in reach the reducers that keep a record as StepObservation::withheld.
  std::vector<Eviction> enforce(Backend& backend, const Step& processed, const Step& raw);

  /// `raw` without the readings the map must not take in now: the landmarks dropped for good
  /// (readmit_evicted = false) and the refused newcomers still waiting for a retry
  /// (admission = compete). Returns `raw` itself (shared) when none of its readings is affected.
  Step admissible(const Step& raw) const;
  /// admissible(raw), then, with [LandmarkBudget] moved_landmarks = split, the readings of the
  /// landmarks under suspicion of having moved left out too (MovedLandmarks::screen), and every
  /// landmark recognised as moved removed from `backend` now, before the step is fused, so that
  /// the step's reading of it starts a new landmark. Those removals (reason `moved`) lead the
  /// drops the next enforce() returns.
  Step admit(Backend& backend, const Step& raw);
  /// The readings of the reading noise the moved-landmark test uses, 1 sigma [m], [rad] (the
  /// backends' [RangeBearingKFSLAM] std_sensor_range and std_sensor_yaw_deg).
  void setReadingNoise(double std_range, double std_bearing);
  /// The moved-landmark record (suspects and their evidence; a session saves it), null when
  /// [LandmarkBudget] moved_landmarks = off.
  const MovedLandmarks* movedLandmarks() const { return moved_.get(); }

  /// Called once after the last step, before Backend::finish() and the outputs: the active
  /// reducer's final scheduled event (mi objective mode runs Alg. 3 here). Returns its drops.
  std::vector<Eviction> finish(Backend& backend, StepIndex last_step);

  /// Gives reducers a disposable copy of the backend for look-ahead (ScheduleContext::scratch).
  /// Without one, ScheduleContext::scratch is Backend::clone().
  using ScratchFactory = std::function<std::unique_ptr<Backend>(const Backend&)>;
  void setScratchFactory(ScratchFactory f) { scratch_factory_ = std::move(f); }

  /// Poses marginalized by scheduled events so far
  /// (PoseHistoryBackend::marginalizePosesWithoutLandmarks).
  std::size_t posesMarginalized() const { return poses_marginalized_; }

  /// Ids dropped so far, kept only when readmit_evicted = false (the readings to filter out); with
  /// readmission on it stays empty so that memory does not grow with the drops.
  const std::set<LandmarkId>& evicted() const { return evicted_; }

  /// Newcomers refused so far and remembered now (admission = compete).
  const RefusalMemory& refusals() const { return refusals_; }

  /// Section `budget`, then the section of every reducer (active, shadows) that keeps memory.
  void saveSession(session::SessionState& state) const override;
  /// The same back. Agreement counts and shadow failures are per session (summary.json).
  void restoreSession(const session::SessionState& state) override;
  /// The negative-evidence record of every kept landmark (its misses and last confirmation; a
  /// session saves it), null when [LandmarkBudget] negative_evidence = off or no reducer is active.
  const NegativeEvidence* negativeEvidence() const { return negative_.get(); }
  NegativeEvidence* negativeEvidence() { return negative_.get(); }

  /// Agreement of every pair among the active and shadow reducers.
  std::vector<Agreement> agreements() const;

  /// Called once before each drop event (several drops after one step), e.g. to dump states.
  void setBeforeDropEvent(std::function<void(const Backend&, StepIndex)> hook) {
    before_drop_event_ = std::move(hook);
  }

  /// The options in force: as given, except readmit_evicted = false when the active reducer
  /// never re-admits (DropScheduler::readmitsEvicted, mi incremental mode).
  const BudgetOptions& options() const { return options_; }
  bool reduces() const { return active_ != nullptr; }
  /// True when max_landmarks bounds the map: a reducer is active and a cap is given.
  bool capped() const { return active_ && options_.max_landmarks.has_value(); }
  /// Shadow reducers that failed at one or more drop decisions, in shadow order.
  std::vector<ShadowFailures> shadowFailures() const;
  const Reducer* activeReducer() const { return active_.get(); }

 private:
  const BudgetOptions options_;
  std::unique_ptr<Reducer> active_;
  std::vector<std::unique_ptr<Reducer>> shadows_;
  std::set<LandmarkId> evicted_;
  std::vector<Agreement> agreements_;  ///< pairs (0,1), (0,2), ..., (1,2), ...
  std::function<void(const Backend&, StepIndex)> before_drop_event_;
  ScratchFactory scratch_factory_;
  std::size_t poses_marginalized_ = 0;
  RefusalMemory refusals_;
  DropScheduler* scheduler_ = nullptr;         ///< the active reducer's own schedule, if it has one
  std::vector<ObservationKeeper*> observers_;  ///< active and shadow reducers keeping a record
  std::vector<ShadowFailures> shadow_failures_;  ///< one a shadow, in shadow order
  std::unique_ptr<NegativeEvidence> negative_;   ///< null when negative_evidence = off
  std::unique_ptr<MovedLandmarks> moved_;        ///< null when moved_landmarks = off
  std::vector<Eviction> moved_drops_;   ///< splits made by admit(), returned by the next enforce()
  std::set<LandmarkId> held_;           ///< landmarks whose readings admit() held at this step
  std::optional<StepIndex> last_step_;  ///< the last step enforce() saw (the backend's pose)

  /// Updates the negative evidence with the step (a step with readings), then, in mode always,
  /// drops every distrusted landmark (reason negative_evidence).
  std::vector<Eviction> weighNegativeEvidence(Backend& backend, StepIndex step,
                                              const Step* processed);
  /// Removes `id` (of `landmarks`) for the negative evidence against it, without asking any
  /// reducer or shadow.
  Eviction dropDistrusted(Backend& backend, const std::vector<LandmarkView>& landmarks,
                          LandmarkId id, StepIndex step);

  std::vector<Eviction> enforceAt(Backend& backend, StepIndex step, const Step* processed,
                                  const Step* raw = nullptr);
  /// Tells the observing reducers what step `step` observed (ObservationKeeper::observe).
  void tellObservations(const Backend& backend, StepIndex step, const Step* processed,
                        const Step* raw);
  std::vector<Eviction> runScheduled(Backend& backend, StepIndex step, bool final);
  /// Drops `victim` (a landmark of ctx.landmarks) from the backend: asks the shadows, removes
  /// it, remembers it when readmission is off, and returns its log record.
  Eviction dropLandmark(Backend& backend, const DropContext& ctx, const ReducerChoice& victim,
                        std::string reason);
  /// Asks the shadows about the current map (filling e.shadow and e.shadow_errors) and counts
  /// their agreement with the active choice. A shadow that throws is logged, never fatal.
  void askShadows(const DropContext& ctx, const ReducerChoice& active, Eviction& e);
};

/// Indices of the landmarks that may be dropped after `step`, under the options' protection rule
/// (docs/ALGORITHMS.md "Candidates"): with
/// `protect = recently_seen` a landmark seen in the last P steps is protected, with
/// `newly_added` one that entered the map in the last P steps; with `admission = compete` the
/// landmarks that entered at `step` itself are never protected (they compete for their place).
/// All landmarks when every one is protected.
std::vector<std::size_t> dropCandidates(const std::vector<LandmarkView>& landmarks, StepIndex step,
                                        const BudgetOptions& options, bool* all_protected);

}  // namespace budget_slam::reducers
