#include "budget_slam/reducers/ViewClusterReducers.h"

#include "budget_slam/reducers/CoverageSelection.h"
#include "budget_slam/reducers/InformationContent.h"

namespace budget_slam::reducers {
namespace {

/// [CoverageReducer] with the run's seed unless the section sets its own.
CoverageOptions loadOptions(const mrpt::config::CConfigFileBase& ini, std::uint64_t seed) {
  CoverageOptions o;
  o.seed = seed;
  o.loadFromConfigFile(ini, CoverageOptions::kSection);
  return o;
}

}  // namespace

ReducerChoice ViewClusterReducer::choose(const DropContext& ctx) {
  const auto clusters = coverageClusters(ctx.landmarks, options_);
  std::vector<double> info;
  info.reserve(ctx.landmarks.size());
  for (const auto& l : ctx.landmarks) info.push_back(informationContent(l.cov));
  const auto p = pickByClusterSpread(ctx, clusters.label, info, Spread::Members);
  return {p.id, p.score};
}

ReducerRegistry::Entry ViewClusterReducer::entry() {
  return {kName,
          "coverage clusters of observation positions, drop the lowest 1/sigma^2 sum in the "
          "cluster of widest spread (Hochdorfer & Schlegel)",
          {tabledSection<CoverageOptions>()},
          [](const mrpt::config::CConfigFileBase& ini, std::uint64_t seed) {
            return std::make_unique<ViewClusterReducer>(loadOptions(ini, seed));
          }};
}

ReducerChoice ViewClusterGainReducer::choose(const DropContext& ctx) {
  const auto clusters = coverageClusters(ctx.landmarks, options_);
  // Gains of every landmark, protected ones too: they define what stays in each region.
  std::vector<LandmarkId> ids;
  ids.reserve(ctx.landmarks.size());
  for (const auto& l : ctx.landmarks) ids.push_back(l.id);
  const auto gains = ctx.backend.informationGain(ids);
  const auto p =
      pickByClusterSpread(ctx, clusters.label, gains, Spread::BestMemberOverWorstCandidate);
  return {p.id, p.score};
}

ReducerRegistry::Entry ViewClusterGainReducer::entry() {
  return {kName,
          "coverage clusters, choice within and across them by information gain in bits "
          "(uses [CoverageReducer])",
          {tabledSection<CoverageOptions>()},
          [](const mrpt::config::CConfigFileBase& ini, std::uint64_t seed) {
            return std::make_unique<ViewClusterGainReducer>(loadOptions(ini, seed));
          }};
}

}  // namespace budget_slam::reducers
