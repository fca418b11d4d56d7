#include "budget_slam/engine/CompareRuns.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <unordered_set>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/core/WorkerThreads.h"

namespace budget_slam::runs {
namespace {

/// Runs `r` over `steps`, then its end phase; records how it ended.
void runOne(CompareRun& r, const std::vector<Step>& steps,
            const std::function<void()>& on_end_phase) {
  bool end_phase = false;
  try {
    for (const auto& s : steps) {
      if (Cancellation::requested()) {
        r.status = RunStatus::Interrupted, r.kind = ErrorKind::Stopped;
        r.error = interruptedLine(r, "");
        break;
      }
      r.driver->process(s);
      ++r.steps_done;
    }
    if (r.ok()) {
      end_phase = true;
      if (on_end_phase) on_end_phase();
      r.driver->complete();
    }
  } catch (const Interrupted&) {
    r.status = RunStatus::Interrupted, r.kind = ErrorKind::Stopped;
    r.error = interruptedLine(r, end_phase ? " in the end phase," : "");
  } catch (const std::exception& e) {
    r.status = RunStatus::Failed, r.kind = errorKindOf(e);
    r.error = failureLine(e);
  }
  r.ended = true;
}

/// [s] since an arbitrary start, monotonic.
double nowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// A run's pace over its recent steps: samples (time, steps done) of the last kWindowS seconds.
class PaceWindow {
 public:
  static constexpr double kWindowS = 20;  ///< [s] long enough to smooth, short enough to follow
  void add(double t, std::size_t done) {
    if (samples_.empty() || done != samples_.back().second) samples_.push_back({t, done});
    while (samples_.size() > 2 && t - samples_[1].first > kWindowS)
      samples_.erase(samples_.begin());
    last_t_ = t;
  }
  /// [s] a step over the window (counting the time since the last step done); NaN before two
  /// samples.
  double stepSeconds() const {
    if (samples_.size() < 2) return std::numeric_limits<double>::quiet_NaN();
    const auto& [t0, d0] = samples_.front();
    const std::size_t steps = samples_.back().second - d0;
    return steps ? (last_t_ - t0) / static_cast<double>(steps)
                 : std::numeric_limits<double>::quiet_NaN();
  }

 private:
  std::vector<std::pair<double, std::size_t>> samples_;
  double last_t_ = 0;
};

}  // namespace

double compareEta(const std::vector<RunPace>& runs, std::size_t threads) {
  std::vector<double> known;
  for (const auto& r : runs)
    if (r.steps_left && std::isfinite(r.step_s)) known.push_back(r.step_s);
  bool any_left = false;
  for (const auto& r : runs) any_left |= r.steps_left > 0;
  if (!any_left) return 0;
  if (known.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(known.begin(), known.begin() + known.size() / 2, known.end());
  const double median = known[known.size() / 2];
  double longest = 0, work = 0;
  for (const auto& r : runs) {
    const double left =
        static_cast<double>(r.steps_left) * (std::isfinite(r.step_s) ? r.step_s : median);
    longest = std::max(longest, left);
    work += left;
  }
  return std::max(longest, work / static_cast<double>(std::max<std::size_t>(1, threads)));
}

std::string largeReferenceNote(const std::string& backend, std::size_t landmarks) {
  if (backend != "ekf" || landmarks < kLargeEkfMap) return "";
  return "the unreduced reference will hold up to " + std::to_string(landmarks) +
         " landmarks (the rawlog's distinct ids), and an EKF step costs the square of the map's "
         "size: the reference will take the longest by far; --backend graph serves large maps "
         "(docs/GRAPH.md)";
}

std::size_t distinctLandmarkIds(const std::vector<Step>& steps) {
  std::unordered_set<LandmarkId> ids;
  for (const auto& s : steps)
    if (s.scan)
      for (const auto& r : s.scan->readings)
        if (r.id != kNoLandmarkId) ids.insert(r.id);
  return ids.size();
}

bool withoutLandmarkIds(const std::vector<Step>& steps) {
  for (const auto& s : steps)
    if (s.scan)
      for (const auto& r : s.scan->readings)
        if (r.id != kNoLandmarkId) return false;
  return true;
}

FinalRelocCoverage relocCoverageThroughReference(const RunDriver& reference, const RunDriver& run,
                                                 double gate_chi2) {
  const auto pairs = metrics::matchLandmarks(run.backend().landmarks(),
                                             reference.backend().landmarks(), gate_chi2);
  std::unordered_set<LandmarkId> matched_reference;
  for (const auto& [mine, theirs] : pairs) matched_reference.insert(theirs);
  FinalRelocCoverage c;
  c.steps = reference.relocalization().steps();
  c.coverage = metrics::coverageOf(
      c.steps, [&](LandmarkId id) { return matched_reference.count(id) > 0; },
      reference.relocalization().minLandmarks(), reference.relocalization().sampled());
  c.source = "reference_association";
  c.details = {{"landmarks_matched_to_reference", pairs.size()}, {"match_gate_chi2", gate_chi2}};
  return c;
}

std::string interruptedLine(const CompareRun& r, const char* where) {
  const auto last = r.driver->lastStep();
  return std::string("interrupted by ") + Cancellation::signalName() + where +
         (last ? " after step " + std::to_string(*last) : std::string(" before the first step"));
}

std::string runInThreads(std::vector<std::unique_ptr<CompareRun>>& runs,
                         const std::vector<Step>& steps, std::size_t threads,
                         const std::function<void()>& on_end_phase, ProgressReporter& progress,
                         const std::string& detail_after) {
  std::atomic<std::size_t> next{0};
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < runs.size();) runOne(*runs[i], steps, on_end_phase);
  };
  WorkerThreads pool(threads, worker);
  // The ETA from each run's own recent pace: the runs differ by far (the unreduced reference's
  // map is the largest), and a run's steps grow dearer as its map grows, so the share of all
  // steps done, which the reduced runs fill fast, would say "a few seconds" for minutes (issue 35).
  std::vector<PaceWindow> pace(runs.size());
  while (pool.started() > 0) {
    std::size_t done = 0, finished = 0;
    std::vector<RunPace> paces(runs.size());
    const double now = nowSeconds();
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const auto& r = *runs[i];
      const std::size_t d = r.steps_done;
      done += d;
      finished += r.ended;
      if (d > 0 && !r.ended) pace[i].add(now, d);
      if (!r.ended) paces[i] = {steps.size() - std::min(d, steps.size()), pace[i].stepSeconds()};
    }
    const std::size_t total = runs.size() * steps.size();
    progress.update(static_cast<double>(done) / std::max<std::size_t>(1, total), done, total,
                    std::to_string(finished) + "/" + std::to_string(runs.size()) + " runs done" +
                        (detail_after.empty() ? "" : "; " + detail_after),
                    compareEta(paces, threads));
    if (next >= runs.size() && finished == runs.size()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  pool.join();  // no thread started: the runs go on here, one after the other
  bool all_ok = true;
  for (const auto& r : runs) all_ok &= r->ok();
  progress.finish(all_ok);
  return pool.failure();
}

}  // namespace budget_slam::runs
