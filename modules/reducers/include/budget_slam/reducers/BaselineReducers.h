#pragma once
#include <random>

#include "budget_slam/core/OptionTable.h"
#include "budget_slam/core/ReducerRegistry.h"
#include "budget_slam/session/SessionStateOwner.h"

namespace budget_slam::reducers {

/// [RandomReducer] (docs/ALGORITHMS.md "Baselines", docs/EXPERIMENTS.md "The honest random
/// baseline").
struct RandomOptions : public TabledOptions<RandomOptions> {
  static constexpr const char* kSection = "RandomReducer";
  /// When the randomness is drawn.
  enum class Draw {
    EachDrop,    ///< each_drop: a fresh uniform draw among the candidates at every drop
    PerLandmark  ///< per_landmark: one uniform score a landmark, fixed for the run (a function of
                 ///< the seed and its id); the candidate with the lowest score goes
  };
  Draw draw = Draw::EachDrop;
  static const OptionTable<RandomOptions>& table();
};

/// `random`: a uniformly random candidate (score: 0 with each_drop; the landmark's score in
/// [0, 1) with per_landmark). With each_drop a landmark dropped and seen again is a new coin, so
/// under re-admission the final map follows what was seen last; with per_landmark the reducer is
/// a rule whose scores carry no information, consistent over time as every other rule's are.
class RandomReducer : public Reducer, public session::SessionStateOwner {
 public:
  explicit RandomReducer(std::uint64_t seed, const RandomOptions& options = {})
      : rng_(seed), seed_(seed), options_(options) {}
  static constexpr const char* kName = "random";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override;
  void dumpOptions(std::ostream& out) const override { options_.dumpToTextStream(out); }
  static ReducerRegistry::Entry entry();
  /// The per_landmark score of landmark `id` under `seed`, uniform in [0, 1): the 53 high bits
  /// of splitmix64(splitmix64(seed) ^ id) (independent across ids for a seed).
  static double landmarkScore(std::uint64_t seed, LandmarkId id);
  /// Section `reducer.random`: the generator's state (its standard text form), so that a resumed
  /// run draws what the one-shot run would have drawn next.
  void saveSession(session::SessionState& state) const override;
  void restoreSession(const session::SessionState& state) override;

 private:
  std::mt19937_64 rng_;  ///< mt19937_64 output is fixed by the standard: same seed, same run
  std::uint64_t seed_;
  RandomOptions options_;
};

/// `oldest`: the candidate first seen earliest; ties by lowest id (score: first step).
class OldestReducer : public Reducer {
 public:
  static constexpr const char* kName = "oldest";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override;
  static ReducerRegistry::Entry entry();
};

/// `info-content`: the candidate with the lowest Dissanayake information content
/// 1/sigma_xx^2 + 1/sigma_yy^2, ties by lowest id (score: that content [1/m^2]). Hochdorfer &
/// Schlegel's rule without the coverage clustering.
class InfoContentReducer : public Reducer {
 public:
  static constexpr const char* kName = "info-content";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override;
  static ReducerRegistry::Entry entry();
};

}  // namespace budget_slam::reducers
