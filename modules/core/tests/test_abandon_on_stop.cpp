#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <stdexcept>
#include <thread>

#include "budget_slam/core/AbandonOnStop.h"

using namespace budget_slam;

namespace {
struct ClearStop {
  ClearStop() { Cancellation::clear(); }
  ~ClearStop() { Cancellation::clear(); }
};
}  // namespace

TEST(AbandonOnStop, GivesTheResultWhenNoStopComes) {
  ClearStop clear;
  const auto r = unlessStopped<int>([] { return 6 * 7; });
  ASSERT_TRUE(r);
  EXPECT_EQ(*r, 42);
}

TEST(AbandonOnStop, RethrowsWhatTheWorkThrows) {
  ClearStop clear;
  EXPECT_THROW(unlessStopped<int>([]() -> int { throw std::invalid_argument("x"); }),
               std::invalid_argument);
}

TEST(AbandonOnStop, AStopRequestEndsTheWaitLongBeforeTheWork) {
  ClearStop clear;
  // The work takes 3 s and cannot be interrupted; the stop comes after 100 ms.
  auto done = std::make_shared<std::atomic<bool>>(false);
  std::thread stopper([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    Cancellation::request(SIGTERM);
  });
  const auto r = unlessStopped<int>([done] {
    std::this_thread::sleep_for(std::chrono::seconds(3));
    *done = true;
    return 1;
  });
  stopper.join();
  EXPECT_FALSE(r);
  EXPECT_FALSE(*done);  // abandoned, not waited for
}

TEST(AbandonOnStop, AStopAlreadyRequestedStartsNothing) {
  ClearStop clear;
  Cancellation::request(SIGINT);
  bool ran = false;
  EXPECT_FALSE(unlessStopped<int>([&ran] {
    ran = true;
    return 1;
  }));
  EXPECT_FALSE(ran);
}
