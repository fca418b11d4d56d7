#include "budget_slam/core/HeapRelease.h"

#include <atomic>
#include <new>
#include <utility>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace budget_slam {

bool releaseFreeHeapPages() {
#if defined(__GLIBC__)
  // Pad 0: besides the top of the heap, every whole free page inside it is given back
  // (madvise(MADV_DONTNEED) since glibc 2.8), in every arena.
  return malloc_trim(0) != 0;
#else
  return false;
#endif
}

namespace {
std::atomic<char*> reserve{nullptr};
}  // namespace

void holdMemoryReserve(std::size_t bytes) {
  char* block = new (std::nothrow) char[bytes];  // none: no reserve, nothing else changes
  delete[] reserve.exchange(block);
}

void releaseMemoryReserve() noexcept { delete[] reserve.exchange(nullptr); }

HeapRelease::HeapRelease(std::size_t every_steps, std::function<bool()> release)
    : every_steps_(every_steps), release_(std::move(release)) {}

bool HeapRelease::afterStep() {
  if (every_steps_ == 0 || ++steps_ < every_steps_) return false;
  steps_ = 0;
  ++releases_;
  release_();
  return true;
}

}  // namespace budget_slam
