#include "budget_slam/reducers/BudgetManager.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/StepFilter.h"

namespace budget_slam::reducers {

std::vector<std::size_t> dropCandidates(const std::vector<LandmarkView>& landmarks, StepIndex step,
                                        const BudgetOptions& options, bool* all_protected) {
  const std::size_t P = options.protect_recent_steps;
  const bool compete = options.admission == BudgetOptions::Admission::Compete;
  // "In the last P steps" means a step in (step - P, step].
  const auto within = [&](StepIndex s) { return s <= step && step - s < P; };
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const LandmarkView& l = landmarks[i];
    const bool newcomer = compete && l.first_step == step;
    const bool is_protected =
        !newcomer && within(options.protect == BudgetOptions::Protect::RecentlySeen ? l.last_step
                                                                                    : l.first_step);
    if (!is_protected) out.push_back(i);
  }
  *all_protected = out.empty();
  if (out.empty())
    for (std::size_t i = 0; i < landmarks.size(); ++i) out.push_back(i);
  return out;
}

namespace {

/// A stop request (Ctrl-C) between two drops of one event: with none done yet, the event ends at
/// once (Interrupted); after some, the loop stops and returns them, so that every landmark that
/// left the map is in the log (the map may then stay over its cap for this last step).
bool stopBetweenDrops(const std::vector<Eviction>& done) {
  if (!Cancellation::requested()) return false;
  if (done.empty()) Cancellation::check();
  return true;
}

BudgetOptions inForce(BudgetOptions options, const Reducer* active) {
  const DropScheduler* scheduler = dropScheduler(active);
  if (scheduler && !scheduler->readmitsEvicted()) options.readmit_evicted = false;
  return options;
}

}  // namespace

void checkCap(const BudgetOptions& options, const Reducer* active) {
  if (options.max_landmarks || !active) return;
  if (const DropScheduler* s = dropScheduler(active); s && s->decidesMapSize()) return;
  throw KeyError::ofValue(BudgetOptions::kSection, "max_landmarks", "none",
                          "reducer '" + active->name() +
                              "' drops landmarks only to keep the map under a cap, so it needs a "
                              "number (no cap suits reducer none, and mi in objective or "
                              "incremental mode)",
                          ConfigErrorKind::NeedsCap);
}

BudgetManager::BudgetManager(const BudgetOptions& options, std::unique_ptr<Reducer> active,
                             std::vector<std::unique_ptr<Reducer>> shadows)
    : options_(inForce(options, active.get())),
      active_(std::move(active)),
      shadows_(std::move(shadows)),
      refusals_(options_.refusal_memory, options_.retry_after_steps) {
  checkCap(options_, active_.get());
  if (active_ && options_.negative_evidence != BudgetOptions::NegativeEvidenceMode::Off) {
    NegativeEvidence::Settings ne;
    ne.misses_to_distrust = options_.misses_to_distrust;
    ne.min_pass_steps = options_.miss_min_view_steps;
    ne.viewpoint_cell = options_.viewpoint_cell;
    ne.range_margin = options_.view_margin_range;
    ne.fov_margin = options_.view_margin_deg * M_PI / 180;
    negative_ = std::make_unique<NegativeEvidence>(ne);
  }
  if (options_.moved_landmarks == BudgetOptions::MovedMode::Split) {
    MovedLandmarks::Settings m;
    m.gate_chi2 = options_.moved_gate_chi2;
    m.readings = options_.moved_readings;
    m.place_distance = options_.moved_place_distance;
    m.min_agreeing = options_.moved_min_agreeing;
    moved_ = std::make_unique<MovedLandmarks>(m);
  }
  scheduler_ = dropScheduler(active_.get());
  if (ObservationKeeper* k = observationKeeper(active_.get())) observers_.push_back(k);
  for (const auto& s : shadows_)
    if (ObservationKeeper* k = observationKeeper(s.get())) observers_.push_back(k);
  std::vector<std::string> names;
  if (active_) names.push_back(active_->name());
  for (const auto& s : shadows_) {
    names.push_back(s->name());
    shadow_failures_.push_back({s->name(), 0, 0, 0, ""});
  }
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = i + 1; j < names.size(); ++j) agreements_.push_back({names[i], names[j]});
}

void BudgetManager::askShadows(const DropContext& ctx, const ReducerChoice& active, Eviction& e) {
  // choices[0] is the active reducer's; a failed shadow leaves its slot empty.
  std::vector<std::optional<ReducerChoice>> choices = {active};
  for (std::size_t k = 0; k < shadows_.size(); ++k) {
    try {
      choices.push_back(shadows_[k]->choose(ctx));
    } catch (const std::exception& ex) {
      // A shadow is only logged: its failure (e.g. mi on a covariance that lost positive
      // definiteness) never stops the run the active reducer is making.
      choices.emplace_back();
      const std::string why = ex.what();
      e.shadow_errors.emplace_back(shadows_[k]->name(), why.substr(0, why.find('\n')));
      ShadowFailures& f = shadow_failures_[k];
      if (f.failures++ == 0) f.first_step = ctx.step, f.first_error = e.shadow_errors.back().second;
      f.last_step = ctx.step;
    }
  }
  // Agreement counts the decisions at which both reducers of a pair answered.
  std::size_t pair = 0;
  for (std::size_t i = 0; i < choices.size(); ++i)
    for (std::size_t j = i + 1; j < choices.size(); ++j, ++pair) {
      if (!choices[i] || !choices[j]) continue;
      agreements_[pair].total++;
      agreements_[pair].agree += choices[i]->id == choices[j]->id;
    }
  for (std::size_t k = 0; k < shadows_.size(); ++k)
    e.shadow.emplace_back(shadows_[k]->name(),
                          choices[k + 1].value_or(ReducerChoice{
                              kNoLandmarkId, std::numeric_limits<double>::quiet_NaN()}));
}

std::vector<ShadowFailures> BudgetManager::shadowFailures() const {
  std::vector<ShadowFailures> out;
  for (const auto& f : shadow_failures_)
    if (f.failures) out.push_back(f);
  return out;
}

Eviction BudgetManager::dropLandmark(Backend& backend, const DropContext& ctx,
                                     const ReducerChoice& victim, std::string reason) {
  Eviction e;
  e.step = ctx.step;
  e.id = victim.id;
  e.reducer = active_->name();
  e.score = victim.score;
  e.n_before = ctx.landmarks.size();
  e.mean = std::find_if(ctx.landmarks.begin(), ctx.landmarks.end(), [&](const LandmarkView& l) {
             return l.id == victim.id;
           })->mean;
  e.reason = std::move(reason);
  askShadows(ctx, victim, e);
  backend.removeLandmark(victim.id);
  e.n_after = backend.landmarkCount();
  if (!options_.readmit_evicted) evicted_.insert(victim.id);  // only needed to filter
  for (ObservationKeeper* r : observers_) r->forget(victim.id);
  if (negative_) negative_->forget(victim.id);
  return e;
}

Eviction BudgetManager::dropDistrusted(Backend& backend, const std::vector<LandmarkView>& landmarks,
                                       LandmarkId id, StepIndex step) {
  Eviction e;
  e.step = step;
  e.id = id;
  e.reducer = active_->name();
  e.score = negative_->records().at(id).misses;  // the misses that condemned it
  e.n_before = backend.landmarkCount();
  const auto it = std::find_if(landmarks.begin(), landmarks.end(),
                               [&](const LandmarkView& l) { return l.id == id; });
  if (it != landmarks.end()) e.mean = it->mean;
  e.reason = "negative_evidence";
  backend.removeLandmark(id);
  e.n_after = backend.landmarkCount();
  if (!options_.readmit_evicted) evicted_.insert(id);
  for (ObservationKeeper* r : observers_) r->forget(id);
  negative_->forget(id);
  return e;
}

std::vector<Eviction> BudgetManager::weighNegativeEvidence(Backend& backend, StepIndex step,
                                                           const Step* processed) {
  std::vector<Eviction> out;
  if (!negative_ || !processed || !processed->scan) return out;
  const auto& scan = *processed->scan;
  SensorView sensor;
  sensor.pose_on_robot = Pose2(scan.sensor_pose_on_robot.x, scan.sensor_pose_on_robot.y,
                               scan.sensor_pose_on_robot.yaw);
  sensor.min_range = scan.min_range;
  sensor.max_range = scan.max_range;
  sensor.fov = scan.fov_yaw;
  const std::vector<LandmarkView> landmarks = backend.landmarks();
  negative_->update(step, backend.robotPose().mean, sensor, landmarks, backend.observedAt(step),
                    held_);
  if (options_.negative_evidence != BudgetOptions::NegativeEvidenceMode::Always) return out;
  for (const LandmarkId id : negative_->distrusted()) {
    if (stopBetweenDrops(out)) break;
    if (out.empty() && before_drop_event_) before_drop_event_(backend, step);
    out.push_back(dropDistrusted(backend, landmarks, id, step));
  }
  return out;
}

void BudgetManager::tellObservations(const Backend& backend, StepIndex step, const Step* processed,
                                     const Step* raw) {
  if (observers_.empty()) return;
  StepObservation seen;
  seen.step = step;
  seen.robot = backend.robotPose().mean;
  seen.observed = backend.observedAt(step);
  if (processed && processed->scan) {
    seen.sensor_max_range = processed->scan->max_range;
    seen.sensor_fov = processed->scan->fov_yaw;
    const auto& s = processed->scan->sensor_pose_on_robot;
    seen.sensor_pose = Pose2(s.x, s.y, s.yaw);
    // The landmark of each reading: the backend's association when it gives one (readings
    // without IDs), else the reading's own ID when that landmark is in the map.
    const std::vector<LandmarkId> association = backend.lastAssociation();
    const std::set<LandmarkId> observed(seen.observed.begin(), seen.observed.end());
    const auto& readings = processed->scan->readings;
    for (std::size_t i = 0; i < readings.size(); ++i) {
      const LandmarkId id = association.size() == readings.size() ? association[i] : readings[i].id;
      if (id != kNoLandmarkId && observed.count(id))
        seen.sightings.push_back({id, readings[i].range, readings[i].yaw});
    }
    // What admissible() left out: readings of the raw step whose landmark the processed step lacks.
    if (raw && raw != processed && raw->scan) {
      std::multiset<LandmarkId> kept;
      for (const auto& r : readings) kept.insert(r.id);
      for (const auto& r : raw->scan->readings) {
        if (r.id == kNoLandmarkId) continue;
        const auto it = kept.find(r.id);
        if (it != kept.end())
          kept.erase(it);
        else
          seen.withheld.push_back({r.id, r.range, r.yaw});
      }
    }
  }
  for (ObservationKeeper* r : observers_) r->observe(seen);
}

Step BudgetManager::admissible(const Step& raw) const {
  if (!raw.scan) return raw;
  const bool compete = options_.admission == BudgetOptions::Admission::Compete;
  std::set<LandmarkId> out;
  for (const auto& r : raw.scan->readings) {
    if (r.id == kNoLandmarkId) continue;
    if ((!options_.readmit_evicted && evicted_.count(r.id)) ||
        (compete && refusals_.withheld(r.id, raw.index)))
      out.insert(r.id);
  }
  return withoutReadingsOf(raw, out);
}

void BudgetManager::setReadingNoise(double std_range, double std_bearing) {
  if (moved_) moved_->setReadingNoise(std_range, std_bearing);
}

Step BudgetManager::admit(Backend& backend, const Step& raw) {
  Step step = admissible(raw);
  held_.clear();
  if (!moved_) return step;
  const MovedScreening screening = moved_->screen(backend, step, last_step_);
  if (!screening.moved.empty()) {
    const std::vector<LandmarkView> landmarks = backend.landmarks();
    for (const auto& [id, nis] : screening.moved) {
      Eviction e;
      e.step = raw.index;
      e.id = id;
      e.reducer = active_ ? active_->name() : "none";
      e.score = nis;
      e.n_before = backend.landmarkCount();
      const auto it = std::find_if(landmarks.begin(), landmarks.end(),
                                   [&](const LandmarkView& l) { return l.id == id; });
      if (it != landmarks.end()) e.mean = it->mean;
      e.reason = "moved";
      backend.removeLandmark(id);
      e.n_after = backend.landmarkCount();
      // Not remembered as evicted: the same sensor ID is the new landmark.
      for (ObservationKeeper* r : observers_) r->forget(id);
      if (negative_) negative_->forget(id);
      moved_drops_.push_back(std::move(e));
    }
  }
  held_ = screening.held;
  return held_.empty() ? step : withoutReadingsOf(step, held_);
}

std::vector<Eviction> BudgetManager::runScheduled(Backend& backend, StepIndex step, bool final) {
  std::vector<Eviction> out;
  if (!scheduler_) return out;
  ScheduleContext sctx{backend, step, final, {}};
  // Look-ahead copy: the application's factory, else the backend's own deep copy (clone(), null
  // when the backend has none; the reducer then falls back, see ActiveMinimization.h).
  if (scratch_factory_)
    sctx.scratch = [this, &backend] { return scratch_factory_(backend); };
  else
    sctx.scratch = [&backend] { return backend.clone(); };
  const ScheduledDrops plan = scheduler_->scheduled(sctx);
  if (plan.drops.empty() && !plan.marginalize_poses) return out;

  if (!plan.drops.empty() && before_drop_event_) before_drop_event_(backend, step);
  // The map as the shadows must see it before each drop. Removing a landmark leaves the others'
  // means alone in both backends, so without shadows (which also read covariances, and on the
  // graph each fresh landmarks() refactorizes) one view of the map serves the whole event.
  std::vector<LandmarkView> landmarks = backend.landmarks();
  for (const ReducerChoice& victim : plan.drops) {
    if (stopBetweenDrops(out)) return out;
    if (!shadows_.empty() && !out.empty()) landmarks = backend.landmarks();
    const auto it = std::find_if(landmarks.begin(), landmarks.end(),
                                 [&](const LandmarkView& l) { return l.id == victim.id; });
    if (it == landmarks.end())
      throw std::logic_error("reducer '" + active_->name() + "' scheduled landmark " +
                             std::to_string(victim.id) + ", not in the map");
    // The shadows see the same map and the candidates of a cap decision.
    bool all_protected = false;
    const auto candidates = dropCandidates(landmarks, step, options_, &all_protected);
    out.push_back(
        dropLandmark(backend, {backend, landmarks, candidates, step}, victim, plan.reason));
    if (shadows_.empty()) landmarks.erase(it);
  }
  if (plan.marginalize_poses)
    if (PoseHistoryBackend* h = poseHistory(&backend))
      poses_marginalized_ += h->marginalizePosesWithoutLandmarks(plan.keep_last_poses);
  return out;
}

std::vector<Eviction> BudgetManager::enforce(Backend& backend, StepIndex step) {
  return enforceAt(backend, step, nullptr);
}

std::vector<Eviction> BudgetManager::enforce(Backend& backend, const Step& step) {
  return enforceAt(backend, step.index, &step);
}

std::vector<Eviction> BudgetManager::enforce(Backend& backend, const Step& processed,
                                             const Step& raw) {
  return enforceAt(backend, processed.index, &processed, &raw);
}

std::vector<Eviction> BudgetManager::enforceAt(Backend& backend, StepIndex step,
                                               const Step* processed, const Step* raw) {
  last_step_ = step;
  std::vector<Eviction> out = std::move(moved_drops_);
  moved_drops_.clear();
  if (!active_) return out;
  tellObservations(backend, step, processed, raw);
  for (auto& e : weighNegativeEvidence(backend, step, processed)) out.push_back(std::move(e));
  for (auto& e : runScheduled(backend, step, false)) out.push_back(std::move(e));
  const bool compete = options_.admission == BudgetOptions::Admission::Compete;
  bool event_started = false;
  std::vector<LandmarkId> newcomers;  // compete: those that entered at this step
  // The cap holds in every mode: after the reducer's own scheduled drops, the cap-mode rule.
  while (options_.max_landmarks && backend.landmarkCount() > *options_.max_landmarks) {
    if (stopBetweenDrops(out)) break;
    if (!event_started && before_drop_event_) before_drop_event_(backend, step);

    const auto landmarks = backend.landmarks();
    if (compete && !event_started)
      for (const auto& l : landmarks)
        if (l.first_step == step) newcomers.push_back(l.id);
    event_started = true;
    // Over the cap, a distrusted landmark goes before the reducer is asked (negative evidence).
    if (negative_) {
      const auto distrusted = negative_->distrusted();
      if (!distrusted.empty()) {
        out.push_back(dropDistrusted(backend, landmarks, distrusted.front(), step));
        continue;
      }
    }
    bool all_protected = false;
    const auto candidates = dropCandidates(landmarks, step, options_, &all_protected);
    const DropContext ctx{backend, landmarks, candidates, step};

    const ReducerChoice victim = active_->choose(ctx);
    if (std::none_of(candidates.begin(), candidates.end(),
                     [&](std::size_t i) { return landmarks[i].id == victim.id; }))
      throw std::logic_error("reducer '" + active_->name() + "' chose landmark " +
                             std::to_string(victim.id) + ", not a candidate");

    const bool refused =
        std::find(newcomers.begin(), newcomers.end(), victim.id) != newcomers.end();
    out.push_back(dropLandmark(backend, ctx, victim,
                               refused         ? "refused"
                               : all_protected ? "over_cap_all_protected"
                                               : "over_cap"));
    if (refused) {
      refusals_.refused(victim.id, step);
      newcomers.erase(std::find(newcomers.begin(), newcomers.end(), victim.id));
    }
  }
  // The newcomers still in the map won their place: their past refusals no longer count.
  for (const LandmarkId id : newcomers) refusals_.admitted(id);
  return out;
}

std::vector<Eviction> BudgetManager::finish(Backend& backend, StepIndex last_step) {
  if (!active_) return {};
  return runScheduled(backend, last_step, true);
}

std::vector<Agreement> BudgetManager::agreements() const { return agreements_; }

namespace {

/// Section `negative_evidence`: every kept landmark's confirmation record (docs/ALGORITHMS.md
/// "Negative evidence"), one entry a landmark in id order; the viewpoint cells of all landmarks
/// one after another, `viewpoint_counts` saying how many are whose.
void saveNegativeEvidence(const NegativeEvidence& ne, session::SessionSection& s) {
  std::vector<std::int64_t> ids, confirmed, misses, in_pass, counted, unseen, counts, cells;
  for (const auto& [id, r] : ne.records()) {
    ids.push_back(id);
    confirmed.push_back(static_cast<std::int64_t>(r.last_confirmed_step));
    misses.push_back(r.misses);
    in_pass.push_back(r.in_pass ? 1 : 0);
    counted.push_back(r.counted ? 1 : 0);
    unseen.push_back(r.pass_unseen);
    counts.push_back(static_cast<std::int64_t>(r.viewpoints.size()));
    cells.insert(cells.end(), r.viewpoints.begin(), r.viewpoints.end());
  }
  s.putIntegers("ids", std::move(ids));
  s.putIntegers("last_confirmed_step", std::move(confirmed));
  s.putIntegers("misses", std::move(misses));
  s.putIntegers("in_pass", std::move(in_pass));
  s.putIntegers("counted", std::move(counted));
  s.putIntegers("pass_unseen", std::move(unseen));
  s.putIntegers("viewpoint_counts", std::move(counts));
  s.putIntegers("viewpoints", std::move(cells));
}

void restoreNegativeEvidence(const session::SessionSection& s, NegativeEvidence& ne) {
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  constexpr std::int64_t kMax32 = std::numeric_limits<std::uint32_t>::max();
  const auto& ids = s.integers("ids");
  const std::size_t n = ids.size();
  const auto& confirmed = s.integers("last_confirmed_step", n, 0, kMax);
  const auto& misses = s.integers("misses", n, 0, kMax32);
  const auto& in_pass = s.integers("in_pass", n, 0, 1);
  const auto& counted = s.integers("counted", n, 0, 1);
  const auto& unseen = s.integers("pass_unseen", n, 0, kMax32);
  const auto max_cells = static_cast<std::int64_t>(ne.settings().max_viewpoints);
  const auto& counts = s.integers("viewpoint_counts", n, 0, max_cells);
  std::size_t total = 0;
  for (const auto c : counts) total += static_cast<std::size_t>(c);
  const auto& cells =
      s.integers("viewpoints", total, std::numeric_limits<std::int64_t>::min(), kMax);
  std::map<LandmarkId, ConfirmationRecord> records;
  std::size_t next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (ids[i] < 0) s.fail("ids", "negative landmark id " + std::to_string(ids[i]));
    if (i > 0 && ids[i] <= ids[i - 1]) s.fail("ids", "not in increasing order");
    ConfirmationRecord r;
    r.last_confirmed_step = static_cast<StepIndex>(confirmed[i]);
    r.misses = static_cast<std::uint32_t>(misses[i]);
    r.in_pass = in_pass[i] == 1;
    r.counted = counted[i] == 1;
    r.pass_unseen = static_cast<std::uint32_t>(unseen[i]);
    const auto c = static_cast<std::size_t>(counts[i]);
    r.viewpoints.assign(cells.begin() + static_cast<std::ptrdiff_t>(next),
                        cells.begin() + static_cast<std::ptrdiff_t>(next + c));
    if (!std::is_sorted(r.viewpoints.begin(), r.viewpoints.end()))
      s.fail("viewpoints", "cells of landmark " + std::to_string(ids[i]) + " not sorted");
    next += c;
    records.emplace(ids[i], std::move(r));
  }
  ne.restore(std::move(records));
}

/// Section `moved_landmarks`: the step of the backend's latest pose and every suspect landmark's
/// evidence (docs/ALGORITHMS.md "Moved landmarks"), one entry a landmark in id order; the pieces
/// of all landmarks one after another, `evidence_counts` saying how many are whose.
void saveMoved(const MovedLandmarks& moved, const std::optional<StepIndex>& last_step,
               session::SessionSection& s) {
  std::vector<std::int64_t> ids, counts, steps;
  std::vector<double> robot, point, cov, nis;
  for (const auto& [id, evidence] : moved.suspects()) {
    ids.push_back(id);
    counts.push_back(static_cast<std::int64_t>(evidence.size()));
    for (const MovedEvidence& e : evidence) {
      steps.push_back(static_cast<std::int64_t>(e.step));
      robot.insert(robot.end(), {e.robot.x(), e.robot.y()});
      point.insert(point.end(), {e.point.x(), e.point.y()});
      cov.insert(cov.end(), {e.point_cov(0, 0), e.point_cov(0, 1), e.point_cov(1, 1)});
      nis.push_back(e.nis);
    }
  }
  s.putInteger("last_step", last_step ? static_cast<std::int64_t>(*last_step) : -1);
  s.putIntegers("ids", std::move(ids));
  s.putIntegers("evidence_counts", std::move(counts));
  s.putIntegers("steps", std::move(steps));
  s.putReals("robot_xy", std::move(robot));
  s.putReals("point_xy", std::move(point));
  s.putReals("point_cov", std::move(cov));
  s.putReals("nis", std::move(nis));
}

void restoreMoved(const session::SessionSection& s, MovedLandmarks& moved,
                  std::optional<StepIndex>& last_step) {
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  const std::int64_t last = s.integer("last_step", -1, kMax);
  last_step.reset();
  if (last >= 0) last_step = static_cast<StepIndex>(last);
  const auto& ids = s.integers("ids");
  const std::size_t n = ids.size();
  if (n > moved.settings().max_suspects)
    s.fail("ids", std::to_string(n) + " suspects, more than " +
                      std::to_string(moved.settings().max_suspects));
  const auto max_pieces = static_cast<std::int64_t>(moved.settings().readings);
  const auto& counts = s.integers("evidence_counts", n, 1, max_pieces);
  std::size_t total = 0;
  for (const auto c : counts) total += static_cast<std::size_t>(c);
  const auto& steps = s.integers("steps", total, 0, kMax);
  const auto& robot = s.reals("robot_xy", 2 * total);
  const auto& point = s.reals("point_xy", 2 * total);
  const auto& cov = s.reals("point_cov", 3 * total);
  const auto& nis = s.reals("nis", total);
  std::map<LandmarkId, std::vector<MovedEvidence>> suspects;
  std::size_t next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (ids[i] < 0) s.fail("ids", "negative landmark id " + std::to_string(ids[i]));
    if (i > 0 && ids[i] <= ids[i - 1]) s.fail("ids", "not in increasing order");
    std::vector<MovedEvidence> evidence;
    for (std::int64_t k = 0; k < counts[i]; ++k, ++next) {
      MovedEvidence e;
      e.step = static_cast<StepIndex>(steps[next]);
      e.robot = Eigen::Vector2d(robot[2 * next], robot[2 * next + 1]);
      e.point = Eigen::Vector2d(point[2 * next], point[2 * next + 1]);
      e.point_cov << cov[3 * next], cov[3 * next + 1], cov[3 * next + 1], cov[3 * next + 2];
      e.nis = nis[next];
      if (!(e.point_cov(0, 0) > 0 && e.point_cov.determinant() > 0))
        s.fail("point_cov", "not positive definite for landmark " + std::to_string(ids[i]));
      evidence.push_back(e);
    }
    suspects.emplace(ids[i], std::move(evidence));
  }
  moved.restore(std::move(suspects));
}

}  // namespace

void BudgetManager::saveSession(session::SessionState& state) const {
  session::SessionSection& b = state.section("budget");
  b.putIntegers("evicted_ids", std::vector<std::int64_t>(evicted_.begin(), evicted_.end()));
  b.putInteger("poses_marginalized", static_cast<std::int64_t>(poses_marginalized_));
  const auto records = refusals_.records();  // oldest first
  std::vector<std::int64_t> ids, at, retry, count;
  for (const auto& r : records) {
    ids.push_back(r.id);
    at.push_back(static_cast<std::int64_t>(r.refused_at));
    retry.push_back(static_cast<std::int64_t>(r.retry_at));
    count.push_back(r.refusals);
  }
  b.putIntegers("refused_ids", std::move(ids));
  b.putIntegers("refused_at", std::move(at));
  b.putIntegers("retry_at", std::move(retry));
  b.putIntegers("refusals", std::move(count));
  if (negative_) saveNegativeEvidence(*negative_, state.section("negative_evidence"));
  if (moved_) saveMoved(*moved_, last_step_, state.section("moved_landmarks"));
  // One section a reducer name: a shadow of the active reducer's own name sees the same steps
  // and decisions, so its memory is the active one's (mi's schedule runs only when active).
  std::set<std::string> saved;
  if (const auto* o = session::sessionOwner(active_.get())) {
    o->saveSession(state);
    saved.insert(active_->name());
  }
  for (const auto& s : shadows_)
    if (const auto* o = session::sessionOwner(s.get()))
      if (saved.insert(s->name()).second) o->saveSession(state);
}

void BudgetManager::restoreSession(const session::SessionState& state) {
  const session::SessionSection& b = state.take("budget");
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  // A map over the cap the state was saved under is not one a run wrote (every step ends within
  // the cap; a resumed run has the saved cap, resumeMismatches): its first step would have to
  // drop the excess one by one.
  if (active_ && options_.max_landmarks && state.map.landmarks.size() > *options_.max_landmarks)
    throw InputError(session::stateLabel(state.source) +
                     ": section 'landmarks': " + std::to_string(state.map.landmarks.size()) +
                     " landmarks, more than the saved [LandmarkBudget] max_landmarks = " +
                     std::to_string(*options_.max_landmarks));
  const auto& evicted = b.integers("evicted_ids");
  evicted_.clear();
  for (const auto id : evicted) {
    if (id < 0) b.fail("evicted_ids", "negative landmark id " + std::to_string(id));
    evicted_.insert(id);
  }
  poses_marginalized_ = static_cast<std::size_t>(b.integer("poses_marginalized", 0));
  const auto& ids = b.integers("refused_ids");
  if (ids.size() > options_.refusal_memory)
    b.fail("refused_ids", std::to_string(ids.size()) +
                              " refusals, more than [LandmarkBudget] "
                              "refusal_memory = " +
                              std::to_string(options_.refusal_memory));
  const auto& at = b.integers("refused_at", ids.size(), 0, kMax);
  const auto& retry = b.integers("retry_at", ids.size(), 0, kMax);
  const auto& count = b.integers("refusals", ids.size(), 1, 1 << 30);
  std::vector<RefusalMemory::Record> records;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] < 0) b.fail("refused_ids", "negative landmark id " + std::to_string(ids[i]));
    if (i > 0 && at[i] < at[i - 1]) b.fail("refused_at", "not oldest first");
    records.push_back({ids[i], static_cast<StepIndex>(at[i]), static_cast<StepIndex>(retry[i]),
                       static_cast<std::uint32_t>(count[i])});
  }
  refusals_.restore(records);
  if (negative_)
    if (const auto* n = state.takeIfPresent("negative_evidence"))
      restoreNegativeEvidence(*n, *negative_);
  if (moved_)
    if (const auto* m = state.takeIfPresent("moved_landmarks"))
      restoreMoved(*m, *moved_, last_step_);
  if (auto* o = session::sessionOwner(active_.get())) o->restoreSession(state);
  for (const auto& s : shadows_)
    if (auto* o = session::sessionOwner(s.get())) o->restoreSession(state);  // saved once a name
}

}  // namespace budget_slam::reducers
