#pragma once
// A small session state for the tests, and the helpers that edit its text.
#include <zlib.h>

#include <Eigen/Dense>
#include <cstdio>
#include <functional>
#include <random>
#include <string>

#include "TempFiles.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/session/SessionState.h"
#include "budget_slam/session/SessionStateFile.h"

namespace budget_slam::session::test {

/// A random symmetric positive-definite n x n matrix.
inline Eigen::MatrixXd randomSpd(Eigen::Index n, std::mt19937& rng) {
  std::normal_distribution<double> g;
  Eigen::MatrixXd a(n, n);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = g(rng);
  Eigen::MatrixXd s =
      a * a.transpose() / static_cast<double>(n) + 0.1 * Eigen::MatrixXd::Identity(n, n);
  return (s + s.transpose()) / 2;  // exactly symmetric
}

/// `n` landmarks with a joint covariance, a robot correlated with them, resume options and two
/// owner sections ("budget", "place-coverage"). Values chosen to test exact round trips: thirds,
/// tenths, signed zero, the smallest subnormal.
inline SessionState sampleState(std::size_t n = 3, bool with_robot = true, unsigned seed = 1) {
  std::mt19937 rng(seed);
  SessionState s;
  s.header.writer = "budget-slam 0.1.0";
  s.header.backend = "ekf";
  s.header.rawlog = "rawlogs/rooms.rawlog";
  s.header.sessions = 2;
  s.header.first_step = 100;
  s.header.next_step = 250;
  s.header.resume_options = {{"LandmarkBudget.max_landmarks", "50"},
                             {"LandmarkBudget.reducer", "place-coverage"},
                             {"RangeBearingKFSLAM.std_sensor_range", "0.1"}};
  const Eigen::MatrixXd joint = randomSpd(static_cast<Eigen::Index>(3 + 2 * n), rng);
  std::uniform_real_distribution<double> u(-20, 20);
  for (std::size_t i = 0; i < n; ++i) {
    LandmarkView v;
    v.id = static_cast<LandmarkId>(7 * i + 3);
    v.mean = Eigen::Vector2d(u(rng) / 3.0, i == 0 ? -0.0 : 0.1 * static_cast<double>(i));
    v.n_obs = 4 + i;
    v.obs_mean = Eigen::Vector2d(u(rng), i == 1 ? 4.9406564584124654e-324 : u(rng));
    v.first_step = 100 + i % 50;
    v.last_step = 200 + i % 50;
    s.map.landmarks.push_back(v);
  }
  s.map.covariance = joint.bottomRightCorner(2 * n, 2 * n);
  if (with_robot) {
    RobotBlock r;
    r.pose.mean = Pose2(1.0 / 3.0, -2.5, 0.7);
    r.pose.cov = joint.topLeftCorner(3, 3);
    r.cross_covariance = joint.topRightCorner(3, 2 * n);
    s.robot = r;
  }
  auto& b = s.section("budget");
  b.putIntegers("refused_ids", {4, 9, 12});
  b.putIntegers("refused_at", {120, 130, 131});
  b.putInteger("next_id", 42);
  b.putReals("scores", {0.1, 1.0 / 3.0, -1e-300});
  b.putText("reducer", "place-coverage");
  auto& p = s.section("place-coverage");
  Eigen::MatrixXd places(2, 3);
  places << 1, 2, 3, 4.5, -5.25, 6e10;
  p.putMatrix("places", places);
  p.putReal("place_size", 2.5);
  return s;
}

/// `text` with its end line replaced by one holding the CRC-32 of the rest: an edited file that
/// passes the checksum, to reach the checks behind it.
inline std::string withChecksum(std::string text) {
  const auto end = text.rfind("end crc32 ");
  if (end != std::string::npos) text.resize(end);
  const auto crc = crc32_z(0L, reinterpret_cast<const Bytef*>(text.data()), text.size());
  char buf[32];
  std::snprintf(buf, sizeof buf, "end crc32 %08lx\n", static_cast<unsigned long>(crc));
  return text + buf;
}

/// The first occurrence of `from` in `text` replaced by `to` (the test fails when absent).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos) return "(" + from + " not found)";
  return text.replace(at, from.size(), to);
}

/// The InputError line of reading `bytes`, "no error" when it reads.
inline std::string readError(const std::string& bytes, const SessionLimits& limits = {}) {
  try {
    readSessionStateBytes("s.txt", bytes, limits);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

using budget_slam::test::errorOf;  // the Error a call throws (core's test helpers)

}  // namespace budget_slam::session::test
