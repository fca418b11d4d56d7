#pragma once
#include <Eigen/Core>
#include <list>
#include <optional>
#include <unordered_map>
#include <vector>

#include "budget_slam/core/OptionTable.h"
#include "budget_slam/core/PlaceGrid.h"
#include "budget_slam/core/ReducerRegistry.h"
#include "budget_slam/reducers/HindsightSelection.h"
#include "budget_slam/reducers/PlaceSlots.h"
#include "budget_slam/session/SessionStateOwner.h"

namespace budget_slam::reducers {

/// [LocalizationInformationReducer] (docs/ALGORITHMS.md "localization-information").
struct LocalizationInformationOptions : public TabledOptions<LocalizationInformationOptions> {
  static constexpr const char* kSection = "LocalizationInformationReducer";

  /// What the kept map maximizes over the visited places.
  enum class Objective {
    SumLogDet,  ///< sum over places of log det (monotone submodular)
    MinLogDet   ///< the least log det over places (then the sum, to decide its ties)
  };
  Objective objective = Objective::SumLogDet;
  /// The prior of every place's pose information, 1 sigma in x and y [m]; 0 = the sensor's
  /// maximum range as the rawlog states it (10 m when it does not). > 0 or 0.
  double prior_std_xy = 0;
  double prior_std_yaw_deg = 180;  ///< the prior's 1 sigma in yaw [deg], > 0
  /// Places as `place-coverage` has them: a cell side [m] (0 = a quarter of the sensor's range)
  /// and heading sectors (0 = from the field of view).
  double place_size = 0;
  std::size_t heading_sectors = 0;
  std::size_t max_places = 100000;  ///< places remembered at most, the oldest visit forgotten first
  /// Landmarks not in the map (dropped, refused, or waiting for a retry) whose readings stay on
  /// record, the one that left longest ago forgotten first; 0 = forgotten when they leave
  /// [landmarks]. A landmark that comes back is valued by every place it was read from.
  std::size_t remember_dropped = 1024;
  /// Under [LandmarkBudget] admission = compete: a newcomer that is the second landmark of the
  /// map read from one of its places (a place where exactly one other map landmark is read) goes
  /// only when every candidate is such a newcomer; among those, and among the others, the
  /// objective decides as before. false = the objective alone decides (the paper's rule).
  bool second_landmark_admission = false;

  static const OptionTable<LocalizationInformationOptions>& table();
};

/// `localization-information`: keeps the map that tells the robot most about its pose at every
/// place it has visited.
///
/// For each place p (grid cell and heading sector, as place-coverage), and each landmark l of the
/// map read from p, the Fisher information of that reading about the robot pose (x, y, yaw),
/// I_l(p) = H^T R^-1 H (H = d(range, bearing)/d(pose) at the robot's estimated pose when it read
/// it, R the sensor noise of [RangeBearingKFSLAM]; the mean over its readings from p). The map K
/// gives the place Lambda_p(K) = Lambda_0 + sum over l in K read from p of I_l(p), with a small
/// prior Lambda_0. The objective is F(K) = sum_p log det Lambda_p(K) [nats], monotone submodular
/// (Carlone & Karaman's anticipation with log det; Zhao & Vela's Max-logDet). A drop is the
/// greedy step of removal: the candidate with the least loss F(K) - F(K \ {l}) = sum over its
/// places of log det Lambda_p - log det (Lambda_p - I_l(p)) goes, ties to the lowest id. With
/// objective = min_log_det, the candidate that least lowers min_p log det Lambda_p goes (its
/// loss max(0, m - min over its places of log det (Lambda_p - I_l(p))), m the least place),
/// ties by the sum's loss, then the lowest id.
///
/// Lazy evaluation: a place's log-determinants are recomputed only when a landmark is read from
/// it again, enters it or leaves the map; every other place keeps its numbers. The reducer decides
/// with what it has seen so far (the places visited up to the drop), and that includes the
/// readings of landmarks it does not keep (refused newcomers, withheld while they wait, and
/// dropped ones): they stay on record, outside every Lambda_p, so that a landmark that enters
/// (again) is valued by all the places the robot read it from, not by the last one alone.
class LocalizationInformationReducer : public Reducer,
                                       public ObservationKeeper,
                                       public session::SessionStateOwner {
 public:
  /// `std_range` [m] and `std_bearing` [rad]: the sensor noise the filter assumes.
  LocalizationInformationReducer(const LocalizationInformationOptions& options, double std_range,
                                 double std_bearing);
  static constexpr const char* kName = "localization-information";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override;
  void dumpOptions(std::ostream& out) const override { options_.dumpToTextStream(out); }
  void observe(const StepObservation& seen) override;
  void forget(LandmarkId id) override;
  static ReducerRegistry::Entry entry();
  /// The sections it reads: [LocalizationInformationReducer] and the sensor noise of
  /// [RangeBearingKFSLAM].
  static std::vector<OptionSection> sections();
  /// The reducer as those sections configure it.
  static std::unique_ptr<LocalizationInformationReducer> fromIni(
      const mrpt::config::CConfigFileBase& ini);
  /// Section `reducer.localization-information`: the grid and prior, the place slots, every
  /// place's readings and cached numbers, the landmarks on record off the map.
  void saveSession(session::SessionState& state) const override;
  void restoreSession(const session::SessionState& state) override;

  /// Lambda_p of the place of `robot` (the prior alone for a place not visited) [1/m^2, 1/rad^2].
  Eigen::Matrix3d placeInformation(const Pose2& robot) const;
  /// F(K) = sum over places of log det Lambda_p [nats].
  double objective() const;
  /// min over places of log det Lambda_p [nats] (+infinity without a place).
  double leastPlace() const;
  /// F(K) - F(K \ {id}) [nats]; 0 for a landmark read from no remembered place.
  double loss(LandmarkId id) const;
  /// max(0, leastPlace() - the least log det of id's places without it) [nats].
  double minLoss(LandmarkId id) const;
  /// The remembered places where `id` is one of exactly two map landmarks read there (0 for a
  /// landmark off the map): the places whose second landmark it is.
  std::size_t secondLandmarkPlaces(LandmarkId id) const;
  std::size_t placeCount() const { return slots_.size(); }
  /// Every remembered place with the landmarks of the map read from it and I_l(p) of each (the
  /// mean over its readings there): what F is made of, for a selection with hindsight
  /// (HindsightSelection.h).
  std::vector<PlaceReadings> placeReadings() const;
  /// The prior Lambda_0 in force (after the first observe(): from the sensor's range).
  const Eigen::Matrix3d& prior() const { return prior_; }

 private:
  struct Entry {
    LandmarkId id = kNoLandmarkId;
    Eigen::Matrix3d info_sum = Eigen::Matrix3d::Zero();  ///< sum of I over its readings here
    double readings = 0;
    double without = 0;  ///< log det (Lambda_p - I_l(p)), valid while the place is clean
    bool active = true;  ///< the landmark is in the map (else only on record)
  };
  struct Place {
    std::vector<Entry> entries;  ///< sorted by id
    Eigen::Matrix3d lambda = Eigen::Matrix3d::Zero();
    double logdet = 0;
    bool dirty = false;  ///< changed since the last refresh (then listed in dirty_)
  };

  void fixGeometry(const StepObservation& seen);
  /// Adds a reading of `id` at place `slot` (active: the landmark is in the map).
  void addReading(std::uint32_t slot, const StepObservation& seen, const Sighting& r, bool active);
  /// Turns every entry of `id` active or not, marking their places dirty.
  void setActive(LandmarkId id, bool active);
  /// `id` is off the map: on record, the least recent forgotten beyond remember_dropped.
  void remember(LandmarkId id);
  void eraseLandmark(LandmarkId id);
  void forgetPlace(std::uint32_t slot);
  void markDirty(std::uint32_t slot);
  /// Recomputes the places changed since the last refresh (lazy evaluation).
  void refresh() const;
  const Entry* entryOf(const Place& p, LandmarkId id) const;
  /// restoreSession's checks of what it read against itself and the state's map: InputError
  /// naming the field of `s` whose value breaks a cross-reference the methods rely on.
  void checkRestored(const session::SessionSection& s,
                     const std::vector<std::int64_t>& landmark_ids,
                     const session::SessionState& state) const;

  LocalizationInformationOptions options_;
  double std_range_, std_bearing_;
  Eigen::Matrix3d prior_ = Eigen::Matrix3d::Identity();
  std::optional<PlaceGrid> grid_;
  PlaceSlots slots_;
  mutable std::vector<Place> places_;  ///< by slot; refresh() updates the cached numbers
  mutable std::vector<std::uint32_t> dirty_;
  std::unordered_map<LandmarkId, std::vector<std::uint32_t>> places_of_;  ///< active or not
  std::list<LandmarkId> dropped_;  ///< ids off the map on record, least recent first
  std::unordered_map<LandmarkId, std::list<LandmarkId>::iterator> dropped_at_;
};

}  // namespace budget_slam::reducers
