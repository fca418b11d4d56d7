#include "budget_slam/core/HeapRelease.h"

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
