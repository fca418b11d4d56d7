#pragma once
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/OptionTable.h"
#include "budget_slam/core/ReducerRegistry.h"
#include "budget_slam/reducers/HindsightSelection.h"
#include "budget_slam/reducers/LocalizationInformationReducer.h"

namespace budget_slam::reducers {

/// [HindsightReducer] (docs/EXPERIMENTS.md "Bounds").
struct HindsightOptions : public TabledOptions<HindsightOptions> {
  static constexpr const char* kSection = "HindsightReducer";
  /// Landmarks kept at the end of the run: a number (>= 1), or a percentage of the map the run
  /// ends with, `P%`, rounded as the experiment scripts round a percentage cap:
  /// max(1, floor(P / 100 * N + 0.5)).
  std::string keep = "20%";
  /// Empty: the places are those of this mapping run (the hindsight bound). Otherwise the
  /// rawlogs whose readings, taken at their ground-truth robot path
  /// (`<rawlog>_ground_truth_robot_path.txt`), make the places: a traversal still to come (the
  /// ceiling, the future known).
  std::vector<std::string> places_rawlogs;
  static const OptionTable<HindsightOptions>& table();
  /// The landmarks `keep` keeps of a final map of `n` landmarks (throws the KeyError of a bad
  /// `keep`).
  static std::size_t keepCount(const std::string& keep, std::size_t n);
};

/// `hindsight`: the best cap-sized map with hindsight, an upper reference for the rules, not a
/// rule. It drops nothing while the run maps (run it with [LandmarkBudget] max_landmarks = none:
/// the map is the unreduced one); after the last step it keeps the `keep` landmarks chosen by
/// greedy insertion on localization-information's objective F(K) = sum over places of log det
/// Lambda_p(K) (HindsightSelection.h: >= 1 - 1/e of the best subset), over the places of the
/// whole mapping run, or over those of `places_rawlogs`, and drops the others. The places, the
/// prior and the sensor noise are those of [LocalizationInformationReducer] and
/// [RangeBearingKFSLAM], so the bound measures what the rule maximizes. Under a cap before the
/// end it decides as `localization-information` does.
class HindsightReducer : public Reducer, public DropScheduler, public ObservationKeeper {
 public:
  /// `record`: records the mapping run; `future`: the places of places_rawlogs already read
  /// (null when it is empty).
  HindsightReducer(HindsightOptions options, std::unique_ptr<LocalizationInformationReducer> record,
                   std::unique_ptr<LocalizationInformationReducer> future);
  static constexpr const char* kName = "hindsight";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override { return record_->choose(ctx); }
  void dumpOptions(std::ostream& out) const override;
  ScheduledDrops scheduled(const ScheduleContext& ctx) override;
  bool decidesMapSize() const override { return true; }
  bool readmitsEvicted() const override { return true; }
  void observe(const StepObservation& seen) override { record_->observe(seen); }
  void forget(LandmarkId id) override { record_->forget(id); }
  static ReducerRegistry::Entry entry();

  /// The selection made at the end of the run (empty before).
  const LogDetSelection& selection() const { return selection_; }
  /// The places the selection is made over as they are now: the mapping run's, or those of
  /// places_rawlogs. Once the selection's drops are made, the mapping run's record holds only the
  /// kept landmarks' readings (the others are off the map), and places no kept landmark is read
  /// from are left out: the selection's own places are selectionPlaces().
  std::vector<PlaceReadings> places() const;
  /// The places the selection was made over, as they were when it was made (empty before): the
  /// ones selection().objective is the value of.
  const std::vector<PlaceReadings>& selectionPlaces() const { return selection_places_; }
  const Eigen::Matrix3d& prior() const { return record_->prior(); }

 private:
  HindsightOptions options_;
  std::unique_ptr<LocalizationInformationReducer> record_, future_;
  LogDetSelection selection_;
  std::vector<PlaceReadings> selection_places_;
};

/// Reads `rawlog` and its ground-truth robot path into `record` (every reading with a sensor ID
/// at the true pose of its step). Throws the KeyError of [HindsightReducer] places_rawlogs
/// naming the file when it cannot be read or has no path for one of its steps.
void recordTraversal(const std::string& rawlog, LocalizationInformationReducer& record,
                     StepIndex& step_counter);

}  // namespace budget_slam::reducers
