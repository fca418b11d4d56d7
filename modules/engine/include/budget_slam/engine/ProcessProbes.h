#pragma once
#include <cstddef>

namespace budget_slam::runs {

/// CPU time of the calling thread [s]: per run even when compare runs several in one process,
/// and unaffected by other processes on a shared machine.
double threadCpuSeconds();
/// Peak resident memory of this process [bytes].
std::size_t peakResidentBytes();
/// Resident memory of this process now [bytes] (/proc/self/statm; 0 where unavailable).
std::size_t residentBytes();
/// CPUs this process may run on (its affinity mask: what taskset, cgroups or a batch scheduler's
/// --cpus-per-task leave it), at least 1; the machine's count where the mask is unknown.
std::size_t availableCpus();

/// Under an address-space limit (RLIMIT_AS, `ulimit -v`), at most two malloc arenas: glibc
/// otherwise reserves 64 MiB of address space for each thread's arena, which a compare's threads
/// would take from the limit without using it. No effect without a limit.
void fitMallocToAddressSpaceLimit();

}  // namespace budget_slam::runs
