#include "budget_slam/reducers/MutualInformationReducer.h"

#include "ReducerSession.h"
#include "budget_slam/reducers/ActiveMinimization.h"

namespace budget_slam::reducers {

MutualInformationReducer::MutualInformationReducer(const MutualInformationOptions& options)
    : options_(options) {}

ReducerChoice MutualInformationReducer::choose(const DropContext& ctx) {
  std::vector<LandmarkId> ids;
  ids.reserve(ctx.candidates.size());
  for (const std::size_t i : ctx.candidates) ids.push_back(ctx.landmarks[i].id);
  // One call for every candidate: the EKF factorizes once per drop event (Schur updates after).
  const auto gains = ctx.backend.informationGain(ids);
  ReducerChoice best{ids[0], gains[0]};
  for (std::size_t i = 1; i < ids.size(); ++i)
    if (gains[i] < best.score || (gains[i] == best.score && ids[i] < best.id))
      best = {ids[i], gains[i]};
  return best;
}

ScheduledDrops MutualInformationReducer::scheduled(const ScheduleContext& ctx) {
  using Mode = MutualInformationOptions::Mode;
  if (options_.mode != Mode::Cap && !look_ahead_checked_ && ctx.backend.landmarkCount() > 0) {
    // Fail at the first step with landmarks, not after the whole run.
    checkLookAhead(ctx, MutualInformationOptions::modeName(options_.mode));
    look_ahead_checked_ = true;
  }
  switch (options_.mode) {
    case Mode::Cap:
      return {};
    case Mode::Objective:
      if (!ctx.final) return {};
      return activeMinimization(ctx, options_.lambda, options_.pose_lag, "objective",
                                options_.stop == MutualInformationOptions::Stop::GlobalMinimum);
    case Mode::Incremental:
      if (ctx.final) return {};
      // Alg. 5 line 6, one pose a step: minimize once psi poses were added since the last time.
      if (++steps_since_minimization_ < options_.psi) return {};
      steps_since_minimization_ = 0;
      return activeMinimization(ctx, options_.lambda, options_.pose_lag, "incremental",
                                options_.stop == MutualInformationOptions::Stop::GlobalMinimum);
  }
  return {};
}

ReducerRegistry::Entry MutualInformationReducer::entry() {
  return {kName,
          "lowest information gain I(L; rest) in bits (Choudhary et al.); modes cap, objective "
          "(Alg. 3), incremental (Alg. 5)",
          {tabledSection<MutualInformationOptions>()},
          [](const mrpt::config::CConfigFileBase& ini, std::uint64_t) {
            MutualInformationOptions o;
            o.loadFromConfigFile(ini, MutualInformationOptions::kSection);
            return std::make_unique<MutualInformationReducer>(o);
          }};
}

void MutualInformationReducer::saveSession(session::SessionState& state) const {
  state.section(reducerSection(name()))
      .putInteger("steps_since_minimization", static_cast<std::int64_t>(steps_since_minimization_));
}

void MutualInformationReducer::restoreSession(const session::SessionState& state) {
  const session::SessionSection& s = state.take(reducerSection(name()));
  steps_since_minimization_ = static_cast<std::size_t>(
      s.integer("steps_since_minimization", 0, static_cast<std::int64_t>(options_.psi)));
}

}  // namespace budget_slam::reducers
