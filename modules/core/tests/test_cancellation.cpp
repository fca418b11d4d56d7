#include <gtest/gtest.h>

#include <csignal>
#include <thread>

#include "budget_slam/core/Cancellation.h"

using namespace budget_slam;

TEST(Cancellation, CheckThrowsInterruptedNamingTheSignal) {
  Cancellation::clear();
  EXPECT_FALSE(Cancellation::requested());
  EXPECT_NO_THROW(Cancellation::check());
  Cancellation::request(SIGTERM);
  EXPECT_TRUE(Cancellation::requested());
  EXPECT_EQ(Cancellation::signal(), SIGTERM);
  try {
    Cancellation::check();
    FAIL();
  } catch (const Interrupted& e) {
    EXPECT_STREQ(e.what(), "interrupted by SIGTERM");
  }
  // A second request does not rename the first: Ctrl-C then SIGTERM is a stop by Ctrl-C.
  Cancellation::request(SIGINT);
  EXPECT_STREQ(Cancellation::signalName(), "SIGTERM");
  Cancellation::clear();
  Cancellation::request(SIGINT);
  Cancellation::request(SIGTERM);
  EXPECT_STREQ(Cancellation::signalName(), "Ctrl-C");
  Cancellation::clear();
  EXPECT_NO_THROW(Cancellation::check());
}

TEST(Cancellation, ARequestFromASignalHandlerReachesOtherThreads) {
  Cancellation::clear();
  const auto previous = std::signal(SIGUSR1, [](int) { Cancellation::request(SIGINT); });
  bool seen = false;
  std::thread worker([&] {
    // A long loop polling the flag, as compare's worker threads do.
    for (long i = 0; i < 2000000000L && !seen; ++i) seen = Cancellation::requested();
  });
  std::raise(SIGUSR1);
  worker.join();
  std::signal(SIGUSR1, previous);
  EXPECT_TRUE(seen);
  EXPECT_THROW(Cancellation::check(), Interrupted);
  Cancellation::clear();
}
