#pragma once
// Work that cannot poll a stop request itself (one dense eigen-decomposition of a few thousand
// rows: seconds, in a library call with no hook), run so that the caller still answers a stop
// request (core/Cancellation.h) within kStopPoll.
#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <system_error>
#include <thread>

#include "budget_slam/core/Cancellation.h"

namespace budget_slam {

/// How often the caller looks at the stop request while the work runs.
inline constexpr std::chrono::milliseconds kStopPoll{20};

/// Runs `work` on a thread of its own and waits for its result, looking at the stop request
/// every kStopPoll. On a stop request it returns none at once and abandons the work: the thread
/// finishes on its own and drops the result. So `work` must own everything it touches (capture
/// by value) and have no effect but its result. An exception `work` throws is rethrown here.
/// When no thread can be started, the work runs on the caller's thread (and is waited for).
template <class R>
std::optional<R> unlessStopped(std::function<R()> work) {
  if (Cancellation::requested()) return std::nullopt;
  auto task = std::make_shared<std::packaged_task<R()>>(std::move(work));
  std::future<R> result = task->get_future();
  try {
    std::thread([task] { (*task)(); }).detach();
  } catch (const std::system_error&) {
    (*task)();  // no thread to be had (an address-space limit): the work, waited for, here
  }
  while (result.wait_for(kStopPoll) != std::future_status::ready)
    if (Cancellation::requested()) return std::nullopt;
  return result.get();
}

}  // namespace budget_slam
