// Reading speed of RawlogReader (every object checked before MRPT deserializes it) against
// MRPT's own reading (CFileGZInputStream + CRawlog::readActionObservationPair, no checks):
// every step of a shipped rawlog, parsed as the app reads it.
// Usage: bench_rawlog_reader [--benchmark_filter=...]; the rawlogs are found under
// BUDGET_SLAM_SOURCE_DIR (the source tree, set at build time).
#include <benchmark/benchmark.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>

#include <string>

#include "budget_slam/dataset/RawlogReader.h"

namespace {

const std::string kRawlogs = std::string(BUDGET_SLAM_SOURCE_DIR) + "/rawlogs/";

void readAll(benchmark::State& state, const std::string& name) {
  std::size_t steps = 0;
  for (auto _ : state) {
    budget_slam::dataset::RawlogReader reader(kRawlogs + name);
    steps = 0;
    while (auto s = reader.next()) {
      benchmark::DoNotOptimize(s->t);
      ++steps;
    }
  }
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["steps_per_s"] =
      benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsIterationInvariantRate);
}

/// The reference: MRPT reading the same pairs unchecked, then the same parsing.
void readAllMrpt(benchmark::State& state, const std::string& name) {
  std::size_t steps = 0;
  for (auto _ : state) {
    mrpt::io::CFileGZInputStream in(kRawlogs + name);
    auto arch = mrpt::serialization::archiveFrom(in);
    mrpt::obs::CActionCollection::Ptr acts;
    mrpt::obs::CSensoryFrame::Ptr frame;
    std::size_t pos = 0;
    steps = 0;
    while (mrpt::obs::CRawlog::readActionObservationPair(arch, acts, frame, pos)) {
      const auto s = budget_slam::dataset::parseStep(acts, frame, steps, 0);
      benchmark::DoNotOptimize(s.t);
      ++steps;
    }
  }
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["steps_per_s"] =
      benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_ReadVictoriaPark(benchmark::State& state) { readAll(state, "victoria_park.rawlog"); }
void BM_MrptReadVictoriaPark(benchmark::State& state) {
  readAllMrpt(state, "victoria_park.rawlog");
}
void BM_ReadKfSlamDemo(benchmark::State& state) { readAll(state, "kf-slam_demo.rawlog"); }
void BM_MrptReadKfSlamDemo(benchmark::State& state) { readAllMrpt(state, "kf-slam_demo.rawlog"); }
BENCHMARK(BM_ReadVictoriaPark)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MrptReadVictoriaPark)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadKfSlamDemo)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MrptReadKfSlamDemo)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
