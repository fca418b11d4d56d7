#pragma once
#include <random>

#include "budget_slam/core/ReducerRegistry.h"
#include "budget_slam/session/SessionStateOwner.h"

namespace budget_slam::reducers {

/// `random`: a uniformly random candidate from a seeded generator (score: 0).
class RandomReducer : public Reducer, public session::SessionStateOwner {
 public:
  explicit RandomReducer(std::uint64_t seed) : rng_(seed) {}
  static constexpr const char* kName = "random";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override;
  static ReducerRegistry::Entry entry();
  /// Section `reducer.random`: the generator's state (its standard text form), so that a resumed
  /// run draws what the one-shot run would have drawn next.
  void saveSession(session::SessionState& state) const override;
  void restoreSession(const session::SessionState& state) override;

 private:
  std::mt19937_64 rng_;  ///< mt19937_64 output is fixed by the standard: same seed, same run
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
