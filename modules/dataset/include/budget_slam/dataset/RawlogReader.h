#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "budget_slam/core/Step.h"

namespace budget_slam::dataset {

/// Streams an MRPT rawlog (actions-observations format, gzip or plain) one Step at a time.
/// Each Step keeps the rawlog's own CActionCollection and CSensoryFrame plus their parsed form.
///
/// Errors are InputError with one line naming the file (and the step when there is one):
///   "rawlog 'x.rawlog': no such file"
///   "rawlog 'x.rawlog': not an MRPT rawlog (...)"
///   "rawlog 'x.rawlog': truncated or corrupt at step 17 (...)"
///   "rawlog 'x.rawlog': step 3: reading 2 has a negative or non-finite range (-1)"
class RawlogReader {
 public:
  explicit RawlogReader(const std::string& path);
  ~RawlogReader();
  RawlogReader(const RawlogReader&) = delete;
  RawlogReader& operator=(const RawlogReader&) = delete;

  /// The next step, or std::nullopt at the end of the file.
  std::optional<Step> next();

  const std::string& path() const { return path_; }
  /// Steps returned so far.
  std::size_t stepsRead() const { return steps_; }
  /// Fraction of the (compressed) file consumed, for progress bars.
  double progress() const;
  /// Steps whose frame held a CObservationBearingRange.
  std::size_t bearingRangeSteps() const { return bearing_range_steps_; }
  /// Class names of every observation met so far (for the "no bearing-range" error).
  const std::set<std::string>& observationClasses() const { return observation_classes_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
  std::size_t steps_ = 0;
  std::size_t bearing_range_steps_ = 0;
  std::set<std::string> observation_classes_;
  std::optional<double> last_t_;
  bool timestamps_usable_ = true;
};

/// Builds a Step from an action-observation pair (the parsed fields from MRPT's objects).
/// `t_fallback` is used when the pair carries no valid timestamp.
Step parseStep(const mrpt::obs::CActionCollection::Ptr& action,
               const mrpt::obs::CSensoryFrame::Ptr& frame, StepIndex index, double t_fallback);

/// Reads a whole rawlog into memory (for `compare`, which parses once and feeds every pipeline).
std::vector<Step> readAllSteps(const std::string& path);

}  // namespace budget_slam::dataset
