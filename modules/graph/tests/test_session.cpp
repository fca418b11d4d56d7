// The graph in a session state (docs/GRAPH.md "Resuming a session"): a run split in two sessions,
// the state written to text and read back between them, equals the one-shot run, with landmarks
// dropped and poses marginalized in both halves; a robot placed elsewhere starts a new chain; a
// bad value in the saved graph is one line naming the field.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFile.h>
#include <functional>

#include "TestGraphs.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/graph/GraphBackend.h"
#include "budget_slam/session/SessionState.h"
#include "budget_slam/session/SessionStateFile.h"

using namespace budget_slam;
using namespace budget_slam::graph;

namespace {

/// Every step of rawlogs/kf-slam_demo.rawlog and its sensor noise (config.ini, then the rawlog's
/// sidecar), read as the app reads them.
std::vector<Step> demoSteps(RangeBearingNoise* noise) {
  const std::string root = BUDGET_SLAM_SOURCE_DIR;
  for (const std::string ini : {root + "/config.ini", root + "/rawlogs/kf-slam_demo.ini"})
    if (std::ifstream(ini).good())
      noise->loadFromConfigFile(mrpt::config::CConfigFile(ini), RangeBearingNoise::kSection);
  std::vector<Step> steps;
  dataset::RawlogReader reader(root + "/rawlogs/kf-slam_demo.rawlog");
  while (std::optional<Step> s = reader.next()) steps.push_back(std::move(*s));
  return steps;
}

/// The landmark with the fewest sightings (ties: lowest id).
LandmarkId leastSeen(const FactorGraph& g) {
  LandmarkId best = 0;
  std::size_t n = ~std::size_t(0);
  for (const auto& [id, l] : g.landmarks())
    if (l.obs.size() < n) n = l.obs.size(), best = id;
  return best;
}

/// One step as a run makes it: the backend's update, the queries a run makes after it (the map,
/// the pose), and a budget's changes: the least-seen landmark dropped every 7 steps once the map
/// holds 6, poses without landmarks marginalized every 25. True when it dropped a landmark.
bool step(GraphBackend& b, const Step& s) {
  b.process(s);
  (void)b.landmarks();
  (void)b.robotPose();
  const bool drop = s.index % 7 == 3 && b.landmarkCount() >= 6;
  if (drop) b.removeLandmark(leastSeen(b.graph()));
  if (s.index % 25 == 11) b.marginalizePosesWithoutLandmarks(3);
  return drop;
}

/// The state a run writes after `b`'s step `next_step - 1`, through its text and back.
session::SessionState savedAndRead(const GraphBackend& b, std::int64_t next_step) {
  session::SessionState st;
  st.header.writer = "test";
  st.header.backend = "graph";
  st.header.rawlog = "kf-slam_demo.rawlog";
  st.header.next_step = next_step;
  b.saveSession(st);
  return session::readSessionStateBytes("saved", session::formatSessionState(st));
}

double poseDiff(const PoseEstimate& a, const PoseEstimate& b) {
  return std::max({std::abs(a.mean.x - b.mean.x), std::abs(a.mean.y - b.mean.y),
                   std::abs(wrapAngle(a.mean.phi - b.mean.phi))});
}

struct SplitRun {
  double online = 0;     ///< largest difference of the per-step poses after the split
  double final = 0;      ///< of the final path, every pose (m, rad)
  double landmarks = 0;  ///< of the final landmark means
  std::size_t drops_before = 0, drops_after = 0;  ///< landmarks dropped in each half
  std::size_t poses_dropped = 0;                  ///< by the bounded graph (max_poses)
};

SplitRun splitAgainstOneShot(const GraphSlamOptions& options, std::size_t at) {
  RangeBearingNoise noise;
  const std::vector<Step> steps = demoSteps(&noise);
  EXPECT_GT(steps.size(), at + 50);
  GraphBackend one(options, noise), first(options, noise);
  SplitRun r;
  for (std::size_t k = 0; k < at; ++k) {
    r.drops_before += step(one, steps[k]) ? 1 : 0;
    step(first, steps[k]);
  }
  const session::SessionState st = savedAndRead(first, static_cast<std::int64_t>(at));
  GraphBackend second(options, noise);
  second.restoreSession(st);
  st.checkAllRead();
  EXPECT_EQ(second.poseCount(), first.poseCount());
  for (std::size_t k = at; k < steps.size(); ++k) {
    r.drops_after += step(one, steps[k]) ? 1 : 0;
    step(second, steps[k]);
    r.online = std::max(r.online, poseDiff(one.robotPose(), second.robotPose()));
  }
  one.finish();
  second.finish();
  const auto a = one.trajectory(), b = second.trajectory();
  EXPECT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
    EXPECT_EQ(a[k].step, b[k].step);
    r.final =
        std::max({r.final, std::abs(a[k].pose.x - b[k].pose.x), std::abs(a[k].pose.y - b[k].pose.y),
                  std::abs(wrapAngle(a[k].pose.phi - b[k].pose.phi))});
  }
  const auto la = one.landmarks(), lb = second.landmarks();
  EXPECT_EQ(la.size(), lb.size());
  for (std::size_t k = 0; k < std::min(la.size(), lb.size()); ++k) {
    EXPECT_EQ(la[k].id, lb[k].id);
    r.landmarks = std::max(r.landmarks, (la[k].mean - lb[k].mean).lpNorm<Eigen::Infinity>());
  }
  r.poses_dropped = one.posesDropped();
  return r;
}

/// The error restoreSession() throws for `st`, "" when it takes it.
std::string restoreError(const session::SessionState& st) {
  RangeBearingNoise noise;
  GraphBackend b(GraphSlamOptions{}, noise);
  try {
    b.restoreSession(st);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(GraphSession, SplitEqualsOneShotWithDropsInBothHalves) {
  const SplitRun r = splitAgainstOneShot(GraphSlamOptions{}, 60);
  EXPECT_GT(r.drops_before, 0u);
  EXPECT_GT(r.drops_after, 0u);
  EXPECT_LE(r.online, 1e-6);
  EXPECT_LE(r.final, 1e-6);
  EXPECT_LE(r.landmarks, 1e-6);
}

// The bounded graph: the saved state holds the marginalized past as it stands (the first pose's
// composed prior, the landmark priors of the sightings that left), at its linearization point.
TEST(GraphSession, SplitEqualsOneShotOnTheBoundedGraph) {
  GraphSlamOptions o;
  o.max_poses = 30;
  const SplitRun r = splitAgainstOneShot(o, 60);
  EXPECT_GT(r.poses_dropped, 0u);
  EXPECT_GT(r.drops_after, 0u);
  EXPECT_LE(r.online, 1e-6);
  EXPECT_LE(r.final, 1e-6);
  EXPECT_LE(r.landmarks, 1e-6);
}

// The run says where the robot starts (session::RobotStart), not the pose: a robot placed on the
// map starts a new chain even where the saved one stopped, and before its first step the backend
// reports the pose it was placed at.
TEST(GraphSession, RobotPlacedElsewhereStartsANewChainOnTheMap) {
  RangeBearingNoise noise;
  const std::vector<Step> steps = demoSteps(&noise);
  GraphBackend first(GraphSlamOptions{}, noise);
  for (std::size_t k = 0; k < 40; ++k) step(first, steps[k]);
  for (const double dx : {0.25, 0.0}) {
    session::SessionState st = savedAndRead(first, 40);
    st.robot->pose.mean.x += dx;  // what --wake-up hands over: a pose found on the map
    st.robot_start = session::RobotStart::Placed;
    GraphBackend woken(GraphSlamOptions{}, noise);
    woken.restoreSession(st);
    st.checkAllRead();
    EXPECT_EQ(woken.poseCount(), 0u) << dx;
    EXPECT_EQ(woken.landmarkCount(), first.landmarkCount());
    for (const auto& [id, l] : woken.graph().landmarks()) EXPECT_TRUE(l.prior.has_value()) << id;
    EXPECT_EQ(woken.robotPose().mean.x, st.robot->pose.mean.x);
    EXPECT_TRUE(woken.robotPose().cov == st.robot->pose.cov);
    // The map alone (landmarks under their priors, no pose yet) is a well-posed system: its
    // marginals are the saved ones (the priors' covariances).
    const auto views = woken.landmarks();
    ASSERT_EQ(views.size(), st.map.landmarks.size());
    for (std::size_t i = 0; i < views.size(); ++i)
      EXPECT_LE((views[i].cov - st.map.landmarks[i].cov).lpNorm<Eigen::Infinity>(), 1e-9);
    // A landmark leaves the map before the first step (a split at the first step after a
    // wake-up), and the session goes on.
    woken.removeLandmark(views.front().id);
    EXPECT_EQ(woken.landmarks().size(), views.size() - 1);
    for (std::size_t k = 40; k < 60; ++k) step(woken, steps[k]);
    EXPECT_EQ(woken.poseCount(), 20u);
  }
}

// A robot the run says goes on where the session stopped must be the saved chain's last pose.
TEST(GraphSession, ARobotOffTheSavedChainIsRefused) {
  RangeBearingNoise noise;
  const std::vector<Step> steps = demoSteps(&noise);
  GraphBackend first(GraphSlamOptions{}, noise);
  for (std::size_t k = 0; k < 40; ++k) step(first, steps[k]);
  session::SessionState st = savedAndRead(first, 40);
  st.robot->pose.mean.y += 0.01;
  const std::string e = restoreError(st);
  EXPECT_NE(e.find("section 'backend.graph', field 'pose_values': the last pose is not the robot"),
            std::string::npos)
      << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

namespace {
/// `st` with field `name` of [backend.graph] replaced by what `change` makes of it.
session::SessionState withField(const session::SessionState& st, const std::string& name,
                                const std::function<void(session::FieldValue&)>& change) {
  session::SessionState out;
  out.header = st.header;
  out.map = st.map;
  out.robot = st.robot;
  for (const session::SessionSection& s : st.sections()) {
    session::SessionSection copy(s.name(), "saved", s.line());
    for (session::Field f : s.fields()) {
      if (s.name() == "backend.graph" && f.name == name) change(f.value);
      copy.add(f);
    }
    out.addSection(copy);
  }
  return out;
}

}  // namespace

TEST(GraphSession, BadValuesAreOneLineNamingTheField) {
  RangeBearingNoise noise;
  const std::vector<Step> steps = demoSteps(&noise);
  GraphBackend first(GraphSlamOptions{}, noise);
  for (std::size_t k = 0; k < 40; ++k) step(first, steps[k]);
  const session::SessionState st = savedAndRead(first, 40);
  ASSERT_EQ(restoreError(st), "");
  const std::string n = std::to_string(first.poseCount());
  using V = std::vector<double>;
  using I = std::vector<std::int64_t>;
  const struct {
    std::string field;
    std::function<void(session::FieldValue&)> change;
    std::string says;
  } cases[] = {
      {"sightings", [](auto& v) { std::get<V>(v)[0] = 0; },
       "field 'sightings': entry 1: range 0.000000 is not above 0"},
      {"sightings", [](auto& v) { std::get<V>(v)[5] = -1; },
       "field 'sightings': entry 1: covariance is not positive definite"},
      {"odometry", [](auto& v) { std::get<V>(v)[4] = 1; },
       "field 'odometry': entry 1: covariance is not finite and symmetric"},
      {"first_pose_prior", [](auto& v) { std::get<V>(v)[0] = 2e9; },
       "field 'first_pose_prior': entry 1: value 2000000000.000000 is beyond +-1e9"},
      {"pose_steps", [](auto& v) { std::swap(std::get<I>(v)[1], std::get<I>(v)[2]); },
       "field 'pose_steps': entry 3: is not above the one before"},
      {"pose_steps", [](auto& v) { std::get<I>(v).back() = 40; },
       "field 'pose_steps': entry " + n + ": step 40 is not before the session's next step 40"},
      {"pose_values", [](auto& v) { std::get<V>(v).pop_back(); },
       "field 'pose_values': " + std::to_string(3 * first.poseCount() - 1) + " values, expected " +
           std::to_string(3 * first.poseCount())},
      {"sighting_poses", [](auto& v) { std::get<I>(v)[0] = 1000; },
       "field 'sighting_poses': entry 1: step 1000 is not in pose_steps"},
      {"pose_covariance", [](auto& v) { std::get<V>(v).assign(9, 0.0); },
       "field 'pose_covariance': covariance is not positive definite"},
  };
  for (const auto& c : cases) {
    const std::string e = restoreError(withField(st, c.field, c.change));
    EXPECT_NE(e.find("section 'backend.graph', " + c.says), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

// A state written before the graph was saved whole ([backend.graph] holds only next_fresh_id) is
// still read: the map's marginals as landmark priors, the robot where it stopped.
TEST(GraphSession, OlderStateWithoutTheGraphIsStillRead) {
  RangeBearingNoise noise;
  const std::vector<Step> steps = demoSteps(&noise);
  GraphBackend first(GraphSlamOptions{}, noise);
  for (std::size_t k = 0; k < 40; ++k) step(first, steps[k]);
  const session::SessionState st = savedAndRead(first, 40);
  session::SessionState old;
  old.header = st.header;
  old.map = st.map;
  old.robot = st.robot;
  for (const session::SessionSection& s : st.sections()) {
    session::SessionSection copy(s.name(), "saved", s.line());
    for (const session::Field& f : s.fields())
      if (s.name() != "backend.graph" || f.name == "next_fresh_id") copy.add(f);
    old.addSection(copy);
  }
  GraphBackend resumed(GraphSlamOptions{}, noise);
  resumed.restoreSession(old);
  old.checkAllRead();
  EXPECT_EQ(resumed.poseCount(), 0u);
  EXPECT_EQ(resumed.landmarkCount(), first.landmarkCount());
  resumed.process(steps[40]);
  EXPECT_LT(poseDiff(resumed.robotPose(), first.robotPose()), 1.0);
}
