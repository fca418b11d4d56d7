#pragma once
// Stopping Python code that a run calls (a plugin's choose() that never returns) when the stop
// request comes (core/Cancellation.h): python/src/PythonReducer.cpp.
#include <pybind11/pybind11.h>

#include <condition_variable>
#include <mutex>
#include <system_error>
#include <thread>

#include "budget_slam/core/AbandonOnStop.h"
#include "budget_slam/core/Cancellation.h"

namespace budget_slam::python {

/// Interrupts the Python code a reducer runs when the stop request comes (Ctrl-C, SIGTERM):
/// Python code that loops never returns to the budget manager's polls, and a stop signal does not
/// reach Python's own handler while a run has the application's handlers installed (and never
/// reaches a worker thread of compare). A thread of the reducer's own looks at the stop request
/// every kStopPoll while a call is in progress and then raises KeyboardInterrupt in the calling
/// thread (PyThreadState_SetAsyncExc, taken at the interpreter's next switch of threads). Code
/// blocked in a C call (time.sleep) is interrupted when it comes back to Python.
/// Lock order: the GIL, then mutex_ (the calling thread holds the GIL in enter() and leave()).
class StopWatch {
 public:
  StopWatch() = default;
  StopWatch(const StopWatch&) = delete;
  StopWatch& operator=(const StopWatch&) = delete;
  /// Joins the thread; call it without the GIL (the thread may be waiting for it).
  ~StopWatch() {
    {
      std::lock_guard<std::mutex> l(mutex_);
      quit_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
  }

  /// A call into Python begins on this thread; the GIL is held.
  void enter() {
    std::lock_guard<std::mutex> l(mutex_);
    caller_ = PyThread_get_thread_ident();
    in_call_ = true;
    fired_ = false;
    if (!thread_.joinable()) {
      try {
        thread_ = std::thread([this] { watch(); });
      } catch (const std::system_error&) {
        // No thread to be had: the call runs unwatched (a loop that never returns then ignores
        // Ctrl-C; the budget manager's own polls still stop the run between drops).
      }
    }
    wake_.notify_one();
  }
  /// The call has ended; the GIL is still held. An interruption raised too late for the call is
  /// withdrawn, so that it never lands in the next Python code the thread runs.
  void leave() {
    std::lock_guard<std::mutex> l(mutex_);
    in_call_ = false;
    if (fired_) PyThreadState_SetAsyncExc(caller_, nullptr);
    fired_ = false;
  }

 private:
  void watch() {
    std::unique_lock<std::mutex> l(mutex_);
    while (!quit_) {
      if (!in_call_) {
        wake_.wait(l);
        continue;
      }
      wake_.wait_for(l, kStopPoll);
      if (quit_ || !in_call_ || fired_ || !Cancellation::requested()) continue;
      l.unlock();
      {
        // The calling thread gives the GIL up at its next switch interval (5 ms) if it runs
        // Python code; if it has left the call meanwhile, nothing is raised.
        pybind11::gil_scoped_acquire gil;
        std::lock_guard<std::mutex> again(mutex_);
        if (in_call_ && !fired_) {
          PyThreadState_SetAsyncExc(caller_, PyExc_KeyboardInterrupt);
          fired_ = true;
        }
      }
      l.lock();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread thread_;
  unsigned long caller_ = 0;
  bool in_call_ = false, fired_ = false, quit_ = false;
};

}  // namespace budget_slam::python
