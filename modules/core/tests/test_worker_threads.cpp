// Threads that cannot start end nothing (issue 23, case 7: compare under a 400 MB address-space
// limit ended in `terminate called after throwing ... std::system_error`): the work goes to the
// threads started, or to the calling thread.
#include <gtest/gtest.h>
#include <pthread.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <string>

#include "budget_slam/core/WorkerThreads.h"

using namespace budget_slam;

TEST(WorkerThreads, EveryItemIsDoneOnce) {
  std::atomic<int> next{0}, done{0};
  WorkerThreads pool(3, [&] {
    while (next++ < 100) ++done;
  });
  pool.join();
  EXPECT_EQ(done, 100);
  EXPECT_EQ(pool.started(), 3u);
  EXPECT_EQ(pool.failure(), "");
}

// Under an address-space limit that leaves no room for a thread's stack, no thread starts: the
// caller does the work, and failure() says why. In a child process (the limit is the process's).
TEST(WorkerThreads, WithNoRoomForAThreadTheCallerDoesTheWork) {
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // Stacks of 256 MiB (none of the stacks glibc keeps from threads that ended is that large)
    // and the address space in use now with 1 MiB more: no thread stack fits.
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstacksize(&attr, std::size_t{256} << 20);
    if (pthread_setattr_default_np(&attr) != 0) ::_exit(12);
    std::ifstream statm("/proc/self/statm");
    unsigned long pages = 0;
    statm >> pages;
    const rlim_t limit = pages * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE)) + (rlim_t{1} << 20);
    const rlimit as{limit, limit};
    if (::setrlimit(RLIMIT_AS, &as) != 0) ::_exit(10);
    int next = 0, done = 0;
    WorkerThreads pool(4, [&] {
      while (next++ < 50) ++done;
    });
    pool.join();
    const bool ok = done == 50 && pool.started() == 0 &&
                    pool.failure().rfind("could start only 0 of 4 threads (", 0) == 0;
    ::_exit(ok ? 0 : 11);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0);
}
