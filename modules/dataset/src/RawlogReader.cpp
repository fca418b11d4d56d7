#include "budget_slam/dataset/RawlogReader.h"

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/system/datetime.h>

#include <sys/stat.h>
#include <cmath>
#include <fstream>
#include <utility>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/MrptPose.h"
#include "rawlog/ByteSource.h"
#include "rawlog/ObjectChecker.h"
#include "rawlog/ObjectDecoder.h"
#include "rawlog/ObjectStream.h"
#include "rawlog/ObservationOdometry.h"
#include "rawlog/ReadFailure.h"

namespace budget_slam::dataset {
namespace {

using rawlog::ReadFailure;
using Kind = ReadFailure::Kind;
using mrpt::obs::CActionCollection;
using mrpt::obs::CObservation;
using mrpt::obs::CObservationOdometry;
using mrpt::obs::CSensoryFrame;

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

std::string shortName(const CObservation& obs) {
  const std::string cls = obs.GetRuntimeClass()->className;  // "mrpt::obs::CObservationX"
  return cls.substr(cls.rfind(':') + 1);
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
      odo.mean = toPose2(mrpt::poses::CPose2D(mov3d->poseChange.mean).asTPose());
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
      odo.mean = toPose2(mean.asTPose());
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

enum class Format { kUnknown, kActionsObservations, kObservations };

struct RawlogReader::Impl {
  std::unique_ptr<rawlog::ObjectStream> stream;
  std::unique_ptr<rawlog::ObjectChecker> checker;
  std::function<bool()> stop;
  Format format = Format::kUnknown;
  std::size_t objects = 0;  // top-level objects read
  std::size_t current = 0;  // the object being handled: its entry in the file, from 0
  std::size_t pending_entry = 0;
  /// An object read ahead (to tell the formats apart) and not handled yet; a null Ptr inside
  /// the optional is a stored null object, an empty optional with `pending_end` the end.
  std::optional<mrpt::serialization::CSerializable::Ptr> pending;
  bool pending_end = false;
  CActionCollection::Ptr action;  // actions-observations: the action waiting for its frame
  rawlog::ObservationOdometry odometry;
  std::set<std::string> used_classes, passed_over_classes;

  /// The next top-level object (nullptr for a stored null object); std::nullopt at the end.
  std::optional<mrpt::serialization::CSerializable::Ptr> nextObject() {
    if (pending) {
      auto p = std::move(pending);
      pending.reset();
      current = pending_entry;
      return p;
    }
    if (pending_end) return std::nullopt;
    if (stop && stop()) throw rawlog::ReadStopped{};
    if (!stream->beginObject()) return std::nullopt;
    checker->checkTopLevel();
    auto obj = rawlog::decodeObject(stream->objectData(), stream->objectSize());
    current = objects++;
    return obj;
  }

  void record(const CSensoryFrame& frame, std::set<std::string>& into) {
    for (const auto& obs : frame)
      if (obs) into.insert(shortName(*obs));
  }
};

RawlogReader::RawlogReader(const std::string& path) : impl_(std::make_unique<Impl>()), path_(path) {
  const std::string who = "rawlog '" + path + "'";
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw InputError(who + ": no such file");
  if (S_ISDIR(st.st_mode)) throw InputError(who + ": is a directory, not a file");
  if (!std::ifstream(path, std::ios::binary).good())
    throw InputError(who + ": cannot be read (permission denied)");
  if (st.st_size == 0) throw InputError(who + ": empty file, not an MRPT rawlog");
  try {
    impl_->stream =
        std::make_unique<rawlog::ObjectStream>(rawlog::openFileSource(path), kMaxObjectBytes);
  } catch (const ReadFailure& e) {
    throw InputError(who + ": cannot be opened (" + e.what() + ")");
  }
  open();
}

RawlogReader::RawlogReader(const std::string& label, std::string_view bytes)
    : impl_(std::make_unique<Impl>()), path_(label) {
  if (bytes.empty()) throw InputError("rawlog '" + label + "': empty file, not an MRPT rawlog");
  impl_->stream =
      std::make_unique<rawlog::ObjectStream>(rawlog::openMemorySource(bytes), kMaxObjectBytes);
  open();
}

void RawlogReader::open() {
  impl_->checker = std::make_unique<rawlog::ObjectChecker>(*impl_->stream);
}

RawlogReader::~RawlogReader() = default;

void RawlogReader::setStopCheck(std::function<bool()> stop) {
  impl_->stop = stop;
  impl_->stream->setStopCheck(std::move(stop));
}

double RawlogReader::progress() const {
  const auto& src = impl_->stream->source();
  const double total = static_cast<double>(src.storedSize());
  return total > 0 ? std::min(1.0, static_cast<double>(src.storedConsumed()) / total) : 0.0;
}

std::set<std::string> RawlogReader::observationClasses() const {
  std::set<std::string> all = impl_->used_classes;
  for (const auto& c : impl_->passed_over_classes)
    if (!impl_->used_classes.count(c)) all.insert(c + " (passed over)");
  return all;
}

bool RawlogReader::observationsFormat() const { return impl_->format == Format::kObservations; }

std::optional<Step> RawlogReader::next() {
  if (stopped_ || ended_) return std::nullopt;
  try {
    auto step = nextStep();
    if (!step) {
      ended_ = true;
      return std::nullopt;
    }
    return finishStep(std::move(*step));
  } catch (const rawlog::ReadStopped&) {
    stopped_ = true;
    return std::nullopt;
  } catch (const ReadFailure& e) {
    ended_ = true;
    throw InputError(describe(e));
  } catch (const std::bad_alloc& e) {
    ended_ = true;
    throw InputError(describe(e));
  }
}

std::optional<Step> RawlogReader::nextStep() {
  auto& m = *impl_;
  const auto observationsStep = [&](const CSensoryFrame::Ptr& frame) {
    for (const auto& obs : *frame)
      if (auto odo = std::dynamic_pointer_cast<CObservationOdometry>(obs)) m.odometry.reading(*odo);
    m.record(*frame, m.used_classes);
    return std::make_pair(m.odometry.actionForStep(), frame);
  };

  std::pair<CActionCollection::Ptr, CSensoryFrame::Ptr> pair;
  while (!pair.second) {
    auto next = m.nextObject();
    if (!next) {
      if (m.objects == 0)
        throw InputError("rawlog '" + path_ + "': not an MRPT rawlog (no objects in it)");
      return std::nullopt;  // an action left without its frame is ignored, as kf-slam does
    }
    const auto& obj = *next;
    if (!obj) continue;  // a stored null object
    if (auto a = std::dynamic_pointer_cast<CActionCollection>(obj)) {
      if (m.format == Format::kObservations)
        throw ReadFailure(Kind::kUnsupported,
                          "holds a mrpt::obs::CActionCollection (entry " +
                              std::to_string(m.current) +
                              " of the file) after observations-only data: the file switches "
                              "to the actions-observations form there, and budget-slam reads one "
                              "form a file");
      m.format = Format::kActionsObservations;
      if (!m.action) m.action = a;  // MRPT keeps the first action and waits for a frame
      continue;
    }
    if (auto f = std::dynamic_pointer_cast<CSensoryFrame>(obj)) {
      if (m.format == Format::kUnknown) {
        // A frame before any action: the first of an observations-only file, or one that
        // kf-slam passes over before the first action-frame pair. The next object tells.
        const std::size_t entry = m.current;
        m.pending = m.nextObject();
        m.pending_entry = m.current;
        m.current = entry;
        m.pending_end = !m.pending;
        const bool action_follows =
            m.pending && std::dynamic_pointer_cast<CActionCollection>(*m.pending);
        m.format = action_follows ? Format::kActionsObservations : Format::kObservations;
      }
      if (m.format == Format::kObservations) {
        pair = observationsStep(f);
      } else if (m.action) {
        m.record(*f, m.used_classes);
        pair = {std::exchange(m.action, nullptr), f};
      } else {
        // kf-slam passes over a frame with no action before it; one with odometry in it is the
        // observations-only form, whose steps would all be lost.
        if (f->getObservationByClass<CObservationOdometry>())
          switchedForm(m.current, "a mrpt::obs::CSensoryFrame holding a CObservationOdometry");
        m.record(*f, m.passed_over_classes);
      }
      continue;
    }
    if (auto o = std::dynamic_pointer_cast<CObservation>(obj)) {
      if (m.format == Format::kActionsObservations) {
        // A bare odometry or bearing-range observation is the observations-only form: a file
        // that switches to it midway would lose every later step (issue 35), so it is refused.
        if (std::dynamic_pointer_cast<CObservationOdometry>(o) ||
            std::dynamic_pointer_cast<mrpt::obs::CObservationBearingRange>(o))
          switchedForm(m.current, "a bare mrpt::obs::" + shortName(*o));
        m.passed_over_classes.insert(shortName(*o));  // kf-slam reads pairs only
        continue;
      }
      m.format = Format::kObservations;
      if (auto odo = std::dynamic_pointer_cast<CObservationOdometry>(o)) {
        m.odometry.reading(*odo);
        m.used_classes.insert(shortName(*o));
        continue;
      }
      auto frame = CSensoryFrame::Create();
      frame->insert(o);
      pair = observationsStep(frame);
    }
  }
  // Timestamps: MRPT's own when usable and increasing, else one second a step (TUM readers
  // need strictly increasing times).
  const double fallback = last_t_ ? *last_t_ + 1.0 : 0.0;
  return parseStep(pair.first, pair.second, steps_, fallback);
}

void RawlogReader::switchedForm(std::size_t entry, const std::string& what) const {
  throw ReadFailure(Kind::kUnsupported,
                    "holds " + what + " (entry " + std::to_string(entry) +
                        " of the file) after actions-observations data: the file switches to "
                        "the observations-only form there, and budget-slam reads one form a file");
}

Step RawlogReader::finishStep(Step step) {
  if (last_t_ && step.t <= *last_t_) step.t = *last_t_ + 1e-3;
  last_t_ = step.t;

  const std::string at = "rawlog '" + path_ + "': step " + std::to_string(steps_);
  if (step.odometry) {
    const auto& m = step.odometry->mean;
    if (!std::isfinite(m.x) || !std::isfinite(m.y) || !std::isfinite(m.phi) ||
        !step.odometry->cov.allFinite())
      throw InputError(at + ": odometry has a non-finite value");
  }
  if (step.scan) {
    ++bearing_range_steps_;
    const auto& p = step.scan->sensor_pose_on_robot;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) ||
        !std::isfinite(p.yaw) || !std::isfinite(p.pitch) || !std::isfinite(p.roll))
      throw InputError(at + ": the sensor pose on the robot has a non-finite value");
    const auto& rs = step.scan->readings;
    for (size_t i = 0; i < rs.size(); ++i) {
      const std::string where = at + ": reading " + std::to_string(i);
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

std::string RawlogReader::describe(const std::exception& failure) const {
  const std::string who = "rawlog '" + path_ + "'";
  const std::string at = " at step " + std::to_string(steps_);
  const auto* f = dynamic_cast<const ReadFailure*>(&failure);
  if (!f) return who + ": out of memory" + at;
  // Bytes taken since the current top-level object began: the failure is inside it.
  const bool inside = impl_->stream->objectSize() > 0;
  const std::string top = inside ? impl_->checker->topLevelName() : std::string();
  const bool at_start = impl_->objects == 0 && top.empty();
  const std::string what = f->what();
  switch (f->kind) {
    case Kind::kEndOfData:
      if (!inside)  // between objects: only a gzip stream can end early there
        return who + ": truncated or corrupt" + at + " (" + what + ")";
      if (at_start) return who + ": not an MRPT rawlog (no serialized MRPT object at its start)";
      return who + ": truncated or corrupt" + at + " (the file ends inside " +
             (top.empty() ? std::string("an object header") : "a " + top) + ")";
    case Kind::kCorrupt:
      if (at_start) return who + ": not an MRPT rawlog (no serialized MRPT object at its start)";
      return who + ": truncated or corrupt" + at + " (" +
             (top.empty() ? what : "a " + top + " " + what) + ")";
    case Kind::kUnsupported:
      return who + ": step " + std::to_string(steps_) + " " + what;
    case Kind::kCompression:
      return who + ": truncated or corrupt" + at + " (" + what + ")";
    case Kind::kIo:
      return who + ": read error" + at + " (" + what + ")";
  }
  return who + ": " + what;
}

std::vector<Step> readAllSteps(const std::string& path) {
  RawlogReader reader(path);
  std::vector<Step> steps;
  while (auto s = reader.next()) steps.push_back(std::move(*s));
  return steps;
}

}  // namespace budget_slam::dataset
