#include "budget_slam/graph/GraphSession.h"

#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace budget_slam::graph {

namespace {
// Field names of the graph in `[backend.graph]` (docs/OUTPUTS.md "Session state").
constexpr const char* kPoseSteps = "pose_steps";            // ints n, increasing
constexpr const char* kPoseTimes = "pose_times";            // reals n [s]
constexpr const char* kPoseValues = "pose_values";          // reals 3n: x, y [m], yaw [rad]
constexpr const char* kPrior = "first_pose_prior";          // reals 12: mean (3), covariance (9)
constexpr const char* kOdometry = "odometry";               // reals 12(n-1): z (3), covariance (9)
constexpr const char* kLandmarkIds = "landmark_ids";        // ints m, increasing
constexpr const char* kLandmarkValues = "landmark_values";  // reals 2m [m]
constexpr const char* kPriorIds = "landmark_prior_ids";     // ints p, increasing, in landmark_ids
constexpr const char* kPriors = "landmark_priors";  // reals 6p: mean (2), sqrt_info (4, by rows)
constexpr const char* kSightingPoses = "sighting_poses";          // ints k: the pose's step
constexpr const char* kSightingLandmarks = "sighting_landmarks";  // ints k: the landmark's id
// reals 9k: range [m], bearing [rad], sensor pose on the robot (3), covariance (4)
constexpr const char* kSightings = "sightings";

constexpr double kMaxCoordinate = 1e9;  ///< [m], the bound the state file's own blocks use

void putMatrix(std::vector<double>& out, const Eigen::MatrixXd& m) {
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c < m.cols(); ++c) out.push_back(m(r, c));
}

template <int N>
Eigen::Matrix<double, N, N> matrixAt(const std::vector<double>& v, std::size_t at) {
  Eigen::Matrix<double, N, N> m;
  for (int r = 0; r < N; ++r)
    for (int c = 0; c < N; ++c) m(r, c) = v[at + static_cast<std::size_t>(N * r + c)];
  return m;
}

/// Reads a section's fields with the field named in every error.
class Reader {
 public:
  explicit Reader(const session::SessionSection& s) : s_(s) {}

  [[noreturn]] void fail(const char* field, std::size_t entry, const std::string& what) const {
    s_.fail(field, "entry " + std::to_string(entry + 1) + ": " + what);
  }
  /// `count * per` reals, each a coordinate-sized value (|v| <= 1e9).
  const std::vector<double>& reals(const char* field, std::size_t count, std::size_t per) const {
    const auto& v = s_.reals(field, count * per);
    for (std::size_t i = 0; i < v.size(); ++i)
      if (std::abs(v[i]) > kMaxCoordinate)
        fail(field, i / per, "value " + std::to_string(v[i]) + " is beyond +-1e9");
    return v;
  }
  /// Ids or steps: non-negative, strictly increasing when `increasing`.
  const std::vector<std::int64_t>& ids(const char* field, bool increasing) const {
    const auto& v = s_.integers(field);
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (v[i] < 0) fail(field, i, "is negative (" + std::to_string(v[i]) + ")");
      if (increasing && i > 0 && v[i] <= v[i - 1])
        fail(field, i,
             "is not above the one before (" + std::to_string(v[i]) + " after " +
                 std::to_string(v[i - 1]) + ")");
    }
    return v;
  }
  /// A factor made from a stored covariance: its own check (symmetric, positive definite) named.
  template <typename F>
  auto make(const char* field, std::size_t entry, F&& f) const {
    try {
      return f();
    } catch (const std::invalid_argument& e) {
      fail(field, entry, e.what());
    }
  }

 private:
  const session::SessionSection& s_;
};
}  // namespace

void writeGraph(const FactorGraph& graph, session::SessionSection& section) {
  std::vector<std::int64_t> steps;
  std::vector<double> times, values, prior, odometry;
  for (const auto& [step, node] : graph.poses()) {
    steps.push_back(static_cast<std::int64_t>(step));
    times.push_back(node.t);
    putMatrix(values, node.x);
    if (node.odo) {
      putMatrix(odometry, node.odo->z.vector());
      putMatrix(odometry, node.odo->cov);
    }
  }
  if (!graph.poses().empty()) {
    putMatrix(prior, graph.prior().mean.vector());
    putMatrix(prior, graph.prior().cov);
  }
  std::vector<std::int64_t> ids, prior_ids, sighting_poses, sighting_landmarks;
  std::vector<double> landmark_values, priors, sightings;
  for (const auto& [id, l] : graph.landmarks()) {
    ids.push_back(static_cast<std::int64_t>(id));
    putMatrix(landmark_values, l.x);
    if (l.prior) {
      prior_ids.push_back(static_cast<std::int64_t>(id));
      putMatrix(priors, l.prior->mean);
      putMatrix(priors, l.prior->sqrt_info);
    }
    for (const Observation& o : l.obs) {
      sighting_poses.push_back(static_cast<std::int64_t>(o.pose));
      sighting_landmarks.push_back(static_cast<std::int64_t>(id));
      sightings.push_back(o.f.range);
      sightings.push_back(o.f.bearing);
      putMatrix(sightings, o.f.sensor.vector());
      putMatrix(sightings, o.f.cov);
    }
  }
  section.putIntegers(kPoseSteps, std::move(steps));
  section.putReals(kPoseTimes, std::move(times));
  section.putReals(kPoseValues, std::move(values));
  section.putReals(kPrior, std::move(prior));
  section.putReals(kOdometry, std::move(odometry));
  section.putIntegers(kLandmarkIds, std::move(ids));
  section.putReals(kLandmarkValues, std::move(landmark_values));
  section.putIntegers(kPriorIds, std::move(prior_ids));
  section.putReals(kPriors, std::move(priors));
  section.putIntegers(kSightingPoses, std::move(sighting_poses));
  section.putIntegers(kSightingLandmarks, std::move(sighting_landmarks));
  section.putReals(kSightings, std::move(sightings));
}

bool hasGraph(const session::SessionSection& section) { return section.has(kPoseSteps); }

FactorGraph readGraph(const session::SessionSection& section, std::int64_t next_step,
                      std::size_t max_poses) {
  const Reader in(section);
  FactorGraph g;

  const auto& steps = in.ids(kPoseSteps, true);
  const std::size_t n = steps.size();
  if (n > max_poses)
    section.fail(kPoseSteps, std::to_string(n) + " poses, more than " + std::to_string(max_poses));
  if (n > 0 && steps.back() >= next_step)
    in.fail(kPoseSteps, n - 1,
            "step " + std::to_string(steps.back()) + " is not before the session's next step " +
                std::to_string(next_step));
  const auto& times = section.reals(kPoseTimes, n);
  const auto& values = in.reals(kPoseValues, n, 3);
  const auto& prior = in.reals(kPrior, n > 0 ? 1 : 0, 12);
  const auto& odometry = in.reals(kOdometry, n > 0 ? n - 1 : 0, 12);
  for (std::size_t i = 0; i < n; ++i) {
    const StepIndex step = static_cast<StepIndex>(steps[i]);
    const Pose2 x(values[3 * i], values[3 * i + 1], values[3 * i + 2]);
    if (i == 0) {
      const PriorFactor p = in.make(kPrior, 0, [&] {
        return PriorFactor::make(Pose2(prior[0], prior[1], prior[2]), matrixAt<3>(prior, 3));
      });
      g.addFirstPose(step, times[i], x, p);
    } else {
      const std::size_t at = 12 * (i - 1);
      const BetweenFactor odo = in.make(kOdometry, i - 1, [&] {
        return BetweenFactor::make(Pose2(odometry[at], odometry[at + 1], odometry[at + 2]),
                                   matrixAt<3>(odometry, at + 3));
      });
      g.addPose(step, times[i], x, odo);
    }
  }

  const auto& ids = in.ids(kLandmarkIds, true);
  const std::size_t m = ids.size();
  const auto& landmark_values = in.reals(kLandmarkValues, m, 2);
  for (std::size_t i = 0; i < m; ++i)
    g.addLandmark(static_cast<LandmarkId>(ids[i]),
                  Eigen::Vector2d(landmark_values[2 * i], landmark_values[2 * i + 1]));

  const auto& prior_ids = in.ids(kPriorIds, true);
  const auto& priors = in.reals(kPriors, prior_ids.size(), 6);
  for (std::size_t i = 0; i < prior_ids.size(); ++i) {
    const LandmarkId id = static_cast<LandmarkId>(prior_ids[i]);
    if (!g.hasLandmark(id))
      in.fail(kPriorIds, i, "landmark " + std::to_string(id) + " is not in " + kLandmarkIds);
    LandmarkPrior p;
    p.mean = Eigen::Vector2d(priors[6 * i], priors[6 * i + 1]);
    p.sqrt_info = matrixAt<2>(priors, 6 * i + 2);
    // The information S^T S must be positive definite: S invertible, and not so close to
    // singular that the information is nothing but rounding.
    const Eigen::JacobiSVD<Eigen::Matrix2d> svd(p.sqrt_info);
    const Eigen::Vector2d sv = svd.singularValues();
    if (!(sv(1) > 0) || sv(1) < 1e-12 * sv(0))
      in.fail(kPriors, i, "the square root of the information is singular");
    g.setLandmarkPrior(id, p);
  }

  const auto& sighting_poses = in.ids(kSightingPoses, false);
  const std::size_t k = sighting_poses.size();
  const auto& sighting_landmarks =
      section.integers(kSightingLandmarks, k, 0, std::numeric_limits<std::int64_t>::max());
  const auto& sightings = in.reals(kSightings, k, 9);
  for (std::size_t i = 0; i < k; ++i) {
    const StepIndex pose = static_cast<StepIndex>(sighting_poses[i]);
    const LandmarkId id = static_cast<LandmarkId>(sighting_landmarks[i]);
    if (!g.hasPose(pose))
      in.fail(kSightingPoses, i, "step " + std::to_string(pose) + " is not in " + kPoseSteps);
    if (!g.hasLandmark(id))
      in.fail(kSightingLandmarks, i,
              "landmark " + std::to_string(id) + " is not in " + kLandmarkIds);
    const double* s = &sightings[9 * i];
    if (!(s[0] > 0)) in.fail(kSightings, i, "range " + std::to_string(s[0]) + " is not above 0");
    const RangeBearingFactor f = in.make(kSightings, i, [&] {
      return RangeBearingFactor::make(s[0], s[1], Pose2(s[2], s[3], s[4]),
                                      matrixAt<2>(sightings, 9 * i + 5));
    });
    g.addObservation(pose, id, f);
  }
  for (const auto& [id, l] : g.landmarks())
    if (l.obs.empty() && !l.prior)
      section.fail(kLandmarkIds, "landmark " + std::to_string(id) +
                                     " has neither a sighting nor a prior (unconstrained)");
  return g;
}

}  // namespace budget_slam::graph
