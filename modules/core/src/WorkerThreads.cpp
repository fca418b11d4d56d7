#include "budget_slam/core/WorkerThreads.h"

#include <system_error>

#include "budget_slam/core/Text.h"

namespace budget_slam {

WorkerThreads::WorkerThreads(std::size_t n, std::function<void()> work)
    : work_(std::move(work)), asked_(n) {
  threads_.reserve(n);
  for (std::size_t t = 0; t < n; ++t) {
    try {
      threads_.emplace_back(work_);
    } catch (const std::system_error& e) {
      failure_ = "could start only " + std::to_string(threads_.size()) + " of " +
                 std::to_string(n) + " threads (" + exceptionLine(e) + ")";
      break;
    }
  }
}

WorkerThreads::~WorkerThreads() {
  for (auto& t : threads_)
    if (t.joinable()) t.join();
}

void WorkerThreads::join() {
  if (joined_) return;
  joined_ = true;
  if (threads_.empty()) work_();
  for (auto& t : threads_) t.join();
}

}  // namespace budget_slam
