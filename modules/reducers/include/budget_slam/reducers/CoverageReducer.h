#pragma once
#include "budget_slam/core/ReducerRegistry.h"
#include "budget_slam/reducers/CoverageOptions.h"

namespace budget_slam::reducers {

/// `coverage` (Hochdorfer & Schlegel; docs/ALGORITHMS.md "coverage"): cluster the landmarks by
/// where they were seen from (coverageClusters), rate each by Dissanayake's information content I =
/// 1/sigma_xx^2 + 1/sigma_yy^2 (their Eq. 4), take the cluster with the largest max I - min I over
/// its members (Eq. 5) among those holding a candidate, and drop its lowest-I candidate. Score:
/// that I [1/m^2].
class CoverageReducer : public Reducer {
 public:
  explicit CoverageReducer(const CoverageOptions& options) : options_(options) {}
  std::string name() const override { return "coverage"; }
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
class CoverageMiReducer : public Reducer {
 public:
  explicit CoverageMiReducer(const CoverageOptions& options) : options_(options) {}
  std::string name() const override { return "coverage-mi"; }
  ReducerChoice choose(const DropContext& ctx) override;
  void dumpOptions(std::ostream& out) const override { options_.dumpToTextStream(out); }
  static ReducerRegistry::Entry entry();

 private:
  CoverageOptions options_;
};

}  // namespace budget_slam::reducers
