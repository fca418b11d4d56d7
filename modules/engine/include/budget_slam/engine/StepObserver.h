#pragma once
// The run driver's step loop is the backend's update and the budget's drops; everything it
// measures or records besides is an observer of that loop (RunObservers.h), called in the
// driver's order at a few fixed points of each step and of the end of the run, each filling its
// own block of the outcome (docs/ARCHITECTURE.md "Data flow").
#include <cstddef>
#include <vector>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/Step.h"
#include "budget_slam/engine/RunOutcome.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/report/RunOutputs.h"

namespace budget_slam::runs {

/// One step of the loop, as the observers see it.
struct StepEvent {
  const Step& raw;       ///< the step as read
  const Step& filtered;  ///< what the backend was given (BudgetManager::admissible)
  /// The landmark each of `filtered`'s readings went to (Backend::lastAssociation).
  std::vector<LandmarkId> association;
  /// The budget's drops and refusals of the step (empty until afterDrops).
  std::vector<reducers::Eviction> drops;
  const Backend& backend;  ///< after the update, then after the drops
};

/// An observer of the run driver's step loop. Every hook does nothing unless overridden.
class StepObserver {
 public:
  virtual ~StepObserver() = default;
  /// Before the step's work: the start of the step's timed window.
  virtual void stepStarts() {}
  /// After the backend's update, before the budget (inside the timed window).
  virtual void afterUpdate(const StepEvent&) {}
  /// After the budget's drops: adds the observer's columns to the step's steps.csv row. The first
  /// observer's (the probes') closes the timed window: what the others do here is not timed.
  virtual void afterDrops(const StepEvent&, report::StepRow&) {}
  /// The step's row is written: the step counts. A step whose row could not be written never
  /// gets here.
  virtual void stepDone(const StepEvent&, const report::StepRow&) {}
  /// The budget's end-of-run drops (RunDriver::complete).
  virtual void endOfRunDrops(const std::vector<reducers::Eviction>&) {}
  /// Writes the observer's block of `outcome`, whose run block (and ground-truth block when the
  /// rawlog has ground truth) exists; `steps_in_rawlog` maps ground-truth rows.
  virtual void fill(RunOutcome& /*outcome*/, std::size_t /*steps_in_rawlog*/) const {}
};

}  // namespace budget_slam::runs
