#pragma once
#include "budget_slam/core/ReducerRegistry.h"
#include "budget_slam/reducers/CoverageOptions.h"

namespace budget_slam::reducers {

// Hochdorfer & Schlegel's "coverage" is the spread of the places a landmark was seen from; the
// reducers keep the paper's word as their registry names (`coverage`, `coverage-mi`, section
// [CoverageReducer]) and the classes say what they cluster: the viewpoints. Not the place
// coverage of `place-coverage` (PlaceCoverageReducer), nor relocalization coverage (metrics).

/// `coverage` (Hochdorfer & Schlegel; docs/ALGORITHMS.md "coverage"): cluster the landmarks by
/// where they were seen from (coverageClusters), rate each by Dissanayake's information content I =
/// 1/sigma_xx^2 + 1/sigma_yy^2 (their Eq. 4), take the cluster with the largest max I - min I over
/// its members (Eq. 5) among those holding a candidate, and drop its lowest-I candidate. Score:
/// that I [1/m^2].
class ViewClusterReducer : public Reducer {
 public:
  explicit ViewClusterReducer(const CoverageOptions& options) : options_(options) {}
  static constexpr const char* kName = "coverage";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override;
  void dumpOptions(std::ostream& out) const override { options_.dumpToTextStream(out); }
  static ReducerRegistry::Entry entry();

 private:
  CoverageOptions options_;
};

/// `coverage-mi`: the same clusters, but usefulness is the information gain I(L; rest) in bits
/// (Backend::informationGain) instead of the diagonal information content, and a cluster's
/// spread is max IG over its members - IG of its least informative candidate. Drops that
/// candidate of the cluster with the largest spread. Score: its gain [bits]. Rationale in
/// docs/ALGORITHMS.md.
class ViewClusterGainReducer : public Reducer {
 public:
  explicit ViewClusterGainReducer(const CoverageOptions& options) : options_(options) {}
  static constexpr const char* kName = "coverage-mi";
  std::string name() const override { return kName; }
  ReducerChoice choose(const DropContext& ctx) override;
  void dumpOptions(std::ostream& out) const override { options_.dumpToTextStream(out); }
  static ReducerRegistry::Entry entry();

 private:
  CoverageOptions options_;
};

}  // namespace budget_slam::reducers
