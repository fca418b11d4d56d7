// Reading speed of RawlogReader: every step of a shipped rawlog, parsed as the app reads it.
// Usage: bench_rawlog_reader [--benchmark_filter=...]; the rawlogs are found under
// BUDGET_SLAM_SOURCE_DIR (the source tree, set at build time).
#include <benchmark/benchmark.h>

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

void BM_ReadVictoriaPark(benchmark::State& state) { readAll(state, "victoria_park.rawlog"); }
void BM_ReadKfSlamDemo(benchmark::State& state) { readAll(state, "kf-slam_demo.rawlog"); }
BENCHMARK(BM_ReadVictoriaPark)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadKfSlamDemo)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
