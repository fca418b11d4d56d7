#pragma once
#include <mrpt/config/CConfigFileBase.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "budget_slam/core/Backend.h"
#include "budget_slam/core/BackendRegistry.h"
#include "budget_slam/core/HeapRelease.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/engine/FinalRelocCoverage.h"
#include "budget_slam/engine/RunObservers.h"
#include "budget_slam/engine/RunOutcome.h"
#include "budget_slam/engine/ShadowReducers.h"
#include "budget_slam/engine/StepObserver.h"
#include "budget_slam/metrics/GroundTruthErrors.h"
#include "budget_slam/metrics/MapAlignment.h"
#include "budget_slam/metrics/RelocalizationCoverage.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/CoverageOptions.h"
#include "budget_slam/report/OutputFolder.h"
#include "budget_slam/report/Pictures.h"
#include "budget_slam/report/ReportOptions.h"
#include "budget_slam/report/RunOutputs.h"
#include "budget_slam/session/SessionState.h"

namespace budget_slam::runs {

/// What a run driver is given besides the ini: the backend's name, the budget, and the values of
/// [MappingApplication] it acts on (read by the caller: runs/MappingOptions.h).
struct DriverSpec {
  std::string backend = "ekf";     ///< a name of the backend registry
  reducers::BudgetOptions budget;  ///< [LandmarkBudget], with the flags applied
  /// false keeps no per-step records in memory (no online poses, no landmark counts, the EKF
  /// keeps only its latest pose): memory stays flat over arbitrarily long runs, everything per
  /// step is still in steps.csv, and NEES is accumulated online.
  bool keep_history = true;
  bool save_3d_scene = true;          ///< [MappingApplication] save_3d_scene
  std::size_t scene_every_steps = 0;  ///< kf-slam's SAVE_3D_SCENES / SAVE_LOG_FREQUENCY
  std::string rawlog_name;            ///< the rawlog's file name, in map.png's title
};

/// The run driver: one SLAM run under a budget, fed one step at a time (docs/ARCHITECTURE.md
/// "Data flow"). Its step loop is the backend's update and the budget's drops; what the run
/// measures and records besides (timings, relocalization coverage, the map's counts and online
/// poses, the NEES, the eviction log, the periodic scenes) is a list of observers
/// (RunObservers.h) it calls in order, each filling its own block of the outcome. Every file goes
/// through report::RunOutputs (steps.csv and evictions.csv as the steps happen, the rest in
/// finish(); docs/OUTPUTS.md).
class RunDriver {
 public:
  /// The backend `spec.backend` of `backends`, the budget's reducers, and the observers, built
  /// from `ini`.
  RunDriver(const mrpt::config::CConfigFileBase& ini, const BackendRegistry& backends,
            const DriverSpec& spec, report::OutputFolder folder,
            std::shared_ptr<const dataset::GroundTruth> truth);
  // The observers and the budget's state dumps hold on to the driver's members.
  RunDriver(const RunDriver&) = delete;
  RunDriver& operator=(const RunDriver&) = delete;

  /// Runs one step: backend update (evicted landmarks filtered out when readmission is off), then
  /// the budget, then its steps.csv row. Throws Error on bad data, on a diverged estimate and when
  /// the row cannot be written, Interrupted on a stop request inside the step; the step then does
  /// not count (lastStep() is the step before) and the outputs written so far stay.
  void process(const Step& step);

  /// Continues from a saved session (`run --resume`): the backend's estimate, the budget's and
  /// every reducer's memory. Every section of the state must be taken (SessionState::
  /// checkAllRead). Throws InputError naming the file, section and field, or ConfigError when the
  /// backend keeps no session state.
  void restoreSession(const session::SessionState& state);
  /// Writes session_state.txt into the output folder (atomically) with `header` and the state
  /// now: call after the last step, before complete() (whose end-of-run drops and final solve a
  /// one-shot run would not have made at this step). Throws Error when it cannot be written.
  void writeSessionState(const session::SessionHeader& header);

  /// Runs the reducer's and the backend's end-of-run work (active minimization, the graph's final
  /// solve) once; finish(RunStatus::Ok) calls it too. Throws Interrupted on a stop request.
  void complete();

  /// Writes every output (steps.csv and evictions.csv flushed to disk, trajectory.tum,
  /// landmarks.csv, map.png, ground_truth.tum) and then summary.json (runs::writeSummary) from
  /// the outcome: `status`, `kind` and `error`, the driver's blocks, and `given`. Only the steps
  /// that completed and only finite estimates are written or drawn (a diverged estimate leaves its
  /// non-finite poses and landmarks out, counted in summary.json). Each output is attempted even
  /// when another fails; an ok run whose outputs could not all be written becomes failed, with the
  /// first write error (see writeError()). `steps_in_rawlog` maps ground truth rows. Returns the
  /// outcome summary.json was written from. With status ok, throws Interrupted when a stop request
  /// came before the outputs were written.
  RunOutcome finish(RunStatus status, ErrorKind kind, const std::string& error,
                    std::size_t steps_in_rawlog, const RunGiven& given = {});
  /// The first output finish() could not write ("" when all were written).
  const std::string& writeError() const { return write_error_; }
  /// Why finish() could not write summary.json ("" when it did).
  const std::string& summaryError() const { return summary_error_; }
  /// The last step that completed (its steps.csv row is written), none before the first.
  std::optional<StepIndex> lastStep() const {
    return steps_done_ ? std::optional<StepIndex>(last_step_) : std::nullopt;
  }

  const Backend& backend() const { return *backend_; }
  Backend& backend() { return *backend_; }
  const reducers::BudgetManager& budget() const { return *manager_; }
  const report::OutputFolder& folder() const { return outputs_.folder(); }
  std::size_t stepsDone() const { return steps_done_; }
  /// Landmarks dropped after holding a place in the map (evictions.csv rows but the refusals).
  std::size_t evictions() const { return evictions_->evictions(); }
  /// Newcomers refused at admission (evictions.csv rows with reason refused).
  std::size_t refused() const { return evictions_->refused(); }
  /// The online robot pose after each step (for the metrics against the reference; empty
  /// without history).
  const std::vector<metrics::PoseRecord>& onlinePoses() const { return map_counts_->onlinePoses(); }
  /// The landmarks in the map after each step (empty without history).
  const std::vector<std::size_t>& landmarkCounts() const { return map_counts_->landmarkCounts(); }
  /// The wall time of the steps done [s].
  double totalStepSeconds() const { return probes_->totalSeconds(); }

  /// The relocalization tracker's steps against the backend's landmarks now (call after
  /// complete()).
  FinalRelocCoverage finalRelocCoverage() const { return reloc_->finalCoverage(*backend_); }
  /// Replaces the relocalization coverage finish() reports (compare on ID-less rawlogs: through
  /// the reference run).
  void setFinalRelocCoverage(FinalRelocCoverage coverage) {
    reloc_->replaceFinal(std::move(coverage));
  }
  /// Which landmarks each step observed, and the coverage so far.
  const metrics::RelocalizationTracker& relocalization() const { return reloc_->tracker(); }
  /// Set by finish() when the rawlog has ground truth: the ground truth's frame in the map's.
  const std::optional<metrics::MapAlignment>& mapAlignment() const { return alignment_; }

 private:
  /// What map.png and map.3Dscene show (runMapContent); with `coverage`, the path coloured by
  /// the final map's landmarks in view.
  report::MapContent mapContent(const std::vector<TrajectoryPoint>& trajectory,
                                const std::vector<LandmarkView>& landmarks,
                                const FinalRelocCoverage* coverage) const;

  /// Adds an observer at the end of the list.
  template <class O, class... Args>
  O& addObserver(Args&&... args) {
    observers_.push_back(std::make_unique<O>(std::forward<Args>(args)...));
    return static_cast<O&>(*observers_.back());
  }

  /// How map.png and map.3Dscene colour the kept landmarks: the picture's k-means clusters
  /// ([CoverageReducer]'s settings, the run's seed), not a reducer.
  reducers::CoverageOptions picture_clusters_;
  bool save_3d_scene_ = true;  ///< [MappingApplication] save_3d_scene
  std::unique_ptr<Backend> backend_;
  std::unique_ptr<reducers::BudgetManager> manager_;
  std::shared_ptr<const dataset::GroundTruth> truth_;
  report::RunOutputs outputs_;
  std::string rawlog_name_;  ///< the rawlog's file name, in map.png's title
  std::vector<report::FigureFormat> figure_formats_;  ///< [Report] figure_format
  bool figure_title_ = true;                          ///< [Report] figure_title
  /// The observers of the step loop, called in this order (RunObservers.h), and those the
  /// driver's accessors read.
  std::vector<std::unique_ptr<StepObserver>> observers_;
  StepProbes* probes_ = nullptr;
  RelocCoverageTracking* reloc_ = nullptr;
  MapCounts* map_counts_ = nullptr;
  EvictionLog* evictions_ = nullptr;
  /// Gives the heap's free pages back every kReleaseHeapEverySteps steps (core/HeapRelease.h:
  /// the filter's reallocated state leaves holes in the heap that free() keeps resident).
  HeapRelease heap_release_;
  std::optional<metrics::MapAlignment> alignment_;
  bool completed_ = false;
  std::string write_error_, summary_error_;
  StepIndex last_step_ = 0;
  std::size_t steps_done_ = 0;
};

}  // namespace budget_slam::runs
