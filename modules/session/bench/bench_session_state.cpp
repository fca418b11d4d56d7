// Writing and reading a session state of N landmarks (docs/PERFORMANCE.md "Session state"): the
// text of the file (formatSessionState, the writer's checks included: a Cholesky factorization
// of the 3 + 2N joint covariance) and reading it back (readSessionStateBytes, every check
// included). The state is the tests' sample: a dense SPD joint covariance, a robot, two owner
// sections. Counters: the file's size [bytes].
#include <benchmark/benchmark.h>

#include <map>

#include "../tests/SessionTestUtil.h"

using namespace budget_slam::session;

namespace {

const std::pair<SessionState, std::string>& caseOf(int n) {
  static std::map<int, std::pair<SessionState, std::string>> cache;
  auto it = cache.find(n);
  if (it == cache.end()) {
    SessionState s = test::sampleState(static_cast<std::size_t>(n), true, 7);
    std::string text = formatSessionState(s);
    it = cache.emplace(n, std::make_pair(std::move(s), std::move(text))).first;
  }
  return it->second;
}

void BM_FormatSessionState(benchmark::State& st) {
  const auto& c = caseOf(static_cast<int>(st.range(0)));
  for (auto _ : st) benchmark::DoNotOptimize(formatSessionState(c.first));
  st.counters["bytes"] = static_cast<double>(c.second.size());
}

void BM_ReadSessionState(benchmark::State& st) {
  const auto& c = caseOf(static_cast<int>(st.range(0)));
  for (auto _ : st) benchmark::DoNotOptimize(readSessionStateBytes("s.txt", c.second));
  st.counters["bytes"] = static_cast<double>(c.second.size());
}

}  // namespace

BENCHMARK(BM_FormatSessionState)
    ->Arg(50)
    ->Arg(200)
    ->Arg(1000)
    ->Arg(2000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadSessionState)
    ->Arg(50)
    ->Arg(200)
    ->Arg(1000)
    ->Arg(2000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
