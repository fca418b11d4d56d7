#include "budget_slam/dataset/RawlogReader.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>

#include <sys/stat.h>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "budget_slam/core/Error.h"

namespace budget_slam::dataset {
namespace {

/// Counts the uncompressed bytes taken from the inner stream, so that an end of file met in
/// the middle of an object (a truncated rawlog) can be told from one met between objects.
class CountingStream : public mrpt::io::CStream {
 public:
  explicit CountingStream(mrpt::io::CStream& inner) : inner_(inner) {}
  size_t Read(void* buf, size_t n) override {
    const size_t got = inner_.Read(buf, n);
    count_ += got;
    return got;
  }
  size_t Write(const void*, size_t) override { return 0; }
  uint64_t Seek(int64_t, CStream::TSeekOrigin) override { return count_; }
  uint64_t getTotalBytesCount() const override { return inner_.getTotalBytesCount(); }
  uint64_t getPosition() const override { return count_; }
  uint64_t count() const { return count_; }

 private:
  mrpt::io::CStream& inner_;
  uint64_t count_ = 0;
};

std::string trim(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  const auto b = s.find_first_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b);
}

/// MRPT nests exceptions ("Exception while parsing typed object 'X'" ... "Message: <cause>")
/// with call stacks; a one-line error wants the outermost object and the innermost cause.
std::string describeMrptError(const std::string& what) {
  std::string outer_object, cause;
  std::istringstream in(what);
  const std::string kParsing = "parsing typed object '";
  for (std::string line; std::getline(in, line);) {
    const auto m = line.find("Message:");
    if (m == std::string::npos) continue;
    const std::string msg = trim(line.substr(m + 8));
    const auto p = msg.find(kParsing);
    if (p != std::string::npos && outer_object.empty()) {
      const auto e = msg.find('\'', p + kParsing.size());
      const std::string obj = msg.substr(p + kParsing.size(), e - p - kParsing.size());
      if (obj.rfind("mrpt::", 0) == 0) outer_object = obj;
    }
    cause = msg;  // the last message is the innermost cause
  }
  if (cause.empty()) cause = trim(what.substr(0, what.find('\n')));
  if (cause.find("EOF") != std::string::npos)
    return outer_object.empty() ? "the file ends inside an object"
                                : "the file ends inside a " + outer_object;
  return outer_object.empty() ? cause : "bad data inside a " + outer_object + ": " + cause;
}

Eigen::Matrix3d toEigen(const mrpt::math::CMatrixDouble33& m) {
  Eigen::Matrix3d e;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) e(r, c) = m(r, c);
  return e;
}

std::optional<double> timestampOf(const mrpt::obs::CActionCollection::Ptr& action,
                                  const mrpt::obs::CSensoryFrame::Ptr& frame) {
  if (frame)
    for (const auto& obs : *frame)
      if (obs && obs->timestamp != INVALID_TIMESTAMP) return mrpt::Clock::toDouble(obs->timestamp);
  if (action)
    for (size_t i = 0; i < action->size(); ++i) {
      const auto a = action->get(i);
      if (a && a->timestamp != INVALID_TIMESTAMP) return mrpt::Clock::toDouble(a->timestamp);
    }
  return std::nullopt;
}

}  // namespace

Step parseStep(const mrpt::obs::CActionCollection::Ptr& action,
               const mrpt::obs::CSensoryFrame::Ptr& frame, StepIndex index, double t_fallback) {
  Step step;
  step.index = index;
  step.action = action;
  step.frame = frame;
  const auto ts = timestampOf(action, frame);
  step.t = ts ? *ts : t_fallback;

  if (action) {
    // Same precedence as MRPT's CRangeBearingKFSLAM2D::OnGetAction: 3D movement first.
    const auto mov3d = action->getActionByClass<mrpt::obs::CActionRobotMovement3D>();
    const auto mov2d = action->getBestMovementEstimation();
    if (mov3d) {
      OdometryIncrement odo;
      odo.mean = mrpt::poses::CPose2D(mov3d->poseChange.mean).asTPose();
      // Rows/cols x, y, yaw of the 6x6 (x y z yaw pitch roll) covariance.
      const int idx[3] = {0, 1, 3};
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) odo.cov(r, c) = mov3d->poseChange.cov(idx[r], idx[c]);
      step.odometry = odo;
    } else if (mov2d && mov2d->poseChange) {
      OdometryIncrement odo;
      mrpt::poses::CPose2D mean;
      mrpt::math::CMatrixDouble33 cov;
      mov2d->poseChange->getCovarianceAndMean(cov, mean);
      odo.mean = mean.asTPose();
      odo.cov = toEigen(cov);
      step.odometry = odo;
    }
  }

  if (frame) {
    // MRPT's 2D EKF uses the first bearing-range observation of the frame.
    const auto obs = frame->getObservationByClass<mrpt::obs::CObservationBearingRange>();
    if (obs) {
      RangeBearingScan scan;
      scan.sensor_pose_on_robot = obs->sensorLocationOnRobot.asTPose();
      scan.min_range = obs->minSensorDistance;
      scan.max_range = obs->maxSensorDistance;
      scan.fov_yaw = obs->fieldOfView_yaw;
      scan.std_range = obs->sensor_std_range;
      scan.std_yaw = obs->sensor_std_yaw;
      scan.readings.reserve(obs->sensedData.size());
      for (const auto& m : obs->sensedData)
        scan.readings.push_back(
            {m.landmarkID < 0 ? kNoLandmarkId : LandmarkId(m.landmarkID), m.range, m.yaw, m.pitch});
      step.scan = std::move(scan);
    }
  }
  return step;
}

struct RawlogReader::Impl {
  mrpt::io::CFileGZInputStream file;
  std::unique_ptr<CountingStream> counter;
};

RawlogReader::RawlogReader(const std::string& path) : impl_(std::make_unique<Impl>()), path_(path) {
  const std::string who = "rawlog '" + path + "'";
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw InputError(who + ": no such file");
  if (S_ISDIR(st.st_mode)) throw InputError(who + ": is a directory, not a file");
  if (!std::ifstream(path, std::ios::binary).good())
    throw InputError(who + ": cannot be read (permission denied)");
  if (st.st_size == 0) throw InputError(who + ": empty file, not an MRPT rawlog");
  std::string err;
  if (!impl_->file.open(path, err)) throw InputError(who + ": cannot be opened (" + err + ")");
  impl_->counter = std::make_unique<CountingStream>(impl_->file);
}

RawlogReader::~RawlogReader() = default;

double RawlogReader::progress() const {
  const double total = static_cast<double>(impl_->file.getTotalBytesCount());
  return total > 0 ? std::min(1.0, impl_->file.getPosition() / total) : 0.0;
}

std::optional<Step> RawlogReader::next() {
  auto arch = mrpt::serialization::archiveFrom(*impl_->counter);
  mrpt::obs::CActionCollection::Ptr action;
  mrpt::obs::CSensoryFrame::Ptr frame;
  // The pairing rule of MRPT's CRawlog::readActionObservationPair (what kf-slam reads): skip to
  // the next action, then to the next sensory frame. Other objects are passed over.
  while (!frame) {
    const uint64_t before = impl_->counter->count();
    mrpt::serialization::CSerializable::Ptr obj;
    try {
      arch >> obj;
    } catch (const std::exception& e) {
      // Nothing consumed: the file ended between objects. MRPT's own rawlogs may end with an
      // action that has no frame after it; kf-slam ignores it, and so do we.
      const bool clean_eof = impl_->counter->count() == before;
      if (clean_eof) {
        if (steps_ == 0 && before == 0)
          throw InputError("rawlog '" + path_ + "': not an MRPT rawlog (no objects in it)");
        return std::nullopt;
      }
      if (steps_ == 0 && !action)
        throw InputError("rawlog '" + path_ +
                         "': not an MRPT rawlog (no serialized MRPT object at its start)");
      throw InputError("rawlog '" + path_ + "': truncated or corrupt at step " +
                       std::to_string(steps_) + " (" + describeMrptError(e.what()) + ")");
    }
    if (!obj) continue;
    if (auto a = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
      if (!action) action = a;  // MRPT keeps the first action and waits for a frame
      continue;
    }
    if (auto f = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
      if (action) frame = f;
      continue;
    }
    if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
      throw InputError("rawlog '" + path_ + "': observations-format rawlog (a " +
                       o->GetRuntimeClass()->className +
                       " outside any sensory frame); budget-slam reads the actions-observations "
                       "format that kf-slam reads");
    }
  }

  for (const auto& obs : *frame)
    if (obs) {
      const std::string cls = obs->GetRuntimeClass()->className;  // "mrpt::obs::CObservationX"
      observation_classes_.insert(cls.substr(cls.rfind(':') + 1));
    }

  // Timestamps: MRPT's own when usable and increasing, else one second a step (TUM readers
  // need strictly increasing times).
  double fallback = last_t_ ? *last_t_ + 1.0 : 0.0;
  Step step = parseStep(action, frame, steps_, fallback);
  if (last_t_ && step.t <= *last_t_) step.t = *last_t_ + 1e-3;
  last_t_ = step.t;

  if (step.odometry) {
    const auto& m = step.odometry->mean;
    if (!std::isfinite(m.x) || !std::isfinite(m.y) || !std::isfinite(m.phi) ||
        !step.odometry->cov.allFinite())
      throw InputError("rawlog '" + path_ + "': step " + std::to_string(steps_) +
                       ": odometry has a non-finite value");
  }
  if (step.scan) {
    ++bearing_range_steps_;
    const auto& rs = step.scan->readings;
    for (size_t i = 0; i < rs.size(); ++i) {
      const std::string where = "rawlog '" + path_ + "': step " + std::to_string(steps_) +
                                ": reading " + std::to_string(i);
      if (!std::isfinite(rs[i].range) || rs[i].range < 0)
        throw InputError(where + " has a negative or non-finite range (" +
                         std::to_string(rs[i].range) + ")");
      if (!std::isfinite(rs[i].yaw) || !std::isfinite(rs[i].pitch))
        throw InputError(where + " has a non-finite bearing");
      if (rs[i].pitch != 0)
        throw InputError(where + " has a non-zero pitch (a 3D sensor); budget-slam is 2D");
    }
  }
  ++steps_;
  return step;
}

std::vector<Step> readAllSteps(const std::string& path) {
  RawlogReader reader(path);
  std::vector<Step> steps;
  while (auto s = reader.next()) steps.push_back(std::move(*s));
  return steps;
}

}  // namespace budget_slam::dataset
