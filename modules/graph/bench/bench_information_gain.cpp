// Fast (one factorization, low-rank determinant) versus naive (two factorizations per landmark,
// Choudhary et al. Alg. 1-2) information gain of every landmark, on prefixes of Victoria Park
// of growing length up to the full graph (6969 poses, 151 landmarks). Each graph is solved to
// its batch optimum first (not timed). Also the whole Victoria Park run (BM_FullSlam).
// Results: docs/PERFORMANCE.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <ctime>

#include <map>
#include <memory>
#include <numeric>

#include "TestGraphs.h"
#include "budget_slam/dataset/Simulator.h"
#include "budget_slam/graph/GraphBackend.h"
#include "budget_slam/graph/InformationGain.h"
#include "budget_slam/graph/Solver.h"

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

/// This thread's CPU time [ms] (the machine is shared: wall time counts the neighbours too).
double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

/// The held factor's partial re-eliminations: how many, and the mean share of L's rows each
/// re-eliminated.
void setPartialCounters(benchmark::State& state, const IncrementalStats& held) {
  state.counters["partial"] = static_cast<double>(held.partial_refactorizations);
  state.counters["partial_rows_pct"] =
      held.partial_of_rows > 0 ? 100.0 * held.partial_rows / held.partial_of_rows : 0.0;
  // Rows of the solution solved again per Gauss-Newton iteration (partial back-substitution).
  state.counters["solved_rows_pct"] =
      held.solve_of_rows > 0 ? 100.0 * held.solved_rows / held.solve_of_rows : 0.0;
}

/// Mean step CPU over the first and the last 10% of the steps, and their ratio.
void setMeanStepCounters(benchmark::State& state, const std::vector<double>& step_ms) {
  const std::size_t tenth = std::max<std::size_t>(1, step_ms.size() / 10);
  const auto mean = [](auto b, auto e) {
    return std::accumulate(b, e, 0.0) / static_cast<double>(std::distance(b, e));
  };
  const double first = mean(step_ms.begin(), step_ms.begin() + tenth);
  const double last = mean(step_ms.end() - tenth, step_ms.end());
  state.counters["step_mean_first10_ms"] = first;
  state.counters["step_mean_last10_ms"] = last;
  state.counters["step_mean_growth"] = last / first;
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
  GraphSlamOptions options;
  options.relinearize_threshold = static_cast<double>(state.range(1)) * 1e-3;
  if (state.range(2) > 0) options.reorder_fill_ratio = static_cast<double>(state.range(2)) / 10.0;
  options.wildfire_threshold = static_cast<double>(state.range(3)) * 1e-6;
  for (auto _ : state) {
    GraphBackend b(options, noise);
    std::vector<double> update_ms;   // CPU time of each step that ran an incremental update
    std::vector<char> refactorized;  // ... and whether it refactorized the whole factor
    std::vector<double> step_ms;     // CPU time of every step
    for (const Step& s : steps) {
      const std::size_t before = b.updateCount(), rebuilds = b.heldFactorStats().rebuilds;
      const double t0 = threadCpuMs();
      b.process(s);
      benchmark::DoNotOptimize(b.robotPose());
      step_ms.push_back(threadCpuMs() - t0);
      if (b.updateCount() != before) {
        update_ms.push_back(threadCpuMs() - t0);
        refactorized.push_back(b.heldFactorStats().rebuilds != rebuilds);
      }
    }
    const std::size_t tail = std::max<std::size_t>(1, refactorized.size() / 10);
    state.counters["last10_refactorized_pct"] =
        100.0 * static_cast<double>(std::count(refactorized.end() - tail, refactorized.end(), 1)) /
        static_cast<double>(tail);
    state.counters["first10_refactorized_pct"] =
        100.0 *
        static_cast<double>(std::count(refactorized.begin(), refactorized.begin() + tail, 1)) /
        static_cast<double>(tail);
    // The batch solution from the same linearization (Gauss-Newton on H factorized afresh at
    // every iteration, from the estimate finish() starts from; not timed) ...
    FactorGraph batch = b.graph();
    SparseCholesky batch_factor;
    optimize(batch, b.options().solver, &batch_factor);
    const double t0 = threadCpuMs();
    b.finish();
    state.counters["finish_ms"] = threadCpuMs() - t0;
    // ... and the largest difference of finish()'s estimate from it [m, rad].
    Eigen::VectorXd diff = b.graph().values() - batch.values();
    for (const auto& [step, p] : batch.poses()) diff[p.col + 2] = wrapAngle(diff[p.col + 2]);
    state.counters["final_vs_batch"] = diff.lpNorm<Eigen::Infinity>();
    benchmark::DoNotOptimize(b.landmarks());
    benchmark::DoNotOptimize(b.trajectory());
    state.counters["updates"] = static_cast<double>(b.updateCount());
    const IncrementalStats& held = b.heldFactorStats();
    state.counters["rebuilds"] = static_cast<double>(held.rebuilds);
    state.counters["fresh_orderings"] = static_cast<double>(held.fresh_orderings);
    state.counters["in_place"] = static_cast<double>(held.modifications);
    setPartialCounters(state, held);
    setMeanStepCounters(state, step_ms);
    // Median update over the first and the last 10% of the updates (the issue's growth measure).
    const std::size_t tenth = std::max<std::size_t>(1, update_ms.size() / 10);
    const auto median = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    const double first = median({update_ms.begin(), update_ms.begin() + tenth});
    const double last = median({update_ms.end() - tenth, update_ms.end()});
    state.counters["upd_first10_ms"] = first;
    state.counters["upd_last10_ms"] = last;
    state.counters["upd_growth"] = last / first;
    setCounters(state, b.graph());
  }
}

/// Median of the first and of the last 10% of `v`.
std::pair<double, double> firstLastMedians(const std::vector<double>& v) {
  const std::size_t tenth = std::max<std::size_t>(1, v.size() / 10);
  const auto median = [](std::vector<double> x) {
    std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
    return x[x.size() / 2];
  };
  return {median({v.begin(), v.begin() + tenth}), median({v.end() - tenth, v.end()})};
}

/// The lifelong scenario (docs/DATASETS.md) streamed from the simulator, seed 1, the first
/// state.range(0) steps, no max_poses, the map capped at 100 landmarks: after each step the
/// landmarks seen longest ago leave (removeLandmark; the held factor folds the removals in at its
/// next update). CPU time of every update (a step that ran an incremental update), median over the
/// first and the last 10% of the updates after the cap is first reached; and of every step.
void BM_Lifelong(benchmark::State& state) {
  dataset::SimulationOptions so;
  so.scenario = dataset::SimulationOptions::ScenarioKind::Lifelong;
  so.seed = 1;
  so.laps = 12;
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  std::vector<Step> steps;
  dataset::Simulator sim(so);
  sim.run([&](const Step& s) {
    if (steps.size() < n) steps.push_back(s);
  });
  RangeBearingNoise noise;
  noise.std_sensor_range = sim.noise().std_range;
  noise.std_sensor_yaw_deg = sim.noise().std_yaw * 180.0 / M_PI;
  GraphSlamOptions options;
  options.relinearize_threshold = static_cast<double>(state.range(1)) * 1e-3;
  options.wildfire_threshold = static_cast<double>(state.range(2)) * 1e-6;
  const std::size_t cap = 100;
  for (auto _ : state) {
    GraphBackend b(options, noise);
    std::map<LandmarkId, StepIndex> last_seen;
    std::vector<double> update_ms, step_ms;
    bool capped = false;
    for (const Step& s : steps) {
      const std::size_t before = b.updateCount();
      const double t0 = threadCpuMs();
      b.process(s);
      benchmark::DoNotOptimize(b.robotPose());
      for (LandmarkId id : b.lastAssociation()) last_seen[id] = s.index;
      while (b.landmarkCount() > cap) {
        auto oldest =
            std::min_element(last_seen.begin(), last_seen.end(), [](const auto& a, const auto& c) {
              return a.second != c.second ? a.second < c.second : a.first < c.first;
            });
        b.removeLandmark(oldest->first);
        last_seen.erase(oldest);
        capped = true;
      }
      const double dt = threadCpuMs() - t0;
      if (capped) {
        step_ms.push_back(dt);
        if (b.updateCount() != before) update_ms.push_back(dt);
      }
    }
    const auto [uf, ul] = firstLastMedians(update_ms);
    const auto [sf, sl] = firstLastMedians(step_ms);
    state.counters["upd_first10_ms"] = uf;
    state.counters["upd_last10_ms"] = ul;
    state.counters["upd_growth"] = ul / uf;
    state.counters["step_first10_ms"] = sf;
    state.counters["step_last10_ms"] = sl;
    state.counters["step_growth"] = sl / sf;
    state.counters["updates"] = static_cast<double>(b.updateCount());
    const IncrementalStats& held = b.heldFactorStats();
    state.counters["rebuilds"] = static_cast<double>(held.rebuilds);
    state.counters["fresh_orderings"] = static_cast<double>(held.fresh_orderings);
    state.counters["in_place"] = static_cast<double>(held.modifications);
    setPartialCounters(state, held);
    setMeanStepCounters(state, step_ms);
    setCounters(state, b.graph());
  }
}

// Steps of the prefix; 6968 steps = the whole file (6969 poses with the start pose).
#define SIZES Arg(500)->Arg(1000)->Arg(2000)->Arg(4000)->Arg(6968)
BENCHMARK(BM_FastAll)->SIZES->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_FastGivenFactor)->SIZES->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_FactorizeOnly)->SIZES->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_NaiveAll)->SIZES->Unit(benchmark::kMillisecond)->Iterations(1);
// Second argument: GraphSlamOptions::relinearize_threshold in mm (and mrad; 0: full Gauss-Newton
// on the held factor, 100: the default); third: reorder_fill_ratio x 10 (0: the default, 10:
// a fresh ordering and a full refactorization at every change, no change in place); fourth:
// wildfire_threshold in um (and urad; 1000: the default, 0: every change spreads).
BENCHMARK(BM_FullSlam)
    ->Args({6968, 100, 0, 1000})
    ->Args({6968, 100, 0, 0})
    ->Args({6968, 10, 0, 1000})
    ->Args({6968, 0, 0, 1000})
    ->Args({6968, 100, 10, 1000})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
// Steps, relinearize_threshold in mm, wildfire_threshold in um.
BENCHMARK(BM_Lifelong)
    ->Args({20000, 100, 1000})
    ->Args({20000, 100, 0})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
}  // namespace

BENCHMARK_MAIN();
