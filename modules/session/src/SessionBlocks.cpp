#include "SessionBlocks.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/OptionTable.h"
#include "budget_slam/core/Text.h"

namespace budget_slam::session {
namespace {

constexpr std::int64_t kMaxInt = std::numeric_limits<std::int64_t>::max();
/// Positions beyond this are refused: squares and sums of them must stay finite [m].
constexpr double kMaxCoordinate = 1e9;
/// Relative asymmetry a covariance may have: |a_ij - a_ji| <= tol * sqrt(a_ii * a_jj). The EKF
/// keeps its covariance exactly symmetric; the graph's marginals are symmetric to round-off.
constexpr double kSymmetryTolerance = 1e-9;

/// A state must leave room for the sessions and steps to come: a resumed run adds one session and
/// its steps to these, and writes them as int64 (steps.csv, the next state). 2^53 steps (285
/// million years at 1 kHz) also keeps every step index exact as a double.
constexpr std::int64_t kMaxSessions = std::int64_t{1} << 40;
constexpr std::int64_t kMaxStepIndex = std::int64_t{1} << 53;

const char* kSession = "session";
const char* kOptions = "resume_options";
const char* kLandmarks = "landmarks";
const char* kRobot = "robot";

std::string num(double v) { return option::numberText(v); }

/// Symmetric (to kSymmetryTolerance) and positive definite, else InputError naming the field.
void checkCovariance(const SessionSection& s, const std::string& field, const Eigen::MatrixXd& m) {
  const Eigen::Index n = m.rows();
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(m(i, i) > 0))
      s.fail(field, "not positive definite (diagonal entry " + std::to_string(i + 1) + " is " +
                        num(m(i, i)) + ")");
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j)
      if (std::abs(m(i, j) - m(j, i)) > kSymmetryTolerance * std::sqrt(m(i, i) * m(j, j)))
        s.fail(field, "not symmetric (row " + std::to_string(i + 1) + ", column " +
                          std::to_string(j + 1) + " is " + num(m(i, j)) + ", row " +
                          std::to_string(j + 1) + ", column " + std::to_string(i + 1) + " is " +
                          num(m(j, i)) + ")");
  if (n == 0) return;
  const Eigen::LLT<Eigen::MatrixXd> llt(m);
  // Eigen's LLT lets a NaN pivot through: check the factor too.
  if (llt.info() != Eigen::Success || !llt.matrixLLT().allFinite())
    s.fail(field, "not positive definite");
}

void checkCoordinates(const SessionSection& s, const std::string& field,
                      const std::vector<double>& v) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (std::abs(v[i]) > kMaxCoordinate)
      s.fail(field, "value " + std::to_string(i + 1) + " (" + num(v[i]) + ") is beyond +-1e9 m");
}

/// A path as one line of text: a backslash doubled, a control character or a byte that is not part
/// of valid UTF-8 as a backslash, 'x' and two hex digits (Linux allows any byte but '/' and NUL in
/// a name: a rawlog named with a newline is still a rawlog). unescapePath() gives the path back.
std::string escapePath(const std::string& path) {
  std::string out;
  for (std::size_t i = 0; i < path.size();) {
    const auto c = static_cast<unsigned char>(path[i]);
    std::size_t n = 1;  // the bytes of the character at i, when it is valid UTF-8
    if (c >= 0x80) {
      n = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : c >= 0xC0 ? 2 : 0;
      if (n == 0 || i + n > path.size() || !isValidUtf8(std::string_view(path).substr(i, n))) n = 0;
    }
    if (c == '\\') {
      out += "\\\\";
    } else if (n == 0 || c < 0x20 || c == 0x7F) {
      char b[5];
      std::snprintf(b, sizeof b, "\\x%02x", c);
      out += b;
      n = 1;
    } else {
      out.append(path, i, n);
    }
    i += n;
  }
  return out;
}

std::string unescapePath(const SessionSection& s, const std::string& field) {
  const std::string& t = s.text(field);
  std::string out;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] != '\\') {
      out += t[i];
      continue;
    }
    if (i + 1 < t.size() && t[i + 1] == '\\') {
      out += '\\', ++i;
      continue;
    }
    unsigned v = 0;
    const auto hex = std::string_view(t).substr(std::min(t.size(), i + 2), 2);
    const auto r = std::from_chars(hex.data(), hex.data() + hex.size(), v, 16);
    if (i + 3 >= t.size() || t[i + 1] != 'x' || hex.size() != 2 || r.ptr != hex.data() + 2)
      s.fail(field,
             "'\\' at byte " + std::to_string(i + 1) + " is not an escape ('\\\\' or '\\xNN')");
    out += static_cast<char>(v);
    i += 3;
  }
  return out;
}

/// Every field of a core section must be one the block defines.
void checkNoOtherField(const SessionSection& s) {
  const auto unread = s.unread();
  if (!unread.empty()) s.fail(unread.front(), "unknown field");
}

void readHeader(const SessionSection& s, SessionHeader* h) {
  h->writer = s.text("writer");
  h->backend = s.text("backend");
  if (h->backend.empty()) s.fail("backend", "empty");
  h->rawlog = unescapePath(s, "rawlog");
  h->sessions = s.integer("sessions", 1, kMaxSessions);
  h->first_step = s.integer("first_step", 0, kMaxStepIndex);
  h->next_step = s.integer("next_step", h->first_step, kMaxStepIndex);
  checkNoOtherField(s);
}

void readOptions(const SessionSection& s, SessionHeader* h) {
  for (const auto& f : s.fields()) h->resume_options[f.name] = s.text(f.name);
}

void readLandmarks(const SessionSection& s, std::int64_t next_step, LandmarkBlock* map) {
  const auto& ids = s.integers("ids");
  const std::size_t n = ids.size();
  std::set<std::int64_t> seen;
  for (std::size_t i = 0; i < n; ++i) {
    if (ids[i] < 0)
      s.fail("ids", "value " + std::to_string(i + 1) + " (" + std::to_string(ids[i]) +
                        ") is not a landmark id (negative)");
    if (!seen.insert(ids[i]).second)
      s.fail("ids", "landmark " + std::to_string(ids[i]) + " appears twice");
  }
  const auto& mean = s.reals("mean", 2 * n);
  checkCoordinates(s, "mean", mean);
  const auto& cov = s.matrix("covariance", 2 * n, 2 * n);
  checkCovariance(s, "covariance", cov);
  const auto& sightings = s.integers("sightings", n, 0, kMaxInt);
  const auto& seen_from = s.reals("seen_from", 2 * n);
  checkCoordinates(s, "seen_from", seen_from);
  const auto& first = s.integers("first_step", n, 0, kMaxInt);
  const auto& last = s.integers("last_step", n, 0, next_step > 0 ? next_step - 1 : 0);
  for (std::size_t i = 0; i < n; ++i)
    if (first[i] > last[i])
      s.fail("last_step", "value " + std::to_string(i + 1) + " (" + std::to_string(last[i]) +
                              ") is before the landmark's first_step " + std::to_string(first[i]));
  checkNoOtherField(s);

  map->landmarks.assign(n, LandmarkView{});
  for (std::size_t i = 0; i < n; ++i) {
    LandmarkView& v = map->landmarks[i];
    v.id = ids[i];
    v.mean = Eigen::Vector2d(mean[2 * i], mean[2 * i + 1]);
    v.cov = cov.block<2, 2>(2 * i, 2 * i);
    v.n_obs = static_cast<std::size_t>(sightings[i]);
    v.obs_mean = Eigen::Vector2d(seen_from[2 * i], seen_from[2 * i + 1]);
    v.first_step = static_cast<StepIndex>(first[i]);
    v.last_step = static_cast<StepIndex>(last[i]);
  }
  map->covariance = cov;
}

void readRobot(const SessionSection& s, const LandmarkBlock& map, RobotBlock* robot) {
  const auto& mean = s.reals("mean", 3);
  checkCoordinates(s, "mean", mean);
  const auto& cov = s.matrix("covariance", 3, 3);
  checkCovariance(s, "covariance", cov);
  const auto n2 = static_cast<Eigen::Index>(map.covariance.rows());
  const auto& cross = s.matrix("cross_covariance", 3, n2);
  checkNoOtherField(s);
  Eigen::MatrixXd joint(3 + n2, 3 + n2);
  joint << cov, cross, cross.transpose(), map.covariance;
  if (n2 > 0) {
    const Eigen::LLT<Eigen::MatrixXd> llt(joint);
    if (llt.info() != Eigen::Success || !llt.matrixLLT().allFinite())
      s.fail("cross_covariance",
             "the joint covariance of the robot and the landmarks is not positive definite");
  }
  robot->pose.mean = Pose2(mean[0], mean[1], mean[2]);
  robot->pose.cov = cov;
  robot->cross_covariance = cross;
}

}  // namespace

bool isCoreSection(const std::string& name) {
  return name == kSession || name == kOptions || name == kLandmarks || name == kRobot;
}

std::vector<SessionSection> coreSections(const SessionState& state, const std::string& source) {
  std::vector<SessionSection> out;
  SessionSection h(kSession, source);
  h.putText("writer", state.header.writer);
  h.putText("backend", state.header.backend);
  h.putText("rawlog", escapePath(state.header.rawlog));
  h.putInteger("sessions", state.header.sessions);
  h.putInteger("first_step", state.header.first_step);
  h.putInteger("next_step", state.header.next_step);
  out.push_back(std::move(h));

  SessionSection o(kOptions, source);
  for (const auto& [k, v] : state.header.resume_options) o.putText(k, v);
  out.push_back(std::move(o));

  const auto& lm = state.map.landmarks;
  const std::size_t n = lm.size();
  std::vector<std::int64_t> ids(n), sightings(n), first(n), last(n);
  std::vector<double> mean(2 * n), seen_from(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    ids[i] = lm[i].id;
    mean[2 * i] = lm[i].mean.x();
    mean[2 * i + 1] = lm[i].mean.y();
    sightings[i] = static_cast<std::int64_t>(lm[i].n_obs);
    seen_from[2 * i] = lm[i].obs_mean.x();
    seen_from[2 * i + 1] = lm[i].obs_mean.y();
    first[i] = static_cast<std::int64_t>(lm[i].first_step);
    last[i] = static_cast<std::int64_t>(lm[i].last_step);
  }
  SessionSection l(kLandmarks, source);
  l.putIntegers("ids", std::move(ids));
  l.putReals("mean", std::move(mean));
  l.putMatrix("covariance", state.map.covariance);
  l.putIntegers("sightings", std::move(sightings));
  l.putReals("seen_from", std::move(seen_from));
  l.putIntegers("first_step", std::move(first));
  l.putIntegers("last_step", std::move(last));
  out.push_back(std::move(l));

  if (state.robot) {
    SessionSection r(kRobot, source);
    const auto& p = state.robot->pose;
    r.putReals("mean", {p.mean.x, p.mean.y, p.mean.phi});
    r.putMatrix("covariance", p.cov);
    r.putMatrix("cross_covariance", state.robot->cross_covariance);
    out.push_back(std::move(r));
  }
  return out;
}

void readCoreBlocks(const std::vector<SessionSection>& sections, SessionState* state) {
  const auto find = [&](const char* name) -> const SessionSection* {
    for (const auto& s : sections)
      if (s.name() == name) return &s;
    return nullptr;
  };
  const auto require = [&](const char* name) -> const SessionSection& {
    if (const auto* s = find(name)) return *s;
    throw InputError(stateLabel(state->source) + ": missing section '" + name + "'");
  };
  readHeader(require(kSession), &state->header);
  readOptions(require(kOptions), &state->header);
  readLandmarks(require(kLandmarks), state->header.next_step, &state->map);
  state->robot.reset();
  if (const auto* r = find(kRobot)) {
    RobotBlock robot;
    readRobot(*r, state->map, &robot);
    state->robot = std::move(robot);
  }
}

}  // namespace budget_slam::session
