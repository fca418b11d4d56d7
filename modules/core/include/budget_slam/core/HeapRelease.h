#pragma once
#include <cstddef>
#include <functional>

namespace budget_slam {

/// Hands the heap's free pages back to the operating system (glibc: malloc_trim(0)); a no-op
/// returning false on other C libraries. Returns true when pages were released.
///
/// Why a run needs it: the EKF's dense state is reallocated at every landmark inserted or dropped
/// (a (3 + 2n)^2 covariance, 330-410 KiB at cap 100), and glibc, once its mmap threshold has
/// risen above that size, serves these blocks from the main heap, between small long-lived
/// allocations. Freed, they leave holes only partly reused, which free() never returns (it trims
/// only the top of the heap): on the lifelong scenario with admission = compete the live heap
/// stays at 10 MiB while the heap's resident size keeps growing (docs/RESULTS.md).
bool releaseFreeHeapPages();

/// Sets `bytes` of address space aside (allocated, never touched: no resident memory) until
/// releaseMemoryReserve(). Why: under an address-space limit (ulimit -v) the allocation that
/// fails is followed by the work of ending well (the one line, summary.json), which allocates
/// too; the reserve is what that work runs in. Called once by the executables' main().
void holdMemoryReserve(std::size_t bytes);
/// Frees the reserve (once; later calls do nothing). failureLine() calls it for a
/// std::bad_alloc. Safe from any thread.
void releaseMemoryReserve() noexcept;

/// Releases the heap's free pages (releaseFreeHeapPages) once every `every_steps` steps, so
/// that the resident memory of a run is its live memory plus the holes reused within that many
/// steps and the partly used pages around free chunks, however long the run. The heap's address
/// space itself can still grow by fragmentation; only its resident part is bounded this way.
class HeapRelease {
 public:
  /// `every_steps` = 0 never releases. `release` is the action (tests count its calls).
  explicit HeapRelease(std::size_t every_steps,
                       std::function<bool()> release = releaseFreeHeapPages);

  /// Called once after each step; releases at the every_steps-th, 2 every_steps-th, ... call.
  /// Returns true when it released at this call.
  bool afterStep();

  std::size_t releases() const { return releases_; }

 private:
  std::size_t every_steps_, steps_ = 0, releases_ = 0;
  std::function<bool()> release_;
};

}  // namespace budget_slam
