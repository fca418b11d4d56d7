// Sessions in one world that changes between them (budget-simulate --sessions N --change F).
#include "budget_slam/dataset/Sessions.h"

#include <sys/stat.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

#include "Random.h"
#include "Scenario.h"
#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/dataset/DatasetFiles.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/dataset/RawlogWriter.h"
#include "budget_slam/dataset/SidecarIni.h"

namespace budget_slam::dataset {
namespace {

constexpr const char* kChangesHeader = "session,change,id,x_before,y_before,x_after,y_after";
constexpr const char* kMark = "# Made by budget-simulate";
/// The largest share of --change-split (SessionChangeOptions::table()'s bound).
constexpr double kMaxShare = 1e9;

bool exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

std::string firstLine(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::getline(in, line);
  return line;
}

/// True when the sidecar at `ini` is one budget-simulate wrote (its mark among the comment lines
/// at the top).
bool simulatorSidecar(const std::string& ini) {
  std::ifstream in(ini, std::ios::binary);
  std::string line;
  for (int i = 0; i < 8 && std::getline(in, line); ++i)
    if (line.rfind(kMark, 0) == 0) return true;
  return false;
}

std::string stemOf(const std::string& rawlog) {
  return rawlog.substr(0, rawlog.size() - std::string(".rawlog").size());
}

/// Coordinates: micrometres, as the ground-truth files hold them.
std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6f", v);
  return b;
}

/// Values in messages and notes.
std::string shortNum(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

/// Counts for the three kinds by largest remainder (ties: disappear, move, appear).
std::array<std::size_t, 3> splitCounts(std::size_t n, const SessionChangeOptions& o) {
  const std::array<double, 3> share = {o.share_disappear, o.share_move, o.share_appear};
  const double sum = share[0] + share[1] + share[2];
  std::array<std::size_t, 3> count{};
  std::array<double, 3> rest{};
  std::size_t given = 0;
  for (int k = 0; k < 3; ++k) {
    const double exact = n * share[k] / sum;
    count[k] = static_cast<std::size_t>(std::floor(exact));
    rest[k] = exact - count[k];
    given += count[k];
  }
  while (given < n) {
    int best = 0;
    for (int k = 1; k < 3; ++k)
      if (rest[k] > rest[best]) best = k;
    count[best]++, rest[best] = -1, given++;
  }
  return count;
}

/// Applies the changes before sessions 2..N to `world` (lap fields count sessions from 0).
std::vector<LandmarkChange> changeWorld(sim::World& world, const SimulationOptions& options,
                                        const SessionChangeOptions& o) {
  sim::Random rng(options.seed * 0xD1B54A32D192ED03ULL + 77);
  std::vector<LandmarkChange> changes;
  LandmarkId next_id = 0;
  for (const auto& l : world.landmarks) next_id = std::max(next_id, l.id + 1);
  for (int s = 1; s < o.sessions; ++s) {  // epoch s = session s + 1
    std::vector<std::size_t> alive;
    for (std::size_t i = 0; i < world.landmarks.size(); ++i)
      if (world.landmarks[i].first_lap <= s - 1 && world.landmarks[i].last_lap >= s - 1)
        alive.push_back(i);
    const auto n =
        std::min(alive.size(), static_cast<std::size_t>(std::lround(o.change * alive.size())));
    const auto count = splitCounts(n, o);
    // Partial Fisher-Yates: distinct victims for the disappearing and moving ones.
    const std::size_t victims = std::min(alive.size(), count[0] + count[1]);
    for (std::size_t k = 0; k < victims; ++k) {
      const std::size_t j = k + static_cast<std::size_t>(rng.uniform() * (alive.size() - k));
      std::swap(alive[k], alive[j]);
    }
    // move_distance away in a random direction; a landmark seen only from its room stays in it
    // (up to 16 directions tried, then the last one).
    const auto away = [&](const Eigen::Vector2d& p, int region, LandmarkId id) {
      Eigen::Vector2d q = p;
      for (int tries = 0; tries < 16; ++tries) {
        const double a = rng.uniform(-M_PI, M_PI);
        q = sim::quantize(p + o.move_distance * Eigen::Vector2d(std::cos(a), std::sin(a)));
        if (region < 0 || world.regions[static_cast<std::size_t>(region)].contains(q)) break;
      }
      // The ground truth and the readings must stay where budget-slam reads them: refused before
      // any file is written.
      if (!(q.cwiseAbs().maxCoeff() <= limits::kMaxCoordinate))
        throw ConfigError("--move-distance " + shortNum(o.move_distance) + ": puts landmark " +
                          std::to_string(id) + " at (" + shortNum(q.x()) + ", " + shortNum(q.y()) +
                          ") m before session " + std::to_string(s + 1) + ", beyond the +-" +
                          shortNum(limits::kMaxCoordinate) + " m budget-slam reads");
      return q;
    };
    std::vector<sim::Landmark> added;
    for (std::size_t k = 0; k < victims; ++k) {
      sim::Landmark& l = world.landmarks[alive[k]];
      l.last_lap = s - 1;
      LandmarkChange c;
      c.session = s + 1;
      c.id = l.id;
      c.before = l.p;
      if (k < count[0]) {
        c.kind = LandmarkChange::Kind::Disappeared;
      } else {
        c.kind = LandmarkChange::Kind::Moved;
        sim::Landmark moved = l;
        moved.p = c.after = away(l.p, l.region, l.id);
        moved.first_lap = s;
        moved.last_lap = std::numeric_limits<int>::max();
        added.push_back(moved);
      }
      changes.push_back(c);
    }
    for (std::size_t k = 0; k < count[2] && !alive.empty(); ++k) {
      const auto& near =
          world.landmarks[alive[static_cast<std::size_t>(rng.uniform() * alive.size())]];
      sim::Landmark l;
      l.id = next_id++;
      l.p = away(near.p, near.region, l.id);
      l.region = near.region;
      l.first_lap = s;
      added.push_back(l);
      LandmarkChange c;
      c.session = s + 1;
      c.kind = LandmarkChange::Kind::Appeared;
      c.id = l.id;
      c.after = l.p;
      changes.push_back(c);
    }
    world.landmarks.insert(world.landmarks.end(), added.begin(), added.end());
  }
  return changes;
}

std::map<LandmarkId, Eigen::Vector2d> landmarksOfEpoch(const sim::World& world, int epoch) {
  std::map<LandmarkId, Eigen::Vector2d> out;
  for (const auto& l : world.landmarks)
    if (l.first_lap <= epoch && epoch <= l.last_lap) out[l.id] = l.p;
  return out;
}

std::string changesText(const std::vector<LandmarkChange>& changes) {
  std::string t = std::string(kChangesHeader) + "\n";
  for (const auto& c : changes) {
    const bool has_before = c.kind != LandmarkChange::Kind::Appeared;
    const bool has_after = c.kind != LandmarkChange::Kind::Disappeared;
    t += std::to_string(c.session) + ',' + LandmarkChange::name(c.kind) + ',' +
         std::to_string(c.id) + ',' + (has_before ? num(c.before.x()) : "") + ',' +
         (has_before ? num(c.before.y()) : "") + ',' + (has_after ? num(c.after.x()) : "") + ',' +
         (has_after ? num(c.after.y()) : "") + '\n';
  }
  return t;
}

/// What a series has put in place so far, undone when it does not finish (a stop request, a full
/// disk): a series is all or nothing, as one rawlog is (saveDatasetFiles).
class SeriesFiles {
 public:
  /// The dataset files of `rawlog`, now in place; `backups`: earlier files of ours it moved
  /// aside (`<name>.~N~`), put back by undo().
  void placed(const std::string& rawlog, const std::vector<std::string>& backups) {
    for (const auto& f : datasetFiles(rawlog))
      if (exists(f)) placed_.push_back(f);
    for (const auto& b : backups) backups_.push_back(b);
  }
  void commit() { placed_.clear(), backups_.clear(); }
  ~SeriesFiles() {
    std::error_code ec;
    for (const auto& f : placed_) std::filesystem::remove(f, ec);
    for (const auto& b : backups_) std::filesystem::rename(b, b.substr(0, b.rfind(".~")), ec);
  }

 private:
  std::vector<std::string> placed_, backups_;
};

/// Simulates `scenario` under `epochs` into `rawlog` with the ground-truth landmarks `truth`.
std::size_t writeOne(const SimulationOptions& options, const sim::Scenario& scenario,
                     const EpochSchedule& epochs, const std::string& rawlog,
                     const std::map<LandmarkId, Eigen::Vector2d>& truth,
                     const std::vector<std::string>& extra_notes, SeriesFiles& series) {
  Simulator sim(options, scenario, epochs);
  RawlogWriter writer(rawlog);
  sim.run([&](const Step& s) {
    Cancellation::check();
    writer.write(s);
  });
  GroundTruth session_truth;
  session_truth.landmarks = truth;
  session_truth.path = sim.groundTruth().path;
  std::vector<std::string> notes = sim.notes();
  notes.insert(notes.begin() + 1, extra_notes.begin(), extra_notes.end());
  // Every target was checked to be ours or free before the first session (checkNotForeign); one
  // of ours from an earlier series is kept as a numbered backup, never replaced.
  const std::size_t steps = writer.stepsWritten();
  series.placed(rawlog,
                saveDatasetFiles(writer, session_truth, sim.noise(), notes, /*force=*/true));
  return steps;
}

}  // namespace

const OptionTable<SessionChangeOptions>& SessionChangeOptions::table() {
  using O = SessionChangeOptions;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  static const OptionTable<O> t = {
      option::integer("sessions", &O::sessions, 1, kMaxSessions, "N"),
      option::real("change", &O::change, 0, 1, "share of the landmarks a session"),
      option::real("share_disappear", &O::share_disappear, 0, 1e9, "relative share"),
      option::real("share_move", &O::share_move, 0, 1e9, "relative share"),
      option::real("share_appear", &O::share_appear, 0, 1e9, "relative share"),
      option::real("move_distance", &O::move_distance, 1e-9, kInf, "[m]"),
      option::flag("joined", &O::joined),
  };
  return t;
}

const char* LandmarkChange::name(Kind k) {
  switch (k) {
    case Kind::Disappeared:
      return "disappeared";
    case Kind::Moved:
      return "moved";
    case Kind::Appeared:
      return "appeared";
  }
  return "?";
}

std::string sessionRawlogName(const std::string& rawlog, int session, int sessions) {
  const int width = std::max(2, static_cast<int>(std::to_string(sessions).size()));
  char k[16];
  std::snprintf(k, sizeof k, "%0*d", width, session);
  return stemOf(rawlog) + "_s" + k + ".rawlog";
}

std::string changesFileFor(const std::string& rawlog) { return stemOf(rawlog) + "_changes.csv"; }

void checkNotForeign(const std::string& rawlog) {
  const std::string ini = sidecarIniPathFor(rawlog);
  if (simulatorSidecar(ini)) return;
  for (const auto& f :
       {rawlog, groundTruthLandmarksPathFor(rawlog), groundTruthRobotPathFor(rawlog), ini})
    if (exists(f))
      throw InputError("'" + f +
                       "': exists and was not written by budget-simulate; not written over");
}

void checkNotForeign(const std::string& file, const std::string& first_line) {
  if (exists(file) && firstLine(file) != first_line)
    throw InputError("'" + file +
                     "': exists and was not written by budget-simulate; not written over");
}

std::vector<WrittenRawlog> simulateSessionsToFiles(const SimulationOptions& options,
                                                   const SessionChangeOptions& o,
                                                   const std::string& rawlog) {
  checkRawlogName(rawlog);
  if (options.scenario == SimulationOptions::ScenarioKind::Lifelong)
    throw ConfigError(
        "--sessions: scenario lifelong changes between its laps already; use "
        "another scenario");
  if (o.sessions < 1 || o.sessions > SessionChangeOptions::kMaxSessions)
    throw ConfigError("--sessions " + std::to_string(o.sessions) + ": must be 1 to " +
                      std::to_string(SessionChangeOptions::kMaxSessions));
  if (!(o.change >= 0 && o.change <= 1))
    throw ConfigError("--change " + shortNum(o.change) + ": must be a share in [0, 1]");
  // Bounded so that their sum is finite and each count exact (1e308 each summed to inf).
  for (const double s : {o.share_disappear, o.share_move, o.share_appear})
    if (!(s >= 0 && s <= kMaxShare))
      throw ConfigError("--change-split: each share must be a number in [0, " +
                        shortNum(kMaxShare) + "]");
  if (!(o.share_disappear + o.share_move + o.share_appear > 0))
    throw ConfigError("--change-split: the shares must not all be 0");
  if (!(o.move_distance > 0 && std::isfinite(o.move_distance)))
    throw ConfigError("--move-distance " + shortNum(o.move_distance) +
                      ": must be a finite number > 0");

  sim::Scenario scenario =
      sim::makeScenario(options.scenario, options.seed, options.laps, options.route);
  const std::vector<LandmarkChange> changes = changeWorld(scenario.world, options, o);
  scenario.world.index(std::max(2.0, scenario.sensor.max_range));

  // Nothing is written before every target is known to be ours or free.
  std::vector<std::string> targets;
  if (o.joined)
    targets.push_back(rawlog);
  else
    for (int s = 1; s <= o.sessions; ++s)
      targets.push_back(sessionRawlogName(rawlog, s, o.sessions));
  for (const auto& t : targets) checkNotForeign(t);
  const std::string changes_file = changesFileFor(rawlog);
  checkNotForeign(changes_file, kChangesHeader);

  const std::string what = std::to_string(o.sessions) + " sessions, change " + shortNum(o.change) +
                           " a session (disappear:move:appear " + shortNum(o.share_disappear) +
                           ":" + shortNum(o.share_move) + ":" + shortNum(o.share_appear) +
                           ", move distance " + shortNum(o.move_distance) + " m); changes in " +
                           changes_file.substr(changes_file.find_last_of('/') + 1) + ".";
  std::vector<WrittenRawlog> out;
  SeriesFiles series;
  if (o.joined) {
    const int laps = scenario.laps;
    scenario.laps = laps * o.sessions;
    EpochSchedule epochs;
    epochs.laps_per_epoch = laps;
    out.push_back({rawlog, writeOne(options, scenario, epochs, rawlog,
                                    landmarksOfEpoch(scenario.world, o.sessions - 1),
                                    {"Joined traversal of " + what +
                                     " Ground-truth landmarks: those of the last session."},
                                    series)});
  } else {
    for (int s = 1; s <= o.sessions; ++s) {
      EpochSchedule epochs;
      epochs.fixed = s - 1;
      // Session 1 has the noise of a single run of the same options; later ones their own.
      epochs.noise_stream = s == 1
                                ? 0
                                : 1000 * static_cast<std::uint64_t>(s) +
                                      (options.route == SimulationOptions::Route::Revisit ? 2 : 1);
      out.push_back(
          {targets[s - 1], writeOne(options, scenario, epochs, targets[s - 1],
                                    landmarksOfEpoch(scenario.world, s - 1),
                                    {"Session " + std::to_string(s) + " of " + what}, series)});
    }
  }
  writeFileAtomically(changes_file, changesText(changes));
  series.commit();
  out.push_back({changes_file, 0});
  return out;
}

}  // namespace budget_slam::dataset
