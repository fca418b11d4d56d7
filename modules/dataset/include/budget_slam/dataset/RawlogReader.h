#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "budget_slam/core/Step.h"

namespace budget_slam::dataset {

/// Streams an MRPT rawlog, gzip or plain, one Step at a time, in either of MRPT's two formats:
///  - actions-observations (what kf-slam reads): each step is a CActionCollection and the
///    CSensoryFrame after it, paired as CRawlog::readActionObservationPair pairs them (objects
///    before the first action and between an action and its frame are passed over);
///  - observations only (no actions anywhere): each CSensoryFrame, and each bare observation
///    other than CObservationOdometry, is a step; its action is built from the
///    CObservationOdometry readings (docs/RELIABILITY.md "Observations-format rawlogs").
/// Each Step keeps the MRPT objects plus their parsed form.
///
/// Every object is checked against MRPT's layout before MRPT deserializes it, so a corrupt or
/// hostile file cannot make the reader allocate more than about kMaxObjectBytes a step, nor
/// reach MRPT code that crashes on bad data (docs/RELIABILITY.md "How the rawlog reader defends
/// itself"). Errors are InputError with one line naming the file and the step reached:
///   "rawlog 'x.rawlog': no such file"
///   "rawlog 'x.rawlog': not an MRPT rawlog (...)"
///   "rawlog 'x.rawlog': truncated or corrupt at step 17 (...)"
///   "rawlog 'x.rawlog': step 4 holds a mrpt::obs::CObservationImage, which budget-slam does not
///    read (...)"
///   "rawlog 'x.rawlog': step 3: reading 2 has a negative or non-finite range (-1)"
class RawlogReader {
 public:
  /// Largest object (one action collection, sensory frame or observation) read [bytes].
  static constexpr std::size_t kMaxObjectBytes = std::size_t{16} << 20;

  explicit RawlogReader(const std::string& path);
  /// Reads `bytes` (a whole rawlog in memory, kept alive by the caller); `label` stands for the
  /// file name in messages.
  RawlogReader(const std::string& label, std::string_view bytes);
  ~RawlogReader();
  RawlogReader(const RawlogReader&) = delete;
  RawlogReader& operator=(const RawlogReader&) = delete;

  /// The next step; std::nullopt at the end of the file, or when the stop check asked to stop.
  std::optional<Step> next();

  /// Polled between objects and between reads inside a large one; when it returns true,
  /// next() returns std::nullopt at once and stopped() becomes true.
  void setStopCheck(std::function<bool()> stop);
  bool stopped() const { return stopped_; }

  const std::string& path() const { return path_; }
  /// Steps returned so far.
  std::size_t stepsRead() const { return steps_; }
  /// Fraction of the (compressed) file consumed, for progress bars.
  double progress() const;
  /// Steps whose frame held a CObservationBearingRange.
  std::size_t bearingRangeSteps() const { return bearing_range_steps_; }
  /// Class names of every observation read so far ("CObservationBearingRange"); those only met
  /// in objects passed over (a frame before the first action) carry " (passed over)".
  std::set<std::string> observationClasses() const;
  /// True once the file showed itself to be in the observations-only format.
  bool observationsFormat() const;

 private:
  struct Impl;
  void open();
  std::optional<Step> nextStep();
  Step finishStep(Step step);
  /// Throws the one-line failure of a file that switches form at `entry` (`what` is there).
  [[noreturn]] void switchedForm(std::size_t entry, const std::string& what) const;
  std::string describe(const std::exception& failure) const;

  std::unique_ptr<Impl> impl_;
  std::string path_;
  std::size_t steps_ = 0;
  std::size_t bearing_range_steps_ = 0;
  std::optional<double> last_t_;
  bool stopped_ = false;
  bool ended_ = false;
};

/// Builds a Step from an action-observation pair (the parsed fields from MRPT's objects).
/// `t_fallback` is used when the pair carries no valid timestamp.
Step parseStep(const mrpt::obs::CActionCollection::Ptr& action,
               const mrpt::obs::CSensoryFrame::Ptr& frame, StepIndex index, double t_fallback);

/// Reads a whole rawlog into memory (tests and tools; `compare` reads step by step itself).
std::vector<Step> readAllSteps(const std::string& path);

}  // namespace budget_slam::dataset
