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

const OptionTable<RandomOptions>& RandomOptions::table() {
  using O = RandomOptions;
  static const EnumNames<Draw> names = {{"each_drop", Draw::EachDrop},
                                        {"per_landmark", Draw::PerLandmark}};
  static const OptionTable<O> t = {
      option::choice("draw", &O::draw, names, "each_drop | per_landmark"),
  };
  return t;
}

namespace {
/// Steele, Lea & Flood's splitmix64 finalizer: a bijection of 64-bit words whose outputs for
/// consecutive inputs pass BigCrush.
std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
}  // namespace

double RandomReducer::landmarkScore(std::uint64_t seed, LandmarkId id) {
  const std::uint64_t h = splitmix64(splitmix64(seed) ^ static_cast<std::uint64_t>(id));
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

ReducerChoice RandomReducer::choose(const DropContext& ctx) {
  if (options_.draw == RandomOptions::Draw::PerLandmark)
    return lowestScore(ctx, [this](const LandmarkView& l) { return landmarkScore(seed_, l.id); });
  // Modulo of the raw 64-bit output rather than std::uniform_int_distribution, whose algorithm
  // differs between standard libraries; the bias is below 1e-16 for any map size.
  const std::size_t k = static_cast<std::size_t>(rng_() % ctx.candidates.size());
  return {ctx.landmarks[ctx.candidates[k]].id, 0.0};
}

ReducerRegistry::Entry RandomReducer::entry() {
  return {kName,
          "a uniformly random unprotected landmark (seeded by [LandmarkBudget] seed)",
          {tabledSection<RandomOptions>()},
          [](const mrpt::config::CConfigFileBase& ini, std::uint64_t seed) {
            RandomOptions o;
            o.loadFromConfigFile(ini, RandomOptions::kSection);
            return std::make_unique<RandomReducer>(seed, o);
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
