#include "CompareRuns.h"

#include <chrono>
#include <thread>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Text.h"

namespace budget_slam::app {
namespace {

/// Runs `r` over `steps`, then its end phase; records how it ended.
void runOne(CompareRun& r, const std::vector<Step>& steps,
            const std::function<void()>& on_end_phase) {
  bool end_phase = false;
  try {
    for (const auto& s : steps) {
      if (Cancellation::requested()) {
        r.status = "interrupted";
        r.error = interruptedLine(r, "");
        break;
      }
      r.driver->process(s);
      ++r.steps_done;
    }
    if (r.status == "ok") {
      end_phase = true;
      if (on_end_phase) on_end_phase();
      r.driver->complete();
    }
  } catch (const Interrupted&) {
    r.status = "interrupted";
    r.error = interruptedLine(r, end_phase ? " in the end phase," : "");
  } catch (const std::exception& e) {
    r.status = "failed";
    r.error = exceptionLine(e);
  }
}

}  // namespace

std::string interruptedLine(const CompareRun& r, const char* where) {
  const auto last = r.driver->lastStep();
  return std::string("interrupted by ") + Cancellation::signalName() + where +
         (last ? " after step " + std::to_string(*last) : std::string(" before the first step"));
}

void runInThreads(std::vector<std::unique_ptr<CompareRun>>& runs, const std::vector<Step>& steps,
                  std::size_t threads, const std::function<void()>& on_end_phase,
                  ProgressReporter& progress) {
  std::atomic<std::size_t> next{0};
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < runs.size();) runOne(*runs[i], steps, on_end_phase);
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < threads; ++t) pool.emplace_back(worker);
  for (;;) {
    std::size_t done = 0, finished = 0;
    for (const auto& r : runs) {
      done += r->steps_done;
      finished += r->steps_done == steps.size() || r->status != "ok";
    }
    const std::size_t total = runs.size() * steps.size();
    progress.update(static_cast<double>(done) / std::max<std::size_t>(1, total), done, total,
                    std::to_string(finished) + "/" + std::to_string(runs.size()) + " runs done");
    if (next >= runs.size() && finished == runs.size()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  for (auto& t : pool) t.join();
  bool all_ok = true;
  for (const auto& r : runs) all_ok &= r->status == "ok";
  progress.finish(all_ok);
}

}  // namespace budget_slam::app
