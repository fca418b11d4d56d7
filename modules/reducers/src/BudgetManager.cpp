#include "budget_slam/reducers/BudgetManager.h"

#include <algorithm>
#include <stdexcept>

namespace budget_slam::reducers {

std::vector<std::size_t> dropCandidates(const std::vector<LandmarkView>& landmarks, StepIndex step,
                                        std::size_t protect_recent_steps, bool* all_protected) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    // Seen in the last P steps means last_step in (step - P, step].
    const bool is_protected =
        step - landmarks[i].last_step < protect_recent_steps && landmarks[i].last_step <= step;
    if (!is_protected) out.push_back(i);
  }
  *all_protected = out.empty();
  if (out.empty())
    for (std::size_t i = 0; i < landmarks.size(); ++i) out.push_back(i);
  return out;
}

BudgetManager::BudgetManager(const BudgetOptions& options, std::unique_ptr<Reducer> active,
                             std::vector<std::unique_ptr<Reducer>> shadows)
    : options_(options), active_(std::move(active)), shadows_(std::move(shadows)) {
  std::vector<std::string> names;
  if (active_) names.push_back(active_->name());
  for (const auto& s : shadows_) names.push_back(s->name());
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = i + 1; j < names.size(); ++j) agreements_.push_back({names[i], names[j]});
}

std::vector<Eviction> BudgetManager::enforce(Backend& backend, StepIndex step) {
  std::vector<Eviction> out;
  if (!active_) return out;
  bool event_started = false;
  while (backend.landmarkCount() > options_.max_landmarks) {
    if (!event_started && before_drop_event_) before_drop_event_(backend, step);
    event_started = true;

    const auto landmarks = backend.landmarks();
    bool all_protected = false;
    const auto candidates =
        dropCandidates(landmarks, step, options_.protect_recent_steps, &all_protected);
    const DropContext ctx{backend, landmarks, candidates, step};

    std::vector<ReducerChoice> choices;
    choices.push_back(active_->choose(ctx));
    for (auto& s : shadows_) choices.push_back(s->choose(ctx));
    const ReducerChoice victim = choices.front();
    if (std::none_of(candidates.begin(), candidates.end(),
                     [&](std::size_t i) { return landmarks[i].id == victim.id; }))
      throw std::logic_error("reducer '" + active_->name() + "' chose landmark " +
                             std::to_string(victim.id) + ", not a candidate");

    std::size_t pair = 0;
    for (std::size_t i = 0; i < choices.size(); ++i)
      for (std::size_t j = i + 1; j < choices.size(); ++j, ++pair) {
        agreements_[pair].total++;
        agreements_[pair].agree += choices[i].id == choices[j].id;
      }

    Eviction e;
    e.step = step;
    e.id = victim.id;
    e.reducer = active_->name();
    e.score = victim.score;
    e.n_before = landmarks.size();
    backend.removeLandmark(victim.id);
    e.n_after = backend.landmarkCount();
    e.reason = all_protected ? "over_cap_all_protected" : "over_cap";
    for (std::size_t k = 0; k < shadows_.size(); ++k)
      e.shadow.emplace_back(shadows_[k]->name(), choices[k + 1]);
    evicted_.insert(victim.id);
    out.push_back(std::move(e));
  }
  return out;
}

std::vector<Agreement> BudgetManager::agreements() const { return agreements_; }

}  // namespace budget_slam::reducers
