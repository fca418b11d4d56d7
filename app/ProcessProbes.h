#pragma once
#include <cstddef>

namespace budget_slam::app {

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

}  // namespace budget_slam::app
