#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

#include "budget_slam/core/HeapRelease.h"

using namespace budget_slam;

namespace {

/// Resident size of this process [bytes] (/proc/self/statm), 0 when unknown.
std::size_t residentBytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t total = 0, resident = 0;
  if (!(statm >> total >> resident)) return 0;
  return resident * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

constexpr std::size_t kMiB = 1024 * 1024;

/// The allocation pattern of a filter whose dense state changes size at every step, reduced to
/// what defeats free(): a large block larger than every one before (so that no earlier hole fits
/// it), touched, then a longer-lived block allocated after it (too large for a hole: it comes
/// from the top of the heap and so pins the large block's hole), then the previous large block
/// freed. All sizes stay under glibc's default mmap threshold (128 KiB), so everything comes
/// from the heap. Runs `steps` steps, calling `after_step` after each; returns the growth of the
/// resident size over the stream [bytes]. Frees everything.
template <class AfterStep>
std::size_t residentGrowthOfStream(std::size_t steps, AfterStep after_step) {
  std::vector<void*> pinned;
  pinned.reserve(steps);
  void* previous = nullptr;
  const std::size_t before = residentBytes();
  for (std::size_t s = 0; s < steps; ++s) {
    const std::size_t size = 64 * 1024 + s * 64;
    void* large = std::malloc(size);
    std::memset(large, static_cast<int>(s), size);
    pinned.push_back(std::malloc(120 * 1024));
    std::free(previous);
    previous = large;
    after_step();
  }
  const std::size_t after = residentBytes();
  std::free(previous);
  for (void* p : pinned) std::free(p);
  releaseFreeHeapPages();
  return after > before ? after - before : 0;
}

}  // namespace

TEST(HeapRelease, ReleasesEveryNthStepAndNeverWithZero) {
  std::size_t calls = 0;
  HeapRelease every3(3, [&] {
    ++calls;
    return true;
  });
  std::vector<bool> released;
  for (int s = 0; s < 10; ++s) released.push_back(every3.afterStep());
  EXPECT_EQ(released,
            std::vector<bool>({false, false, true, false, false, true, false, false, true, false}));
  EXPECT_EQ(calls, 3u);
  EXPECT_EQ(every3.releases(), 3u);

  HeapRelease never(0, [&] {
    ++calls;
    return true;
  });
  for (int s = 0; s < 100; ++s) EXPECT_FALSE(never.afterStep());
  EXPECT_EQ(calls, 3u);
}

TEST(HeapRelease, ResidentMemoryStaysBoundedUnderAFragmentingStream) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "releaseFreeHeapPages is a no-op without glibc";
#endif
  if (residentBytes() == 0) GTEST_SKIP() << "no /proc/self/statm";
  // 400 large blocks of 64-89 KiB: about 30 MiB freed inside the heap over the stream.
  const std::size_t steps = 400;
  // Without release the holes stay resident (free() trims only the top of the heap)...
  const std::size_t unbounded = residentGrowthOfStream(steps, [] {});
  EXPECT_GT(unbounded, 20 * kMiB) << "the stream no longer fragments this C library's heap";
  // ... with a release every 10 steps at most 10 holes are resident at any time (plus the first
  // page of each pinning block, 1.6 MiB).
  HeapRelease release(10);
  const std::size_t bounded = residentGrowthOfStream(steps, [&] { release.afterStep(); });
  EXPECT_EQ(release.releases(), steps / 10);
  EXPECT_LT(bounded, 8 * kMiB);
}
