#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPoint2D.h>
#include <mrpt/poses/CPose2D.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "../TextTable.h"
#include "ConvertCommon.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/core/MrptPose.h"
#include "budget_slam/dataset/Converters.h"
#include "budget_slam/dataset/StepToMrpt.h"

namespace budget_slam::dataset {
namespace {

using mrpt::poses::CPose2D;

struct Timed {
  double t;
  double a, b, c;  // odometry: v w -; ground truth: x y theta; measurement: barcode range bearing
  std::size_t line;
};

/// A column of a UTIAS file: its name and the largest magnitude it may take.
struct Column {
  const char* name;
  double limit;
};

/// The largest barcode read (the dataset's are two-digit; a double holds integers exactly to
/// 2^53).
constexpr double kMaxBarcode = 1e9;

/// The records of a time-ordered UTIAS file with `columns` after the time.
std::vector<Timed> readTimed(const std::string& file, const std::string& what,
                             const std::vector<Column>& columns) {
  std::vector<Timed> out;
  TextTable t(file);
  while (t.next()) {
    t.expectFields(columns.size() + 1, what);
    Timed r{t.bounded(0, "time", limits::kMaxTime), 0, 0, 0, t.line()};
    double* dst[3] = {&r.a, &r.b, &r.c};
    for (std::size_t i = 0; i < columns.size(); ++i)
      *dst[i] = t.bounded(i + 1, columns[i].name, columns[i].limit);
    if (!out.empty() && r.t < out.back().t)
      t.fail("time " + t.word(0) + " is earlier than the previous record's");
    out.push_back(r);
  }
  if (out.empty()) throw InputError(file + ": no data records");
  return out;
}

/// One robot's three time-ordered files.
struct RobotFiles {
  std::string odometry, groundtruth, measurement;
};

/// The files of a UTIAS folder (docs/DATASETS.md "UTIAS MR.CLAM"), each in either form: MRCLAM's
/// own `Name.dat` (or `Name.dat.gz`), whitespace-separated, or `Name.csv`, comma-separated with a
/// header line, as other projects ship it. A robot's files are `RobotN_Name`; a folder of one
/// robot may name them `Name` alone.
struct UtiasFiles {
  std::string barcodes, landmarks;
  RobotFiles robot, frame;  ///< frame: the --frame-robot's, when one is given
};

/// There, and not a folder (a device or a FIFO is read, and refused for what it holds).
bool isFile(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && !S_ISDIR(st.st_mode);
}

/// `dir + name` with the extension it has (.dat also for .dat.gz: TextTable reads either), or ""
/// when none is there.
std::string findForm(const std::string& dir, const std::string& name) {
  if (isFile(dir + name + ".dat") || isFile(dir + name + ".dat.gz")) return dir + name + ".dat";
  if (isFile(dir + name + ".csv")) return dir + name + ".csv";
  return "";
}

/// Every file of the folder found, or one InputError naming every missing one at once.
UtiasFiles findUtiasFiles(const std::string& folder, const std::string& dir, int robot,
                          int frame_robot) {
  std::vector<std::string> missing;
  const auto need = [&](const std::string& name, const std::string& alone = "") {
    std::string path = findForm(dir, name);
    if (path.empty() && !alone.empty()) path = findForm(dir, alone);
    if (path.empty()) missing.push_back(name + (alone.empty() ? "" : " (or " + alone + ")"));
    return path;
  };
  const auto robotFiles = [&](int n, bool may_be_alone) {
    const std::string r = "Robot" + std::to_string(n) + "_";
    const auto alone = [&](const char* name) { return may_be_alone ? std::string(name) : ""; };
    RobotFiles f;
    f.odometry = need(r + "Odometry", alone("Odometry"));
    f.groundtruth = need(r + "Groundtruth", alone("Groundtruth"));
    f.measurement = need(r + "Measurement", alone("Measurement"));
    return f;
  };
  UtiasFiles files;
  files.barcodes = need("Barcodes");
  files.landmarks = need("Landmark_Groundtruth");
  files.robot = robotFiles(robot, true);
  if (frame_robot != 0) files.frame = robotFiles(frame_robot, false);
  if (!missing.empty()) {
    std::string list;
    for (const auto& m : missing) list += (list.empty() ? "" : ", ") + m;
    throw InputError("UTIAS folder '" + folder + "': missing " + list +
                     " (each as .dat, .dat.gz or .csv; docs/DATASETS.md shows the layout)");
  }
  return files;
}

/// One robot's three time-ordered files' records.
struct RobotRecords {
  std::vector<Timed> odo, gt, meas;
};

RobotRecords readRobot(const RobotFiles& f) {
  RobotRecords r;
  r.odo = readTimed(f.odometry, "odometry record (time v omega)",
                    {{"v", limits::kMaxSpeed}, {"omega", limits::kMaxSpeed}});
  r.gt = readTimed(
      f.groundtruth, "ground-truth record (time x y theta)",
      {{"x", limits::kMaxCoordinate}, {"y", limits::kMaxCoordinate}, {"theta", limits::kMaxAngle}});
  r.meas = readTimed(
      f.measurement, "measurement record (time barcode range bearing)",
      {{"barcode", kMaxBarcode}, {"range", limits::kMaxRange}, {"bearing", limits::kMaxAngle}});
  return r;
}

/// Pose change of a unicycle driving at v [m/s], w [rad/s] for dt [s] (exact arc).
CPose2D arc(double v, double w, double dt) {
  const double th = w * dt;
  if (std::abs(th) < 1e-9) return CPose2D(v * dt * std::cos(th / 2), v * dt * std::sin(th / 2), th);
  const double r = v / w;
  return CPose2D(r * std::sin(th), r * (1 - std::cos(th)), th);
}

/// Integrates the odometry records (each holds from its time to the next record's) over [t0, t1].
CPose2D integrate(const std::vector<Timed>& odo, double t0, double t1) {
  CPose2D p;
  auto it = std::upper_bound(odo.begin(), odo.end(), t0,
                             [](double t, const Timed& r) { return t < r.t; });
  if (it != odo.begin()) --it;
  for (; it != odo.end() && it->t < t1; ++it) {
    const double from = std::max(t0, it->t);
    const double to = std::next(it) == odo.end() ? t1 : std::min(t1, std::next(it)->t);
    if (to > from) p = p + arc(it->a, it->b, to - from);
  }
  return p;
}

/// Ground-truth pose at time t: linear interpolation (shortest turn for the heading), clamped to
/// the first and last record.
CPose2D groundTruthAt(const std::vector<Timed>& gt, double t) {
  if (t <= gt.front().t) return CPose2D(gt.front().a, gt.front().b, gt.front().c);
  if (t >= gt.back().t) return CPose2D(gt.back().a, gt.back().b, gt.back().c);
  const auto hi =
      std::upper_bound(gt.begin(), gt.end(), t, [](double x, const Timed& r) { return x < r.t; });
  const auto lo = std::prev(hi);
  const double a = (t - lo->t) / (hi->t - lo->t);
  const double dth = mrpt::math::wrapToPi(hi->c - lo->c);
  return CPose2D(lo->a + a * (hi->a - lo->a), lo->b + a * (hi->b - lo->b), lo->c + a * dth);
}

/// 1.4826 x median absolute deviation: a standard deviation that outliers (false barcode reads,
/// Vicon dropouts) do not inflate.
double robustStd(std::vector<double> v) {
  if (v.empty()) return 0;
  auto median = [](std::vector<double> x) {
    std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
    return x[x.size() / 2];
  };
  const double m = median(v);
  for (auto& x : v) x = std::abs(x - m);
  return 1.4826 * median(v);
}

/// The true pose of `robot` when it first sights a landmark (a known barcode of subject 6 or
/// more) at or after its first odometry record: the start pose convertUtias gives that robot.
CPose2D trueStartPose(const RobotFiles& files, const std::map<long long, long long>& subject_of) {
  const auto [odo, gt, meas] = readRobot(files);
  for (const auto& m : meas) {
    const auto s = subject_of.find(static_cast<long long>(m.a));
    if (m.t >= odo.front().t && s != subject_of.end() && s->second > 5)
      return groundTruthAt(gt, m.t);
  }
  throw InputError(files.measurement + ": no landmark sighting");
}

}  // namespace

ConvertedDataset convertUtias(const std::string& folder, int robot, int frame_robot) {
  if (robot < 1 || robot > 5)
    throw InputError("UTIAS robot number must be 1 to 5, found " + std::to_string(robot));
  if (frame_robot != 0 && (frame_robot < 1 || frame_robot > 5))
    throw InputError("UTIAS frame robot number must be 1 to 5, found " +
                     std::to_string(frame_robot));
  if (frame_robot == robot) frame_robot = 0;
  const std::string dir = folder.empty() || folder.back() == '/' ? folder : folder + "/";
  const UtiasFiles files = findUtiasFiles(folder, dir, robot, frame_robot);
  const std::string& measurement = files.robot.measurement;

  // Barcodes.dat: subject barcode. Subjects 1-5 are the robots, 6-20 the landmarks.
  std::map<long long, long long> subject_of;  // barcode -> subject
  {
    TextTable t(files.barcodes);
    while (t.next()) {
      t.expectFields(2, "barcode record (subject barcode)");
      const long long subject = t.landmarkId(0, "subject"), barcode = t.integer(1, "barcode");
      if (subject_of.count(barcode))
        t.fail("barcode " + std::to_string(barcode) + " is given to two subjects");
      subject_of[barcode] = subject;
    }
  }
  std::map<LandmarkId, Eigen::Vector2d> landmarks_world;
  {
    TextTable t(files.landmarks);
    while (t.next()) {
      t.expectFields(5, "landmark record (subject x y sx sy)");
      const long long subject = t.landmarkId(0, "subject");
      if (landmarks_world.count(subject))
        t.fail("landmark subject " + std::to_string(subject) + " appears twice");
      landmarks_world[subject] = Eigen::Vector2d(t.bounded(1, "x", limits::kMaxCoordinate),
                                                 t.bounded(2, "y", limits::kMaxCoordinate));
      t.bounded(3, "sx", limits::kMaxCoordinate), t.bounded(4, "sy", limits::kMaxCoordinate);
    }
  }
  const auto [odo, gt, meas] = readRobot(files.robot);

  // Steps: one per measurement time with at least one landmark sighting, from the first odometry
  // record on. The start pose is the pose of the first step (its motion is zero): MRPT's 2D EKF
  // does not predict while its map is empty, so its frame is the pose of the first sighting.
  const double t_odo = odo.front().t;
  std::vector<double> times;
  std::vector<std::size_t> lines;  // Measurement.dat line of each step's first sighting
  std::vector<std::vector<RangeBearingReading>> readings;
  std::size_t robots_left_out = 0, unknown_left_out = 0, early_left_out = 0;
  std::vector<RangeBearingReading> all;
  for (const auto& m : meas) {
    if (m.a != std::floor(m.a))
      throw InputError(measurement + ":" + std::to_string(m.line) + ": barcode is not an integer");
    if (m.b < 0)
      throw InputError(measurement + ":" + std::to_string(m.line) + ": range must not be negative");
    const auto s = subject_of.find(static_cast<long long>(m.a));
    if (s == subject_of.end()) {
      ++unknown_left_out;
      continue;
    }
    if (s->second <= 5) {
      ++robots_left_out;
      continue;
    }
    if (m.t < t_odo) {
      ++early_left_out;
      continue;
    }
    if (times.empty() || m.t != times.back()) {
      if (times.size() >= limits::kMaxSteps)
        throw InputError(measurement + ":" + std::to_string(m.line) + ": more than " +
                         std::to_string(limits::kMaxSteps) + " steps in one conversion");
      times.push_back(m.t);
      lines.push_back(m.line);
      readings.emplace_back();
    }
    auto& rs = readings.back();
    const LandmarkId id = s->second;
    if (std::any_of(rs.begin(), rs.end(), [&](const auto& r) { return r.id == id; }))
      throw InputError(measurement + ":" + std::to_string(m.line) + ": landmark " +
                       std::to_string(id) + " seen twice at time " + std::to_string(m.t));
    rs.push_back({id, m.b, m.c, 0});
    all.push_back(rs.back());
  }
  if (times.empty()) throw InputError(measurement + ": no landmark sighting");

  const double t0 = times.front();
  ConvertedDataset out;
  // Ground truth in the frame of the true start pose (the filter starts at the origin).
  const CPose2D start = groundTruthAt(gt, t0);
  out.ground_truth.path.push_back(Pose2(0, 0, 0));
  std::vector<CPose2D> true_at;
  for (double t : times) {
    true_at.push_back(groundTruthAt(gt, t) - start);
    out.ground_truth.path.push_back(toPose2(true_at.back().asTPose()));
  }
  for (const auto& [id, p] : landmarks_world) {
    const auto local = mrpt::poses::CPoint2D(p.x(), p.y()) - start;
    out.ground_truth.landmarks[id] = Eigen::Vector2d(local.x(), local.y());
  }

  // Sensor noise: robust spread of the readings about what the ground truth predicts.
  std::vector<double> er, eb;
  for (std::size_t k = 0; k < times.size(); ++k)
    for (const auto& r : readings[k]) {
      const auto it = out.ground_truth.landmarks.find(r.id);
      if (it == out.ground_truth.landmarks.end()) continue;
      const auto rel = mrpt::poses::CPoint2D(it->second.x(), it->second.y()) - true_at[k];
      er.push_back(r.range - std::hypot(rel.x(), rel.y()));
      eb.push_back(mrpt::math::wrapToPi(r.yaw - std::atan2(rel.y(), rel.x())));
    }
  out.noise.std_range = robustStd(er);
  out.noise.std_yaw = robustStd(eb);
  convert::limitsFromReadings(all, out.noise);
  convert::checkSensorNoise(out.noise, measurement);

  // Odometry increments, and their noise: a random walk whose variance grows with time,
  // q = sum of squared errors against ground truth / sum of durations (per axis).
  std::vector<CPose2D> inc;
  double sx = 0, sy = 0, sth = 0, st = 0;
  double prev_t = t0;
  CPose2D prev_true;
  for (std::size_t k = 0; k < times.size(); ++k) {
    inc.push_back(integrate(odo, prev_t, times[k]));
    // Speeds are bounded, durations are not: a gap in time can integrate to an impossible step.
    if (!(std::abs(inc.back().x()) <= limits::kMaxStepTranslation &&
          std::abs(inc.back().y()) <= limits::kMaxStepTranslation))
      throw InputError(measurement + ":" + std::to_string(lines[k]) +
                       ": the odometry since the previous step integrates to (" +
                       std::to_string(inc.back().x()) + ", " + std::to_string(inc.back().y()) +
                       ") m, more than " +
                       std::to_string(static_cast<long long>(limits::kMaxStepTranslation)) +
                       " m in one step");
    const CPose2D true_inc = true_at[k] - prev_true;
    sx += std::pow(inc.back().x() - true_inc.x(), 2);
    sy += std::pow(inc.back().y() - true_inc.y(), 2);
    sth += std::pow(mrpt::math::wrapToPi(inc.back().phi() - true_inc.phi()), 2);
    st += times[k] - prev_t;
    prev_t = times[k];
    prev_true = true_at[k];
  }
  const double qxy = st > 0 ? (sx + sy) / (2 * st) : 0, qth = st > 0 ? sth / st : 0;
  prev_t = t0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    OdometryIncrement o;
    o.mean = toPose2(inc[k].asTPose());
    const double dt = times[k] - prev_t;
    // At least 1e-6 m / rad std, so that the zero first step stays invertible for a graph.
    o.cov = Eigen::Vector3d(std::max(qxy * dt, 1e-12), std::max(qxy * dt, 1e-12),
                            std::max(qth * dt, 1e-12))
                .asDiagonal();
    if (!(o.cov.maxCoeff() <= limits::kMaxVariance))
      throw InputError(measurement + ":" + std::to_string(lines[k]) +
                       ": the odometry noise fitted to the ground truth gives this step a "
                       "variance above 1e24");
    RangeBearingScan scan = convert::emptyScan(out.noise);
    scan.readings = readings[k];
    out.steps.push_back(makeStep(k, times[k], o, scan));
    prev_t = times[k];
  }

  // Another robot's start frame: the robots of one dataset then share a world frame (a map made
  // by one is the frame the others' ground truth is compared in).
  if (frame_robot != 0) {
    const CPose2D frame = trueStartPose(files.frame, subject_of);
    for (auto& p : out.ground_truth.path)
      p = toPose2(((start + CPose2D(toTPose2D(p))) - frame).asTPose());
    for (auto& [id, l] : out.ground_truth.landmarks) {
      const auto q = (start + mrpt::poses::CPoint2D(l.x(), l.y())) - frame;
      l = Eigen::Vector2d(q.x(), q.y());
    }
  }

  char buf[256];
  std::snprintf(buf, sizeof buf,
                "Odometry noise fitted to ground truth: variance %.3g m^2/s (x, y), %.3g "
                "rad^2/s (yaw) x step duration.",
                qxy, qth);
  out.notes = {
      "Made by budget-convert --format utias from " + convert::baseName(folder) + ", robot " +
          std::to_string(robot) + ".",
      "One step per measurement time with a landmark sighting; odometry (v, omega) integrated",
      "exactly (constant between records) between step times; the first step (zero motion)",
      "defines the start pose. Times: Unix seconds.",
      "Landmark ids: subject numbers through Barcodes.dat. Left out: sightings of robots",
      "(subjects 1-5): " + std::to_string(robots_left_out) +
          ", of unknown barcodes: " + std::to_string(unknown_left_out) +
          ", before the first odometry record: " + std::to_string(early_left_out) + ".",
      frame_robot == 0
          ? "Ground truth (Vicon) in the frame of the robot's true start pose."
          : "Ground truth (Vicon) in the frame of robot " + std::to_string(frame_robot) +
                "'s true start pose (--frame-robot " + std::to_string(frame_robot) + ").",
      "Sensor noise fitted to ground truth: 1.4826 x MAD of range and bearing residuals.",
      buf,
  };
  return out;
}

}  // namespace budget_slam::dataset
