#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace budget_slam {

/// Up to n threads, each running `work` once (work takes its items from a shared counter), joined
/// by join() or the destructor. A thread that cannot be started (std::system_error: an
/// address-space or process limit, `ulimit -v`/`-u`) ends nothing: the threads already started
/// do the work, and with none started, join() runs `work` on the calling thread. `failure()` says
/// why fewer threads than asked for run (compare reports it in one warning line).
class WorkerThreads {
 public:
  WorkerThreads(std::size_t n, std::function<void()> work);
  ~WorkerThreads();
  WorkerThreads(const WorkerThreads&) = delete;
  WorkerThreads& operator=(const WorkerThreads&) = delete;

  std::size_t started() const { return threads_.size(); }
  std::size_t asked() const { return asked_; }
  /// "" when every thread asked for was started; else "could start only 1 of 4 threads (...)".
  const std::string& failure() const { return failure_; }
  /// Waits for the threads; with none started, runs the work here. Idempotent.
  void join();

 private:
  std::function<void()> work_;
  std::vector<std::thread> threads_;
  std::size_t asked_ = 0;
  std::string failure_;
  bool joined_ = false;
};

}  // namespace budget_slam
