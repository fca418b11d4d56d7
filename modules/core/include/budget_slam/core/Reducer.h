#pragma once

#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "budget_slam/core/Backend.h"

namespace budget_slam {

/// What a reducer is asked at one drop: the backend (read-only), every landmark in the map,
/// and which of them may be dropped.
struct DropContext {
  const Backend& backend;
  const std::vector<LandmarkView>& landmarks;  ///< all landmarks in the map
  const std::vector<std::size_t>& candidates;  ///< indices into `landmarks`, never empty
  StepIndex step;                              ///< step after which the drop happens
};

/// The landmark a reducer would drop and the score it gave it (lower = less useful; the unit
/// depends on the reducer: bits for mi, 1/m^2 for info-content, ...).
struct ReducerChoice {
  LandmarkId id = kNoLandmarkId;
  double score = 0;
};

/// One reading of a landmark of the map at a step (the sensor frame).
struct Sighting {
  LandmarkId id = kNoLandmarkId;
  double range = 0;    ///< [m]
  double bearing = 0;  ///< [rad]
};

/// What the robot observed at one step: told to the reducers that keep a record of it
/// (ObservationKeeper) after the backend has processed the step and before any drop
/// decision of that step (BudgetManager::enforce).
struct StepObservation {
  StepIndex step = 0;
  Pose2 robot;                       ///< the robot pose estimate after the step [m, m, rad]
  std::vector<LandmarkId> observed;  ///< landmarks of the map observed at this step, new ones too
  /// The readings behind `observed`: each reading of the step with the landmark it went to
  /// (its sensor ID, else the backend's association, Backend::lastAssociation).
  std::vector<Sighting> sightings;
  /// Readings the map did not take in at this step (landmarks refused and waiting for a retry,
  /// or dropped for good; BudgetManager::admissible), with their sensor IDs: what the robot saw of
  /// landmarks it does not keep.
  std::vector<Sighting> withheld;
  Pose2 sensor_pose;            ///< the sensor's pose on the robot (2D) [m, m, rad]
  double sensor_max_range = 0;  ///< [m]; 0 when the step did not say
  double sensor_fov = 0;        ///< total horizontal field of view [rad]; 0 when unknown
};

/// A rule that picks the landmark to drop (docs/ALGORITHMS.md). Registered by name in a
/// ReducerRegistry; adding one is one file plus one line in reducers/BuiltinReducers.cpp. What
/// only some reducers do are optional capabilities, each asked once when the BudgetManager is
/// built (as session::SessionStateOwner is): DropScheduler (drops on the reducer's own
/// schedule) and ObservationKeeper (its own record of where landmarks were observed from).
class Reducer {
 public:
  virtual ~Reducer() = default;
  /// The reducer's registry name (the `reducer` column of evictions.csv).
  virtual std::string name() const = 0;

  /// Returns one of `ctx.candidates`.
  virtual ReducerChoice choose(const DropContext& ctx) = 0;

  /// Writes the reducer's options, MRPT's dumpToTextStream style.
  virtual void dumpOptions(std::ostream& out) const {}
};

/// What a reducer is told when the BudgetManager offers it a drop event of its own (besides the
/// cap), after every step and once more after the last one.
struct ScheduleContext {
  const Backend& backend;
  StepIndex step;  ///< last step processed
  bool final;      ///< true only for the call after the last step (BudgetManager::finish)
  /// A disposable copy of `backend` for look-ahead (e.g. the whole greedy sequence of Choudhary
  /// et al. Alg. 3 before deciding where to stop): the application's factory, else
  /// Backend::clone(). May be empty, or return null when the backend cannot be copied.
  std::function<std::unique_ptr<Backend>()> scratch;
};

/// Landmarks a reducer drops on its own schedule (Choudhary et al. Alg. 3 and 5), in order.
struct ScheduledDrops {
  std::vector<ReducerChoice> drops;  ///< removed in this order
  std::string reason;                ///< evictions.csv reason, e.g. "objective"
  /// After the drops, PoseHistoryBackend::marginalizePosesWithoutLandmarks(keep_last_poses)
  /// (Alg. 3 l. 15-16), on a backend that keeps past poses.
  bool marginalize_poses = false;
  std::size_t keep_last_poses = 0;
};

/// The optional capability of a reducer that drops landmarks on its own schedule besides the cap
/// (Choudhary et al. Alg. 3 and 5: `mi`). Only the active reducer's schedule runs.
class DropScheduler {
 public:
  virtual ~DropScheduler() = default;

  /// The drops of this step (ctx.final: after the last step), in order; none when off schedule.
  /// The BudgetManager removes them, logs them and asks the shadows at each one.
  virtual ScheduledDrops scheduled(const ScheduleContext& ctx) = 0;

  /// True when the scheduled drops decide how many landmarks stay (Choudhary et al.'s objective
  /// and incremental modes), so that the reducer may run without a cap ([LandmarkBudget]
  /// max_landmarks = none). A cap given still bounds the map after every step.
  virtual bool decidesMapSize() const = 0;

  /// False when dropped landmarks must never come back (Choudhary et al. Alg. 5); the
  /// BudgetManager then reports readmit_evicted = false whatever [LandmarkBudget] says.
  virtual bool readmitsEvicted() const = 0;
};

/// The optional capability of a reducer that keeps its own record of where landmarks were observed
/// from (`place-coverage`, `localization-information`): the BudgetManager tells it every step's
/// observations and every landmark that leaves the map.
class ObservationKeeper {
 public:
  virtual ~ObservationKeeper() = default;
  /// What step `seen.step` observed, after the backend processed it and before any drop decision
  /// of that step (BudgetManager::enforce).
  virtual void observe(const StepObservation& seen) = 0;
  /// Landmark `id` left the map (dropped, refused, or scheduled away).
  virtual void forget(LandmarkId id) = 0;
};

/// `reducer` as a DropScheduler, or nullptr when it drops only when asked at the cap.
inline DropScheduler* dropScheduler(Reducer* reducer) {
  return dynamic_cast<DropScheduler*>(reducer);
}
inline const DropScheduler* dropScheduler(const Reducer* reducer) {
  return dynamic_cast<const DropScheduler*>(reducer);
}

/// `reducer` as an ObservationKeeper, or nullptr when it keeps no such record.
inline ObservationKeeper* observationKeeper(Reducer* reducer) {
  return dynamic_cast<ObservationKeeper*>(reducer);
}

}  // namespace budget_slam
