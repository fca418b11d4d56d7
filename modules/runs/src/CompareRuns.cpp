#include "budget_slam/runs/CompareRuns.h"

#include <chrono>
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
}

}  // namespace

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
                         const std::function<void()>& on_end_phase, ProgressReporter& progress) {
  std::atomic<std::size_t> next{0};
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < runs.size();) runOne(*runs[i], steps, on_end_phase);
  };
  WorkerThreads pool(threads, worker);
  while (pool.started() > 0) {
    std::size_t done = 0, finished = 0;
    for (const auto& r : runs) {
      done += r->steps_done;
      finished += r->steps_done == steps.size() || !r->ok();
    }
    const std::size_t total = runs.size() * steps.size();
    progress.update(static_cast<double>(done) / std::max<std::size_t>(1, total), done, total,
                    std::to_string(finished) + "/" + std::to_string(runs.size()) + " runs done");
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
