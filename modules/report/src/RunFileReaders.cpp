#include "budget_slam/report/RunFileReaders.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/core/Text.h"

namespace budget_slam::report {
namespace {

/// Lines longer than this are not what budget-slam writes (and would be read whole otherwise).
constexpr std::size_t kMaxLine = 4096;

/// A text file read line by line with its line number, every error naming both.
class Lines {
 public:
  explicit Lines(const std::string& path) : path_(path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
      throw InputError(path + ": cannot open (no such file)");
    in_.open(path);
    if (!in_) throw InputError(path + ": cannot open (not readable)");
  }
  bool next(std::string& line) {
    line.clear();
    char c;
    bool any = false;
    while (in_.get(c)) {
      any = true;
      if (c == '\n') break;
      if (line.size() == kMaxLine) fail("line longer than " + std::to_string(kMaxLine) + " bytes");
      line.push_back(c);
    }
    if (!any) return false;
    ++n_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_ + ":" + std::to_string(n_ + (n_ == 0)) + ": " + what);
  }
  std::size_t line() const { return n_; }

 private:
  std::string path_;
  std::ifstream in_;
  std::size_t n_ = 0;
};

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  if (sep == ' ') {
    std::istringstream ss(line);
    for (std::string w; ss >> w;) out.push_back(w);
    return out;
  }
  std::string cell;
  std::istringstream ss(line);
  while (std::getline(ss, cell, sep)) out.push_back(cell);
  if (!line.empty() && line.back() == sep) out.emplace_back();
  return out;
}

double finite(const Lines& l, const std::string& word, const char* name) {
  const char* b = word.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(b, &end);
  if (word.empty() || end != b + word.size() || !std::isfinite(v))
    l.fail(std::string(name) + " is not a finite number: '" + excerpt(word) + "'");
  return v;
}

/// A finite number of magnitude at most `limit` (core/InputLimits.h).
double bounded(const Lines& l, const std::string& word, const char* name, double limit) {
  const double v = finite(l, word, name);
  if (std::abs(v) > limit) {
    char text[64];
    std::snprintf(text, sizeof text, " is out of range (at most %g either way)", limit);
    l.fail(std::string(name) + " = " + excerpt(word) + text);
  }
  return v;
}

long long nonNegativeInteger(const Lines& l, const std::string& word, const char* name) {
  const double v = finite(l, word, name);
  if (v < 0 || v != std::floor(v) || v > 9.0e15)
    l.fail(std::string(name) + " is not a non-negative integer: '" + word + "'");
  return static_cast<long long>(v);
}

}  // namespace

std::vector<LandmarkView> readLandmarksCsv(const std::string& path, std::size_t max_rows) {
  static const char* kHeader =
      "id,x,y,cov_xx,cov_xy,cov_yy,n_obs,obs_mean_x,obs_mean_y,first_step,last_step";
  Lines in(path);
  std::string line;
  if (!in.next(line)) in.fail("empty file (expected the header '" + std::string(kHeader) + "')");
  // Later versions may add columns after these; the rows must then have as many cells.
  if (line.compare(0, std::strlen(kHeader), kHeader) != 0 ||
      (line.size() > std::strlen(kHeader) && line[std::strlen(kHeader)] != ','))
    in.fail("not a budget-slam landmarks.csv header: '" + excerpt(line, 80) + "'");
  const std::size_t columns = split(line, ',').size();
  std::vector<LandmarkView> out;
  std::set<LandmarkId> ids;
  while (in.next(line)) {
    if (line.empty()) continue;
    const auto c = split(line, ',');
    if (c.size() != columns)
      in.fail("expected " + std::to_string(columns) + " cells (" + std::string(kHeader) +
              "), found " + std::to_string(c.size()));
    if (out.size() == max_rows) in.fail("more than " + std::to_string(max_rows) + " landmarks");
    LandmarkView v;
    v.id = nonNegativeInteger(in, c[0], "id");
    if (v.id > limits::kMaxLandmarkId)
      in.fail("id " + c[0] + " is not a landmark id (0 to " +
              std::to_string(limits::kMaxLandmarkId) + ")");
    if (!ids.insert(v.id).second) in.fail("landmark id " + c[0] + " appears twice");
    v.mean = Eigen::Vector2d(bounded(in, c[1], "x", limits::kMaxCoordinate),
                             bounded(in, c[2], "y", limits::kMaxCoordinate));
    const double xx = bounded(in, c[3], "cov_xx", limits::kMaxVariance),
                 xy = bounded(in, c[4], "cov_xy", limits::kMaxVariance),
                 yy = bounded(in, c[5], "cov_yy", limits::kMaxVariance);
    if (xx < 0 || yy < 0 || xy * xy > xx * yy * (1 + 1e-9) + 1e-300)
      in.fail("covariance (cov_xx, cov_xy, cov_yy) = (" + excerpt(c[3]) + ", " + excerpt(c[4]) +
              ", " + excerpt(c[5]) + ") is not positive semi-definite");
    v.cov << xx, xy, xy, yy;
    v.n_obs = static_cast<std::size_t>(nonNegativeInteger(in, c[6], "n_obs"));
    v.obs_mean = Eigen::Vector2d(bounded(in, c[7], "obs_mean_x", limits::kMaxCoordinate),
                                 bounded(in, c[8], "obs_mean_y", limits::kMaxCoordinate));
    v.first_step = static_cast<StepIndex>(nonNegativeInteger(in, c[9], "first_step"));
    v.last_step = static_cast<StepIndex>(nonNegativeInteger(in, c[10], "last_step"));
    out.push_back(v);
  }
  return out;
}

std::vector<TrajectoryPoint> readTrajectoryTum(const std::string& path, std::size_t max_rows) {
  Lines in(path);
  std::string line;
  std::vector<TrajectoryPoint> out;
  while (in.next(line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto w = split(line, ' ');
    if (w.size() != 8)
      in.fail("expected 8 numbers (t x y z qx qy qz qw), found " + std::to_string(w.size()));
    if (out.size() == max_rows) in.fail("more than " + std::to_string(max_rows) + " poses");
    double v[8];
    static const char* names[8] = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};
    static const double limit[8] = {limits::kMaxTime,
                                    limits::kMaxCoordinate,
                                    limits::kMaxCoordinate,
                                    limits::kMaxCoordinate,
                                    2,
                                    2,
                                    2,
                                    2};
    for (int i = 0; i < 8; ++i) v[i] = bounded(in, w[i], names[i], limit[i]);
    if (!out.empty() && !(v[0] > out.back().t)) in.fail("time " + w[0] + " does not increase");
    const double norm = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (!(norm > 0.5 && norm < 1.5)) in.fail("quaternion is not of unit length");
    // Yaw of the quaternion's rotation (about z for every budget-slam trajectory).
    const double yaw =
        std::atan2(2 * (v[7] * v[6] + v[4] * v[5]), 1 - 2 * (v[5] * v[5] + v[6] * v[6]));
    out.push_back({out.size(), v[0], Pose2(v[1], v[2], yaw)});
  }
  return out;
}

}  // namespace budget_slam::report
