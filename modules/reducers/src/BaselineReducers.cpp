#include "budget_slam/reducers/BaselineReducers.h"

#include <sstream>

#include "ReducerSession.h"
#include "budget_slam/reducers/InformationContent.h"

namespace budget_slam::reducers {
namespace {

/// The candidate with the lowest score, ties to the lowest id.
template <class ScoreFn>
ReducerChoice lowestScore(const DropContext& ctx, ScoreFn score) {
  ReducerChoice best;
  bool first = true;
  for (const std::size_t i : ctx.candidates) {
    const auto& l = ctx.landmarks[i];
    const double s = score(l);
    if (first || s < best.score || (s == best.score && l.id < best.id)) best = {l.id, s};
    first = false;
  }
  return best;
}

}  // namespace

ReducerChoice RandomReducer::choose(const DropContext& ctx) {
  // Modulo of the raw 64-bit output rather than std::uniform_int_distribution, whose algorithm
  // differs between standard libraries; the bias is below 1e-16 for any map size.
  const std::size_t k = static_cast<std::size_t>(rng_() % ctx.candidates.size());
  return {ctx.landmarks[ctx.candidates[k]].id, 0.0};
}

ReducerRegistry::Entry RandomReducer::entry() {
  return {kName,
          "a uniformly random unprotected landmark (seeded by [LandmarkBudget] seed)",
          {},
          [](const mrpt::config::CConfigFileBase&, std::uint64_t seed) {
            return std::make_unique<RandomReducer>(seed);
          }};
}

ReducerChoice OldestReducer::choose(const DropContext& ctx) {
  return lowestScore(ctx, [](const LandmarkView& l) { return static_cast<double>(l.first_step); });
}

ReducerRegistry::Entry OldestReducer::entry() {
  return {kName,
          "the landmark first seen earliest",
          {},
          [](const mrpt::config::CConfigFileBase&, std::uint64_t) {
            return std::make_unique<OldestReducer>();
          }};
}

ReducerChoice InfoContentReducer::choose(const DropContext& ctx) {
  return lowestScore(ctx, [](const LandmarkView& l) { return informationContent(l.cov); });
}

ReducerRegistry::Entry InfoContentReducer::entry() {
  return {kName,
          "lowest 1/sigma_xx^2 + 1/sigma_yy^2 (Dissanayake), no coverage",
          {},
          [](const mrpt::config::CConfigFileBase&, std::uint64_t) {
            return std::make_unique<InfoContentReducer>();
          }};
}

void RandomReducer::saveSession(session::SessionState& state) const {
  std::ostringstream o;
  o << rng_;
  state.section(reducerSection(name())).putText("rng_state", o.str());
}

void RandomReducer::restoreSession(const session::SessionState& state) {
  const session::SessionSection& s = state.take(reducerSection(name()));
  std::istringstream in(s.text("rng_state"));
  std::mt19937_64 rng;
  in >> rng;
  // Exactly the generator's state (its 312 words and position) and nothing after it.
  std::string rest;
  if (in.fail() || (in >> rest, !rest.empty()))
    s.fail("rng_state", "not the state of a mt19937_64 generator");
  rng_ = rng;
}

}  // namespace budget_slam::reducers
