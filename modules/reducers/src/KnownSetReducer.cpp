#include "budget_slam/reducers/KnownSetReducer.h"

#include <cstdlib>
#include <limits>
#include <ostream>

#include "budget_slam/core/Error.h"

namespace budget_slam::reducers {
namespace {

using O = KnownSetOptions;

const EnumNames<O::When>& whenNames() {
  static const EnumNames<O::When> n = {{"first_sight", O::When::FirstSight}, {"end", O::When::End}};
  return n;
}

/// The ids, each a landmark id >= 0 (the KeyError names the first bad one).
std::set<LandmarkId> parseIds(const std::vector<std::string>& ids) {
  std::set<LandmarkId> out;
  for (const std::string& t : ids) {
    char* end = nullptr;
    const long long v = std::strtoll(t.c_str(), &end, 10);
    if (t.empty() || *end != '\0' || v < 0)
      throw KeyError::ofValue(O::kSection, "ids", t, "not a landmark id (an integer >= 0)");
    out.insert(static_cast<LandmarkId>(v));
  }
  return out;
}

}  // namespace

const OptionTable<KnownSetOptions>& KnownSetOptions::table() {
  static const OptionTable<O> t = {
      option::list("ids", &O::ids, "landmark ids, comma or space separated"),
      option::choice("when", &O::when, whenNames(), "first_sight | end"),
  };
  return t;
}

KnownSetReducer::KnownSetReducer(const KnownSetOptions& options)
    : options_(options), set_(parseIds(options.ids)) {}

ReducerChoice KnownSetReducer::choose(const DropContext& ctx) {
  // Outside the set first (lowest id), else the set's highest id.
  ReducerChoice best;
  bool best_outside = false;
  for (const std::size_t i : ctx.candidates) {
    const LandmarkId id = ctx.landmarks[i].id;
    const bool outside = !set_.count(id);
    const bool better = best.id == kNoLandmarkId || (outside && !best_outside) ||
                        (outside == best_outside && (outside ? id < best.id : id > best.id));
    if (better) best = {id, outside ? 0.0 : 1.0}, best_outside = outside;
  }
  return best;
}

ScheduledDrops KnownSetReducer::scheduled(const ScheduleContext& ctx) {
  ScheduledDrops out;
  out.reason = "known_set";
  if (options_.when == KnownSetOptions::When::End && !ctx.final) return out;
  for (const LandmarkView& l : ctx.backend.landmarks())
    if (!set_.count(l.id)) out.drops.push_back({l.id, 0.0});
  return out;
}

ReducerRegistry::Entry KnownSetReducer::entry() {
  return {kName,
          "not a rule: keeps exactly the landmarks [KnownSetReducer] ids names, every other one "
          "dropped at first sight (or at the end)",
          {{KnownSetOptions::kSection, KnownSetOptions::describe(),
            [](const mrpt::config::CConfigFileBase& ini) {
              KnownSetOptions o;
              o.loadFromConfigFile(ini, KnownSetOptions::kSection);
              parseIds(o.ids);
            }}},
          [](const mrpt::config::CConfigFileBase& ini, std::uint64_t) {
            KnownSetOptions o;
            o.loadFromConfigFile(ini, KnownSetOptions::kSection);
            return std::make_unique<KnownSetReducer>(o);
          }};
}

}  // namespace budget_slam::reducers
