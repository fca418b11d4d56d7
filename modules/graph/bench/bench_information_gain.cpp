// Fast (one factorization, low-rank determinant) versus naive (two factorizations per landmark,
// Choudhary et al. Alg. 1-2) information gain of every landmark, on prefixes of Victoria Park
// of growing length up to the full graph (6969 poses, 151 landmarks). Each graph is solved to
// its batch optimum first (not timed). Also the whole Victoria Park run (BM_FullSlam).
// Results: docs/PERFORMANCE.md.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "TestGraphs.h"
#include "budget_slam/graph/GraphBackend.h"
#include "budget_slam/graph/InformationGain.h"

using namespace budget_slam;
using namespace budget_slam::graph;

namespace {
/// The optimized graph of the first `n` steps (built once per size).
const GraphBackend* graphOf(std::size_t n) {
  static std::map<std::size_t, std::unique_ptr<GraphBackend>> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second.get();
  RangeBearingNoise noise;
  const std::vector<Step> steps = testgraphs::victoriaParkSteps(n, &noise);
  if (steps.empty()) return nullptr;
  auto b = std::make_unique<GraphBackend>(GraphSlamOptions{}, noise);
  for (const Step& s : steps) b->process(s);
  b->finish();
  return cache.emplace(n, std::move(b)).first->second.get();
}

/// The optimized graph of the prefix the benchmark's argument names, or null after marking the
/// benchmark skipped when the rawlog is missing.
const FactorGraph* graphOrSkip(benchmark::State& state) {
  const GraphBackend* b = graphOf(state.range(0));
  if (!b) state.SkipWithError("rawlogs/victoria_park.rawlog not found");
  return b ? &b->graph() : nullptr;
}

std::vector<LandmarkId> idsOf(const FactorGraph& g) {
  std::vector<LandmarkId> ids;
  for (const auto& [id, l] : g.landmarks()) ids.push_back(id);
  return ids;
}

void setCounters(benchmark::State& state, const FactorGraph& g) {
  state.counters["poses"] = static_cast<double>(g.poses().size());
  state.counters["landmarks"] = static_cast<double>(g.landmarks().size());
}

/// Factorization of H at the estimate plus the gains of all landmarks.
void BM_FastAll(benchmark::State& state) {
  const FactorGraph* graph = graphOrSkip(state);
  if (!graph) return;
  const FactorGraph& g = *graph;
  const std::vector<LandmarkId> ids = idsOf(g);
  for (auto _ : state) {
    SparseCholesky chol;
    factorizeAtEstimate(g, &chol);
    benchmark::DoNotOptimize(informationGain(g, chol, ids));
  }
  setCounters(state, g);
}

/// The gains of all landmarks given the factorization of H at the estimate, which the backend
/// keeps between queries (GraphBackend::factorization(): the landmark covariances of the same
/// step share it): what the mi reducer pays per call in a run. Choudhary et al.'s own setting
/// ("SAM maintains the square root information matrix R", Sec. IV-A).
void BM_FastGivenFactor(benchmark::State& state) {
  const FactorGraph* graph = graphOrSkip(state);
  if (!graph) return;
  const FactorGraph& g = *graph;
  const std::vector<LandmarkId> ids = idsOf(g);
  SparseCholesky chol;
  factorizeAtEstimate(g, &chol);
  for (auto _ : state) benchmark::DoNotOptimize(informationGain(g, chol, ids));
  setCounters(state, g);
}

/// Linearization and factorization of H at the estimate alone (symbolic analysis included).
void BM_FactorizeOnly(benchmark::State& state) {
  const FactorGraph* graph = graphOrSkip(state);
  if (!graph) return;
  const FactorGraph& g = *graph;
  for (auto _ : state) {
    SparseCholesky chol;
    factorizeAtEstimate(g, &chol);
    benchmark::DoNotOptimize(chol.logDet());
  }
  setCounters(state, g);
}

/// Alg. 2 per landmark: relinearize and factorize with and without the landmark's factors.
void BM_NaiveAll(benchmark::State& state) {
  const FactorGraph* graph = graphOrSkip(state);
  if (!graph) return;
  const FactorGraph& g = *graph;
  const std::vector<LandmarkId> ids = idsOf(g);
  for (auto _ : state)
    for (LandmarkId id : ids) benchmark::DoNotOptimize(naiveInformationGain(g, id));
  setCounters(state, g);
}

/// Full graph SLAM over the first n steps as the app runs it: process() and robotPose() (the
/// steps.csv row) every step, then finish() (solve to the batch optimum) and the final outputs.
void BM_FullSlam(benchmark::State& state) {
  RangeBearingNoise noise;
  const std::vector<Step> steps = testgraphs::victoriaParkSteps(state.range(0), &noise);
  if (steps.empty()) {
    state.SkipWithError("rawlogs/victoria_park.rawlog not found");
    return;
  }
  for (auto _ : state) {
    GraphBackend b(GraphSlamOptions{}, noise);
    for (const Step& s : steps) {
      b.process(s);
      benchmark::DoNotOptimize(b.robotPose());
    }
    b.finish();
    benchmark::DoNotOptimize(b.landmarks());
    benchmark::DoNotOptimize(b.trajectory());
    state.counters["updates"] = static_cast<double>(b.updateCount());
    setCounters(state, b.graph());
  }
}

// Steps of the prefix; 6968 steps = the whole file (6969 poses with the start pose).
#define SIZES Arg(500)->Arg(1000)->Arg(2000)->Arg(4000)->Arg(6968)
BENCHMARK(BM_FastAll)->SIZES->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_FastGivenFactor)->SIZES->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_FactorizeOnly)->SIZES->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_NaiveAll)->SIZES->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_FullSlam)->Arg(6968)->Unit(benchmark::kMillisecond)->Iterations(1);
}  // namespace

BENCHMARK_MAIN();
