// Time of one drop decision of mi, coverage and coverage-mi at N landmarks (docs/PERFORMANCE.md
// "Reducers"). The state is EKF-like: a random dense SPD covariance of size 3 + 2N (robot, then
// landmarks) behind GaussianStateBackend, whose information gain is the EKF backend's own
// evaluator (gaussian::BlockMutualInformation). Each iteration forgets the factorization first, as
// a new filter step does, so a decision includes it: O(N^3) for mi and coverage-mi.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <numeric>
#include <random>

#include "budget_slam/gaussian/GaussianStateBackend.h"
#include "budget_slam/reducers/MutualInformationReducer.h"
#include "budget_slam/reducers/ViewClusterReducers.h"

using namespace budget_slam;
using namespace budget_slam::reducers;
using budget_slam::gaussian::GaussianStateBackend;

namespace {

struct Case {
  std::unique_ptr<GaussianStateBackend> state;
  std::vector<LandmarkView> landmarks;
  std::vector<std::size_t> candidates;
};

/// N landmarks along a 2-D random walk of observation positions (a trajectory), dense SPD
/// covariance A A^T / n + 0.01 I.
const Case& stateOf(int n_landmarks) {
  static std::map<int, Case> cache;
  auto it = cache.find(n_landmarks);
  if (it != cache.end()) return it->second;
  std::mt19937 rng(static_cast<unsigned>(n_landmarks));
  std::normal_distribution<double> g;
  const int n = 3 + 2 * n_landmarks;
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = g(rng);
  Eigen::MatrixXd P = A * A.transpose() / n;
  P.diagonal().array() += 0.01;
  std::vector<LandmarkView> lms(n_landmarks);
  Eigen::Vector2d walk(0, 0);
  for (int i = 0; i < n_landmarks; ++i) {
    walk += Eigen::Vector2d(g(rng), g(rng));
    lms[i].id = i;
    lms[i].n_obs = 5;
    lms[i].obs_mean = walk;
    lms[i].last_step = 0;
  }
  Case c;
  c.state = std::make_unique<GaussianStateBackend>(lms, P, 100);
  c.landmarks = c.state->landmarks();
  c.candidates.resize(n_landmarks);
  std::iota(c.candidates.begin(), c.candidates.end(), 0);
  return cache.emplace(n_landmarks, std::move(c)).first->second;
}

void decide(benchmark::State& st, Reducer& r) {
  const Case& c = stateOf(static_cast<int>(st.range(0)));
  const DropContext ctx{*c.state, c.landmarks, c.candidates, 100};
  for (auto _ : st) {
    c.state->resetCache();
    benchmark::DoNotOptimize(r.choose(ctx));
  }
  st.SetComplexityN(st.range(0));
}

void BM_Mi(benchmark::State& st) {
  MutualInformationReducer r{MutualInformationOptions()};
  decide(st, r);
}

void BM_Coverage(benchmark::State& st) {
  ViewClusterReducer r{CoverageOptions()};
  decide(st, r);
}

void BM_CoverageMi(benchmark::State& st) {
  ViewClusterGainReducer r{CoverageOptions()};
  decide(st, r);
}

/// The second and later drops of one event: gains from the Schur-updated information, no new
/// factorization (O(N^2) per drop). Times a decision plus the removal, on a copy per batch.
void BM_MiNextDropSameEvent(benchmark::State& st) {
  const Case& c = stateOf(static_cast<int>(st.range(0)));
  MutualInformationReducer r{MutualInformationOptions()};
  for (auto _ : st) {
    st.PauseTiming();
    GaussianStateBackend copy = *c.state;
    copy.resetCache();
    std::vector<LandmarkId> ids;
    for (const auto& l : c.landmarks) ids.push_back(l.id);
    copy.informationGain(ids);  // the event's one factorization, not timed
    copy.removeLandmark(ids[0]);
    const auto lms = copy.landmarks();
    std::vector<std::size_t> cand(lms.size());
    std::iota(cand.begin(), cand.end(), 0);
    st.ResumeTiming();
    const auto v = r.choose({copy, lms, cand, 100});
    copy.removeLandmark(v.id);
    benchmark::DoNotOptimize(v);
  }
  st.SetComplexityN(st.range(0));
}

#define SIZES Arg(50)->Arg(100)->Arg(200)->Arg(400)->Arg(800)->Unit(benchmark::kMillisecond)
BENCHMARK(BM_Mi)->SIZES->Complexity();
BENCHMARK(BM_Coverage)->SIZES->Complexity();
BENCHMARK(BM_CoverageMi)->SIZES->Complexity();
BENCHMARK(BM_MiNextDropSameEvent)->SIZES->Iterations(10)->Complexity();

}  // namespace

int main(int argc, char** argv) {
  // Build every state first. Besides keeping set-up out of the timings, this puts glibc's
  // allocator in the state of a long run: its mmap threshold rises once a large block is freed,
  // and without that the first benchmark alone would pay page faults on every allocation.
  for (const int n : {50, 100, 200, 400, 800}) stateOf(n);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
