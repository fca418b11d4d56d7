#include "Pipeline.h"

#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <iomanip>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "BuiltinBackends.h"
#include "MappingOptions.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/StepFilter.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/report/FileWrite.h"
#include "budget_slam/report/MapScene.h"
#include "budget_slam/report/Pictures.h"
#include "budget_slam/report/RunFiles.h"

namespace budget_slam::app {
namespace {

std::vector<std::unique_ptr<Reducer>> makeShadows(const mrpt::config::CConfigFileBase& ini,
                                                  const reducers::BudgetOptions& budget) {
  std::vector<std::unique_ptr<Reducer>> out;
  for (const auto& name : budget.shadow_reducers) {
    auto r = reducers::builtinReducers().create(name, ini, budget.seed);
    if (r) out.push_back(std::move(r));
  }
  return out;
}

/// CPU time of the calling thread [s]: per run even when compare runs several in one process,
/// and unaffected by other processes on a shared machine.
double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// map.png marks at most this many dropped landmarks (a lifelong run drops millions).
constexpr std::size_t kMaxDroppedMarks = 20000;
/// Without per-step history, the relocalization coverage follows at most this many evenly spread
/// steps (bounded memory on lifelong runs; docs/OUTPUTS.md).
constexpr std::size_t kMaxCoverageSteps = 4096;

std::size_t relocMinLandmarks(const mrpt::config::CConfigFileBase& ini) {
  metrics::MetricsOptions m;
  m.loadFromConfigFile(ini, metrics::MetricsOptions::kSection);
  return m.reloc_min_landmarks;
}

double nanIfEmpty(std::size_t n, double v) {
  return n ? v : std::numeric_limits<double>::quiet_NaN();
}

/// JSON has no NaN: write null instead.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

bool finite(const LandmarkView& l) {
  return l.mean.allFinite() && l.cov.allFinite() && l.obs_mean.allFinite();
}

/// A cell of evictions.csv's shadow_choices: `name:id:score` a shadow, `;`-separated; a shadow
/// that failed at this drop has empty id and score (`name::`).
std::string shadowChoices(const reducers::Eviction& e) {
  std::string out;
  for (const auto& [name, choice] : e.shadow) {
    out += (out.empty() ? "" : ";") + name + ":";
    if (choice.id != kNoLandmarkId)
      out += std::to_string(choice.id) + ":" +
             (std::isnan(choice.score) ? std::string() : report::formatDouble(choice.score));
    else
      out += ":";
  }
  return out;
}

/// A cell of evictions.csv's shadow_errors: `name: why` a failed shadow, `;`-separated (a `;`
/// inside a message reads as `,`).
std::string shadowErrors(const reducers::Eviction& e) {
  std::string out;
  for (auto [name, why] : e.shadow_errors) {
    std::replace(why.begin(), why.end(), ';', ',');
    out += (out.empty() ? "" : ";") + name + ": " + why;
  }
  return out;
}

}  // namespace

std::string shadowFailureLine(const reducers::ShadowFailures& f) {
  return "shadow reducer '" + f.shadow + "' failed at " + std::to_string(f.failures) +
         " drop decision" + (f.failures == 1 ? "" : "s") + " from step " +
         std::to_string(f.first_step) + " to " + std::to_string(f.last_step) +
         " (first: " + f.first_error + "); the active reducer's drops stand";
}

std::size_t peakResidentBytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<std::size_t>(u.ru_maxrss) * 1024;  // Linux reports KiB
}

std::size_t residentBytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return 0;
  return pages_resident * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

Pipeline::Pipeline(const mrpt::config::CConfigFileBase& ini, const std::string& backend,
                   const reducers::BudgetOptions& budget, report::OutputFolder folder,
                   std::shared_ptr<const dataset::GroundTruth> truth, bool keep_history)
    : folder_(std::move(folder)),
      backend_(builtinBackends().create(backend, ini, BackendSettings{keep_history})),
      manager_(std::make_unique<reducers::BudgetManager>(
          budget, reducers::builtinReducers().create(budget.reducer, ini, budget.seed),
          makeShadows(ini, budget))),
      truth_(std::move(truth)),
      steps_csv_(folder_.file("steps.csv"), report::stepsCsvColumns()),
      evictions_csv_(folder_.file("evictions.csv"), report::evictionsCsvColumns()),
      keep_history_(keep_history),
      reloc_(relocMinLandmarks(ini), keep_history ? 0 : kMaxCoverageSteps) {
  if (truth_ && !truth_->path.empty()) truth_frame_ = metrics::toEstimateFrame(*truth_);
  // map.png colours the kept landmarks by the coverage clusters ([CoverageReducer], run's seed).
  coverage_.seed = budget.seed;
  coverage_.loadFromConfigFile(ini, reducers::CoverageOptions::kSection);
  MappingOptions mapping;
  mapping.loadFromConfigFile(ini, MappingOptions::kSection);
  save_3d_scene_ = mapping.save_3d_scene;
  scene_every_steps_ = mapping.scene_every_steps;
  if (budget.dump_states)
    manager_->setBeforeDropEvent([this](const Backend& b, StepIndex step) { dumpState(b, step); });
}

void Pipeline::process(const Step& raw) {
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = threadCpuSeconds();
  // Without the readings of landmarks dropped for good and of refused newcomers still waiting.
  const Step filtered = manager_->admissible(raw);

  const std::size_t before = backend_->landmarkCount();
  backend_->process(filtered);
  // The landmarks the step's readings went to are in the map now (new ones included).
  const std::vector<LandmarkId> assoc = backend_->lastAssociation();
  for (const LandmarkId id : assoc) reloc_.landmarkAdded(id);
  const std::size_t added = backend_->landmarkCount() - before;
  const auto diverged = [](const PoseEstimate& p) {
    return !std::isfinite(p.mean.x) || !std::isfinite(p.mean.y) || !std::isfinite(p.mean.phi) ||
           !p.cov.allFinite();
  };
  if (diverged(backend_->robotPose()))
    throw Error("step " + std::to_string(raw.index) + ": the " + backend_->name() +
                " estimate diverged (the robot pose or its covariance is not finite)");
  const auto drops = manager_->enforce(*backend_, filtered);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = threadCpuSeconds() - cpu0;
  // The coverage over time counts the map as it stands after this step's drops.
  for (const auto& e : drops) reloc_.landmarkRemoved(e.id);
  const std::size_t reloc_landmarks = trackCoverage(raw, filtered, assoc);
  const std::size_t n = backend_->landmarkCount();
  const PoseEstimate pose = backend_->robotPose();

  // The row first: a step whose row cannot be written (a full disk) does not count, so that
  // steps.csv, trajectory.tum and summary.json agree on the steps done.
  steps_csv_.cell(raw.index)
      .cell(raw.t)
      .cell(n)
      .cell(added)
      .cell(drops.size())
      .cell(backend_->poseCount())
      .cell(pose.mean.x)
      .cell(pose.mean.y)
      .cell(pose.mean.phi)
      .cell(pose.cov(0, 0))
      .cell(pose.cov(1, 1))
      .cell(pose.cov(2, 2))
      .cell(1e3 * dt)
      .cell(1e3 * cpu)
      .cell(residentBytes())
      .cell(reloc_landmarks)
      .cell(reloc_.coverageSoFarPct());
  steps_csv_.endRow();

  ++steps_done_;
  last_step_ = raw.index;
  landmarks_added_ += added;
  total_step_s_ += dt;
  max_step_s_ = std::max(max_step_s_, dt);
  peak_landmarks_ = std::max(peak_landmarks_, n);
  if (keep_history_) counts_.push_back(n);
  if (keep_history_) online_.push_back({raw.index, pose});
  if (truth_frame_)
    for (int offset : {0, 1}) {
      const std::size_t row = raw.index + offset;
      if (row >= truth_frame_->path.size()) continue;
      const double nees = metrics::poseNees(pose, truth_frame_->path[row]);
      if (!std::isfinite(nees)) continue;  // e.g. the zero covariance before the first motion
      nees_sum_[offset] += nees;
      ++nees_n_[offset];
    }

  logEvictions(drops);
  if (scene_every_steps_ && raw.index % scene_every_steps_ == 0) {
    char name[48];
    std::snprintf(name, sizeof name, "kf_state_%05llu.3Dscene",
                  static_cast<unsigned long long>(raw.index));
    writeScene(name, mapContent(backend_->trajectory(), backend_->landmarks(), nullptr));
  }
}

std::size_t Pipeline::trackCoverage(const Step& raw, const Step& filtered,
                                    const std::vector<LandmarkId>& assoc) {
  // A reading with a sensor ID observes that landmark (whether the map holds it or not); one
  // without is known only through the backend's association.
  std::vector<LandmarkId> observed;
  if (raw.scan)
    for (const auto& r : raw.scan->readings)
      if (r.id != kNoLandmarkId) observed.push_back(r.id), saw_ids_ = true;
  if (filtered.scan)
    for (std::size_t r = 0; r < filtered.scan->readings.size(); ++r)
      if (filtered.scan->readings[r].id == kNoLandmarkId) {
        saw_idless_ = true;
        if (r < assoc.size()) observed.push_back(assoc[r]);
      }
  return reloc_.addStep(raw.index, observed);
}

Pipeline::FinalCoverage Pipeline::finalCoverage() const {
  FinalCoverage c;
  std::unordered_set<LandmarkId> ids;
  for (const auto& l : backend_->landmarks()) ids.insert(l.id);
  c.steps = reloc_.steps();
  c.coverage = metrics::coverageOf(
      c.steps, [&](LandmarkId id) { return ids.count(id) > 0; }, reloc_.minLandmarks(),
      reloc_.sampled());
  c.source = saw_idless_ ? (saw_ids_ ? "landmark_ids_and_own_association" : "own_association")
                         : "landmark_ids";
  return c;
}

void Pipeline::logEvictions(const std::vector<reducers::Eviction>& drops) {
  for (const auto& e : drops) {
    // A refused newcomer never held a place between steps: counted apart from the drops.
    const bool refused = e.reason == "refused";
    ++(refused ? refused_ : evictions_);
    if (!refused && dropped_.size() < kMaxDroppedMarks) dropped_.push_back(e.mean);
    evictions_csv_.cell(e.step)
        .cell(static_cast<long long>(e.id))
        .cell(e.reducer)
        .cell(e.score)
        .cell(e.n_before)
        .cell(e.n_after)
        .cell(e.reason)
        .cell(shadowChoices(e))
        .cell(shadowErrors(e));
    evictions_csv_.endRow();
  }
}

report::MapContent Pipeline::mapContent(const std::vector<TrajectoryPoint>& trajectory,
                                        const std::vector<LandmarkView>& landmarks,
                                        const FinalCoverage* coverage) const {
  report::MapContent map;
  const auto& budget = manager_->options();
  map.title = backend_->name() + ", reducer " + budget.reducer +
              (manager_->capped() ? ", cap " + std::to_string(*budget.max_landmarks) : "") + ": " +
              std::to_string(landmarks.size()) + " landmarks kept, " + std::to_string(evictions_) +
              " dropped";
  for (const auto& p : trajectory) map.trajectory.push_back(p.pose);
  map.kept = landmarks;
  std::vector<Eigen::Vector2d> obs_means;
  for (const auto& l : landmarks) obs_means.push_back(l.obs_mean);
  for (const std::size_t c :
       reducers::KMeans::cluster(obs_means, coverage_.kmeans(obs_means.size())).label)
    map.cluster_of_kept.push_back(static_cast<int>(c));
  map.dropped = dropped_;
  // The path coloured by the final map's landmarks in view, when every pose's step is known.
  if (coverage) {
    std::unordered_map<StepIndex, std::size_t> in_view;
    for (const auto& st : coverage->steps) in_view[st.step] = st.in_map;
    map.min_landmarks = coverage->coverage.min_landmarks;
    for (const auto& p : trajectory) {
      const auto it = in_view.find(p.step);
      if (it == in_view.end()) {
        map.trajectory_landmarks.clear();
        break;
      }
      map.trajectory_landmarks.push_back(it->second);
    }
  }
  if (truth_ && !truth_->empty()) {
    const auto gt = metrics::toEstimateFrame(*truth_);
    map.ground_truth_path = gt.path;
    for (const auto& [id, l] : gt.landmarks) map.ground_truth_landmarks.push_back(l);
  }
  return map;
}

void Pipeline::writeScene(const std::string& name, const report::MapContent& map) const {
  report::writeMapScene(folder_.file(name), map, backend_->robotPose().mean);
}

void Pipeline::writeGroundTruthTum(const std::vector<TrajectoryPoint>& trajectory,
                                   std::size_t steps_in_rawlog) const {
  // The ground truth of every pose in trajectory.tum, same timestamps, in the estimate's frame:
  // `evo_ape tum ground_truth.tum trajectory.tum` compares them.
  const auto gt = metrics::toEstimateFrame(*truth_);
  std::vector<TrajectoryPoint> rows;
  for (const auto& p : trajectory) {
    const std::size_t row = metrics::groundTruthRow(p.step, gt.path.size(), steps_in_rawlog);
    if (row < gt.path.size()) rows.push_back({p.step, p.t, gt.path[row]});
  }
  report::writeTrajectoryTum(folder_.file("ground_truth.tum"), rows);
}

void Pipeline::dumpState(const Backend& backend, StepIndex step) const {
  // Full mean and covariance, robot pose first then landmarks in the backend's order, so that
  // any reducer's score can be recomputed by hand.
  const auto lms = backend.landmarks();
  std::vector<VariableKey> vars = {VariableKey::pose(step)};
  for (const auto& l : lms) vars.push_back(VariableKey::landmark(l.id));
  const Eigen::MatrixXd P = backend.jointCovariance(vars);
  const PoseEstimate pose = backend.robotPose();

  std::ostringstream out;
  out << std::setprecision(17);
  out << "# state before the drop event after step " << step << " (backend " << backend.name()
      << ")\n# order: robot x y yaw, then x y of each landmark below\n# ids:";
  for (const auto& l : lms) out << ' ' << l.id;
  out << "\n# mean\n" << pose.mean.x << ' ' << pose.mean.y << ' ' << pose.mean.phi;
  for (const auto& l : lms) out << ' ' << l.mean.x() << ' ' << l.mean.y();
  out << "\n# covariance\n";
  for (Eigen::Index r = 0; r < P.rows(); ++r) {
    for (Eigen::Index c = 0; c < P.cols(); ++c) out << (c ? " " : "") << P(r, c);
    out << '\n';
  }
  report::writeFileAtomically(folder_.file("states/step_" + std::to_string(step) + ".txt"),
                              out.str());
}

void Pipeline::complete() {
  if (completed_) return;
  completed_ = true;
  // The reducer's end-of-run event (mi objective mode: Choudhary et al.'s active minimization),
  // then the backend's (the graph's solve to the batch optimum).
  if (steps_done_ > 0) {
    const auto drops = manager_->finish(*backend_, last_step_);
    for (const auto& e : drops) reloc_.landmarkRemoved(e.id);
    logEvictions(drops);
  }
  Cancellation::check();  // drops cut short by a stop request are logged above
  backend_->finish();
}

nlohmann::json Pipeline::finish(const std::string& status, const std::string& error,
                                std::size_t steps_in_rawlog, const nlohmann::json& extra) {
  if (status == "ok") {
    complete();
    Cancellation::check();  // a stop request before the outputs: the run ends as interrupted
  }
  // What the outputs may hold: the poses of the steps that completed, and finite estimates only
  // (a diverged filter's NaN reaches no picture, metric, k-means or file).
  const auto finitePose = [](const mrpt::math::TPose2D& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.phi);
  };
  std::vector<TrajectoryPoint> trajectory;
  std::size_t poses_not_finite = 0;
  for (const auto& p : backend_->trajectory()) {
    if (steps_done_ == 0 || p.step > last_step_) continue;  // a step cut short
    if (!finitePose(p.pose) || !std::isfinite(p.t))
      ++poses_not_finite;
    else
      trajectory.push_back(p);
  }
  std::vector<LandmarkView> landmarks;
  std::size_t landmarks_not_finite = 0;
  for (const auto& l : backend_->landmarks()) {
    if (finite(l))
      landmarks.push_back(l);
    else
      ++landmarks_not_finite;
  }

  // Every output is attempted; the first failure (a full disk) is the run's error.
  std::vector<std::string> not_written;
  std::string first_error;
  const auto attempt = [&](const std::string& name, const std::function<void()>& write) {
    try {
      write();
    } catch (const std::exception& e) {
      not_written.push_back(name);
      if (first_error.empty()) first_error = exceptionLine(e);
    }
  };
  attempt("steps.csv", [&] { steps_csv_.close(); });
  attempt("evictions.csv", [&] { evictions_csv_.close(); });
  attempt("trajectory.tum",
          [&] { report::writeTrajectoryTum(folder_.file("trajectory.tum"), trajectory); });
  attempt("landmarks.csv",
          [&] { report::writeLandmarksCsv(folder_.file("landmarks.csv"), landmarks); });
  const FinalCoverage coverage = final_coverage_ ? *final_coverage_ : finalCoverage();
  // One map content (its k-means included) for both pictures of the final map.
  std::optional<report::MapContent> map;
  const auto finalMap = [&]() -> const report::MapContent& {
    if (!map) map = mapContent(trajectory, landmarks, &coverage);
    return *map;
  };
  attempt("map.png", [&] { report::writeMapPng(folder_.file("map.png"), finalMap()); });
  if (save_3d_scene_) attempt("map.3Dscene", [&] { writeScene("map.3Dscene", finalMap()); });
  if (truth_ && !truth_->path.empty())
    attempt("ground_truth.tum", [&] { writeGroundTruthTum(trajectory, steps_in_rawlog); });

  std::string st = status, why = error;
  if (st == "ok" && (poses_not_finite || landmarks_not_finite)) {
    st = "failed";
    why = "the " + backend_->name() + " estimate is not finite at the end of the run (" +
          std::to_string(poses_not_finite) + " poses, " + std::to_string(landmarks_not_finite) +
          " landmarks)";
  }
  if (st == "ok" && !first_error.empty()) st = "failed", why = first_error;

  const auto& budget = manager_->options();
  nlohmann::json j;
  j["status"] = st;
  j["error"] = why;
  if (!not_written.empty()) j["files_not_written"] = not_written;
  j["backend"] = backend_->name();
  j["reducer"] = budget.reducer;
  j["cap"] = manager_->capped() ? nlohmann::json(*budget.max_landmarks) : nlohmann::json();
  j["counts"] = {{"steps", steps_done_},
                 {"landmarks_final", landmarks.size()},
                 {"landmarks_not_finite", landmarks_not_finite},
                 {"poses_not_finite", poses_not_finite},
                 {"landmarks_peak", peak_landmarks_},
                 {"landmarks_added", landmarks_added_},
                 {"evictions", evictions_},
                 {"refused", refused_},
                 {"poses_kept", backend_->poseCount()},
                 {"poses_marginalized", manager_->posesMarginalized()}};
  j["timings"] = {
      {"steps_s", total_step_s_},
      {"step_ms_mean", number(nanIfEmpty(steps_done_, 1e3 * total_step_s_ /
                                                          std::max<std::size_t>(1, steps_done_)))},
      {"step_ms_max", 1e3 * max_step_s_},
      {"peak_rss_bytes", peakResidentBytes()}};
  nlohmann::json agreement = nlohmann::json::array();
  for (const auto& a : manager_->agreements())
    agreement.push_back({{"a", a.a},
                         {"b", a.b},
                         {"agree", a.agree},
                         {"total", a.total},
                         {"rate", number(a.total ? a.rate() : NAN)}});
  j["agreement"] = agreement;
  nlohmann::json shadow_failures = nlohmann::json::array();
  for (const auto& f : manager_->shadowFailures())
    shadow_failures.push_back({{"shadow", f.shadow},
                               {"failures", f.failures},
                               {"first_step", f.first_step},
                               {"last_step", f.last_step},
                               {"first_error", f.first_error}});
  j["shadow_failures"] = shadow_failures;

  if (truth_ && !truth_->empty()) {
    metrics::GroundTruthErrors e;
    try {
      e = metrics::groundTruthErrors(trajectory, {}, landmarks, *truth_, steps_in_rawlog);
    } catch (const Error& x) {
      if (first_error.empty()) first_error = x.what();  // a bug: inputs are finite here
    }
    const int offset =
        truth_->path.empty()
            ? 1
            : static_cast<int>(metrics::groundTruthRow(0, truth_->path.size(), steps_in_rawlog));
    const double nees_mean = nees_n_[offset] ? nees_sum_[offset] / nees_n_[offset] : NAN;
    j["ground_truth"] = {{"landmarks_file", truth_->landmarks_file},
                         {"path_file", truth_->path_file},
                         {"poses", e.poses},
                         {"trajectory_rmse_m", number(e.trajectory_rmse)},
                         {"trajectory_max_m", number(e.trajectory_max)},
                         {"trajectory_rmse_aligned_m", number(e.trajectory_rmse_aligned)},
                         {"alignment_rotation_deg", number(e.alignment_rotation_deg)},
                         {"landmark_rmse_aligned_m", number(e.landmark_rmse_aligned)},
                         {"landmarks", e.landmarks},
                         {"landmark_rmse_m", number(e.landmark_rmse)},
                         {"nees_mean", number(nees_mean)},
                         {"nees_samples", nees_n_[offset]}};
    // Where the ground truth's frame sits in the map's (budget-slam localize starts another
    // traversal's robot there; docs/OUTPUTS.md).
    alignment_ = metrics::mapAlignment(landmarks, trajectory, *truth_, steps_in_rawlog);
    if (alignment_)
      j["ground_truth"]["map_alignment"] = {{"x", alignment_->transform.t.x()},
                                            {"y", alignment_->transform.t.y()},
                                            {"yaw", alignment_->yaw()},
                                            {"source", alignment_->source},
                                            {"points", alignment_->points}};
  }
  {
    const auto& c = coverage.coverage;
    nlohmann::json r = {{"min_landmarks", c.min_landmarks},
                        {"coverage_pct", number(c.coverage_pct)},
                        {"mean_landmarks", number(c.mean_landmarks)},
                        {"steps", c.steps},
                        {"steps_covered", c.steps_covered},
                        {"sampled", c.sampled},
                        {"source", coverage.source}};
    for (const auto& [k, v] : coverage.details.items()) r[k] = v;
    j["relocalization"] = r;
  }
  for (const auto& [k, v] : extra.items()) j[k] = v;
  try {
    report::writeJson(folder_.file("summary.json"), j);
  } catch (const std::exception& e) {
    summary_error_ = exceptionLine(e);
    if (first_error.empty()) first_error = summary_error_;
  }
  write_error_ = first_error;
  return j;
}

}  // namespace budget_slam::app
