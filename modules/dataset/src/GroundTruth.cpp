#include "budget_slam/dataset/GroundTruth.h"

#include <sys/stat.h>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>

#include "TextTable.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/InputLimits.h"

namespace budget_slam::dataset {
namespace {

/// `<dir>/<stem>` of a rawlog name: without ".rawlog" (or whatever extension the name has).
std::string stemOf(const std::string& rawlog) {
  const auto slash = rawlog.find_last_of('/');
  const auto dot = rawlog.find_last_of('.');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash + 1))
    return rawlog.substr(0, dot);
  return rawlog;
}

bool isFile(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::map<LandmarkId, Eigen::Vector2d> loadLandmarks(const std::string& file) {
  // MRPT's CLandmarksMap::saveToTextFile: x y z type times_seen time_last_seen id.
  std::map<LandmarkId, Eigen::Vector2d> landmarks;
  std::map<LandmarkId, std::size_t> line_of;
  TextTable t(file);
  while (t.next()) {
    t.expectAtLeast(7, "landmark row (x y z type seen time id)");
    const double x = t.bounded(0, "x", limits::kMaxCoordinate);
    const double y = t.bounded(1, "y", limits::kMaxCoordinate);
    const double id_value = t.number(6, "id");
    if (id_value != std::floor(id_value) || id_value < 0 ||
        id_value > std::numeric_limits<int>::max())
      t.fail("id is not a non-negative integer: '" + t.word(6) + "'");
    const auto id = static_cast<LandmarkId>(id_value);
    if (const auto it = line_of.find(id); it != line_of.end())
      t.fail("landmark id " + std::to_string(id) + " appears twice (first on line " +
             std::to_string(it->second) + ")");
    line_of[id] = t.line();
    landmarks[id] = Eigen::Vector2d(x, y);
  }
  return landmarks;
}

std::vector<Pose2> loadPath(const std::string& file) {
  // MRPT's CMatrixDouble::saveToTextFile of simul-landmarks: x y z yaw pitch roll; kf-slam also
  // accepts x y yaw.
  std::vector<Pose2> path;
  TextTable t(file);
  while (t.next()) {
    if (t.size() == 6 || t.size() == 3)
      path.emplace_back(t.bounded(0, "x", limits::kMaxCoordinate),
                        t.bounded(1, "y", limits::kMaxCoordinate),
                        t.bounded(t.size() == 6 ? 3 : 2, "yaw", limits::kMaxAngle));
    else
      t.fail("robot path row needs 6 fields (x y z yaw pitch roll) or 3 (x y yaw), found " +
             std::to_string(t.size()));
  }
  return path;
}

/// printf into a std::string.
template <typename... Args>
std::string format(const char* fmt, Args... args) {
  const int n = std::snprintf(nullptr, 0, fmt, args...);
  std::string s(static_cast<std::size_t>(n) + 1, '\0');
  std::snprintf(s.data(), s.size(), fmt, args...);
  s.pop_back();
  return s;
}

double noNegativeZero(double v) { return v == 0 ? 0.0 : v; }

}  // namespace

std::string groundTruthLandmarksPathFor(const std::string& rawlog) {
  return stemOf(rawlog) + "_ground_truth.txt";
}

std::string groundTruthRobotPathFor(const std::string& rawlog) {
  return stemOf(rawlog) + "_ground_truth_robot_path.txt";
}

GroundTruth loadGroundTruth(const std::string& rawlog, const std::string& landmarks_file,
                            const std::string& path_file) {
  GroundTruth gt;
  const std::string lm =
      landmarks_file.empty() ? groundTruthLandmarksPathFor(rawlog) : landmarks_file;
  if (!landmarks_file.empty() || isFile(lm)) {
    gt.landmarks = loadLandmarks(lm);
    gt.landmarks_file = lm;
  }
  const std::string pf = path_file.empty() ? groundTruthRobotPathFor(rawlog) : path_file;
  if (!path_file.empty() || isFile(pf)) {
    gt.path = loadPath(pf);
    gt.path_file = pf;
  }
  return gt;
}

std::string groundTruthLandmarksText(const std::map<LandmarkId, Eigen::Vector2d>& landmarks) {
  // Same layout as MRPT's CLandmarksMap::saveToTextFile (what simul-landmarks writes): type 5 is
  // featBeacon, times seen and time last seen are 0.
  std::string text;
  for (const auto& [id, p] : landmarks) {
    if (id < 0 || id > std::numeric_limits<int>::max())
      throw InputError("landmark id " + std::to_string(id) + " does not fit MRPT's int");
    text += format("%10f %10f %10f %4i %4u %10f", noNegativeZero(p.x()), noNegativeZero(p.y()), 0.0,
                   5, 0u, 0.0);
    text += format(" %i \n", static_cast<int>(id));
  }
  return text;
}

std::string groundTruthPathText(const std::vector<Pose2>& path) {
  // Same layout as MRPT's CMatrixDouble::saveToTextFile(MATRIX_FORMAT_FIXED) in simul-landmarks,
  // without the generation date so that the same input gives the same bytes.
  std::string text =
      "% Columns are: x(m) y(m) z(m) yaw(rad) pitch(rad) roll(rad)\n"
      "% File generated with budget-slam\n"
      "\n"
      "%------------------------------------\n";
  for (const auto& p : path)
    text += format("%.16f %.16f %.16f %.16f %.16f %.16f\n", noNegativeZero(p.x),
                   noNegativeZero(p.y), 0.0, noNegativeZero(p.phi), 0.0, 0.0);
  return text;
}

void saveGroundTruthLandmarks(const std::string& file,
                              const std::map<LandmarkId, Eigen::Vector2d>& landmarks) {
  writeFileAtomically(file, groundTruthLandmarksText(landmarks));
}

void saveGroundTruthPath(const std::string& file, const std::vector<Pose2>& path) {
  writeFileAtomically(file, groundTruthPathText(path));
}

}  // namespace budget_slam::dataset
