#include "ObjectChecker.h"

#include <mrpt/math/CMatrixD.h>
#include <mrpt/math/CMatrixF.h>
#include <mrpt/obs/CAction.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussianInf.h>

#include "ReadFailure.h"

namespace budget_slam::dataset::rawlog {
namespace {

using mrpt::rtti::TRuntimeClassId;
using Kind = ReadFailure::Kind;

constexpr std::uint8_t kEndFlag = 0x88;  // MRPT's SERIALIZATION_END_FLAG
/// Fewest bytes a non-null object takes: length byte, a 1-character name, version, end flag.
constexpr std::uint64_t kMinObjectBytes = 4;
/// Fewest bytes a CMatrixD 3x3 object takes (header with a 1-character name, sizes, 9 doubles).
constexpr std::uint64_t kMinCov33Bytes = 4 + 8 + 9 * 8;

struct Versions {
  const TRuntimeClassId* cls;
  std::uint8_t first, last;  // what MRPT 2.5's serializeFrom accepts
};

const std::vector<Versions>& knownVersions() {
  using namespace mrpt::obs;
  using namespace mrpt::poses;
  using namespace mrpt::math;
  static const std::vector<Versions> v = {
      {CLASS_ID(CActionCollection), 0, 0},
      {CLASS_ID(CSensoryFrame), 0, 2},
      {CLASS_ID(CActionRobotMovement2D), 0, 7},
      {CLASS_ID(CActionRobotMovement3D), 0, 1},
      {CLASS_ID(CObservationBearingRange), 0, 3},
      {CLASS_ID(CObservationOdometry), 0, 2},
      {CLASS_ID(CPose2D), 0, 1},
      {CLASS_ID(CPose3D), 0, 3},
      {CLASS_ID(CPosePDFGaussian), 0, 2},
      {CLASS_ID(CPosePDFGaussianInf), 0, 0},
      {CLASS_ID(CPose3DPDFGaussian), 1, 1},
      {CLASS_ID(CMatrixD), 0, 0},
      {CLASS_ID(CMatrixF), 0, 0},
  };
  return v;
}

bool isA(const TRuntimeClassId* cls, const TRuntimeClassId* base) {
  return cls && cls->derivedFrom(base);
}

std::string quoted(const std::string& name) { return "'" + printable(name) + "'"; }

}  // namespace

std::string printable(const std::string& bytes) {
  static const char* kHex = "0123456789abcdef";
  std::string out;
  for (const unsigned char c : bytes) {
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

const TRuntimeClassId* ObjectChecker::checkTopLevel() {
  top_name_.clear();
  path_.clear();
  return object(Slot::kTopLevel);
}

ObjectChecker::Header ObjectChecker::header() {
  Header h;
  std::uint8_t len = in_.get<std::uint8_t>();
  if (!(len & 0x80)) {
    // MRPT < 0.5.5 framing: the length is a 32-bit integer whose upper three bytes are zero.
    const std::uint8_t* z = in_.take(3);
    if (z[0] || z[1] || z[2])
      badHeader("bytes that are not an MRPT object header",
                "holds bytes that are not an MRPT object header");
    h.old_format = true;
  }
  len &= 0x7f;
  if (len > 120)
    badHeader("an object header with a " + std::to_string(len) + "-character class name",
              "holds an object header with a " + std::to_string(len) +
                  "-character class name (at most 120)");
  const char* p = reinterpret_cast<const char*>(in_.take(len));
  const std::string raw(p, len);
  h.name = raw.substr(0, raw.find('\0'));  // MRPT reads the name as a C string
  h.null = h.name == "nullptr";
  if (h.old_format) {
    const auto v = in_.get<std::int32_t>();
    if (v < 0 || v >= 255)
      badHeader("a " + quoted(h.name) + " of serialization version " + std::to_string(v),
                "holds a " + quoted(h.name) + " of serialization version " + std::to_string(v));
    h.version = static_cast<std::uint8_t>(v);
  } else if (!h.null) {
    h.version = in_.get<std::uint8_t>();
  }
  if (!h.null) h.cls = mrpt::rtti::findRegisteredClass(h.name);
  return h;
}

const TRuntimeClassId* ObjectChecker::object(Slot slot, const TRuntimeClassId* exact) {
  const Header h = header();
  if (h.null) {
    // MRPT hands back a null pointer, which the classes read here dereference.
    if (slot != Slot::kTopLevel) bad("holds a null object where MRPT needs one");
  } else {
    if (!h.cls)
      badHeader("an object of unknown class " + quoted(h.name),
                "holds an object of unknown class " + quoted(h.name));
    const bool allowed = [&] {
      using namespace mrpt::obs;
      using namespace mrpt::poses;
      switch (slot) {
        case Slot::kTopLevel:
          return h.cls == CLASS_ID(CActionCollection) || h.cls == CLASS_ID(CSensoryFrame) ||
                 h.cls == CLASS_ID(CObservationBearingRange) ||
                 h.cls == CLASS_ID(CObservationOdometry);
        case Slot::kAction:
          return h.cls == CLASS_ID(CActionRobotMovement2D) ||
                 h.cls == CLASS_ID(CActionRobotMovement3D);
        case Slot::kObservation:
          return h.cls == CLASS_ID(CObservationBearingRange) ||
                 h.cls == CLASS_ID(CObservationOdometry);
        case Slot::kPosePdf:
          return h.cls == CLASS_ID(CPosePDFGaussian) || h.cls == CLASS_ID(CPosePDFGaussianInf);
        case Slot::kExact:
          return h.cls == exact;
      }
      return false;
    }();
    if (!allowed) refuseClass(slot, h, exact);
    if (path_.empty()) top_name_ = h.cls->className;
    path_.push_back(h.cls->className);
    for (const auto& k : knownVersions())
      if (k.cls == h.cls && (h.version < k.first || h.version > k.last))
        bad("is of serialization version " + std::to_string(h.version) + " (MRPT 2.5 reads " +
            std::to_string(k.first) + "-" + std::to_string(k.last) + ")");
    payload(h.cls, h.version);
  }
  if (!h.old_format && in_.get<std::uint8_t>() != kEndFlag) {
    if (h.null)
      badHeader("a null object without its end flag", "holds a null object without its end flag");
    bad("does not end where MRPT's layout says (no end flag)");
  }
  if (!h.null) path_.pop_back();
  return h.cls;
}

void ObjectChecker::refuseClass(Slot slot, const Header& h, const TRuntimeClassId* exact) {
  using namespace mrpt::obs;
  const std::string name = h.cls->className;
  const bool observation = isA(h.cls, CLASS_ID(CObservation));
  if ((slot == Slot::kTopLevel || slot == Slot::kObservation) && observation)
    throw ReadFailure(Kind::kUnsupported,
                      "holds a " + name +
                          ", which budget-slam does not read (it reads CObservationBearingRange "
                          "and CObservationOdometry; rawlog-edit --remove-label drops other "
                          "sensors)");
  if (slot == Slot::kAction && isA(h.cls, CLASS_ID(CAction)))
    throw ReadFailure(Kind::kUnsupported, "holds a " + name +
                                              ", which budget-slam does not read (it reads "
                                              "CActionRobotMovement2D and CActionRobotMovement3D)");
  if (slot == Slot::kPosePdf && isA(h.cls, CLASS_ID(mrpt::poses::CPosePDF)))
    throw ReadFailure(Kind::kUnsupported,
                      "holds odometry as a " + name +
                          ", which budget-slam does not read (it reads CPosePDFGaussian and "
                          "CPosePDFGaussianInf)");
  switch (slot) {
    case Slot::kTopLevel:
      throw ReadFailure(
          Kind::kUnsupported,
          "holds a " + name + ", where a rawlog holds actions, sensory frames and observations");
    case Slot::kAction:
      bad("holds a " + name + " where MRPT expects an action");
    case Slot::kObservation:
      bad("holds a " + name + " where MRPT expects an observation");
    case Slot::kPosePdf:
      bad("holds a " + name + " where MRPT expects a pose distribution");
    case Slot::kExact:
      bad("holds a " + name + " where MRPT expects a " + exact->className);
  }
  bad("holds a " + name);
}

void ObjectChecker::payload(const TRuntimeClassId* cls, std::uint8_t v) {
  using namespace mrpt::obs;
  using namespace mrpt::poses;
  if (cls == CLASS_ID(CActionCollection)) return actionCollection(v);
  if (cls == CLASS_ID(CSensoryFrame)) return sensoryFrame(v);
  if (cls == CLASS_ID(CActionRobotMovement2D)) return robotMovement2D(v);
  if (cls == CLASS_ID(CActionRobotMovement3D)) return robotMovement3D(v);
  if (cls == CLASS_ID(CObservationBearingRange)) return bearingRange(v);
  if (cls == CLASS_ID(CObservationOdometry)) return odometry(v);
  if (cls == CLASS_ID(CPose2D)) return pose2D(v);
  if (cls == CLASS_ID(CPose3D)) return pose3D(v);
  if (cls == CLASS_ID(CPosePDFGaussian)) return posePdfGaussian(v);
  if (cls == CLASS_ID(CPosePDFGaussianInf)) return posePdfGaussianInf(v);
  if (cls == CLASS_ID(CPose3DPDFGaussian)) return pose3DPdfGaussian(v);
  bad("cannot be checked");  // unreachable: object() admits only the classes above
}

// ---- the payloads, field by field as MRPT 2.5's serializeFrom reads them --------------------

void ObjectChecker::actionCollection(std::uint8_t) {
  const auto n = in_.get<std::uint32_t>();
  counted(n, kMinObjectBytes, "actions");  // MRPT resizes its deque to n before reading them
  for (std::uint32_t i = 0; i < n; ++i) object(Slot::kAction);
}

void ObjectChecker::sensoryFrame(std::uint8_t v) {
  if (v < 2) skip(4);   // ID
  if (v == 0) skip(8);  // timestamp
  const auto n = in_.get<std::uint32_t>();
  counted(n, kMinObjectBytes, "observations");  // MRPT resizes its vector to n first
  for (std::uint32_t i = 0; i < n; ++i) object(Slot::kObservation);
}

void ObjectChecker::motionModel(std::int32_t model, std::uint32_t particles) {
  // MRPT rebuilds the distribution from the raw odometry: model 0 is Gaussian, any other value
  // draws `particles` samples (Thrun's model) with nothing bounding their number.
  if (model == 0) return;
  if (model != 1) bad("has an unknown motion model (" + std::to_string(model) + ")");
  if (particles < 1 || particles > kMaxParticles)
    bad("asks for " + std::to_string(particles) + " motion-model particles (1-" +
        std::to_string(kMaxParticles) + " are read)");
}

void ObjectChecker::robotMovement2D(std::uint8_t v) {
  const auto estimation = [&](std::int32_t m) {
    if (m != 0 && m != 1) bad("has an unknown estimation method (" + std::to_string(m) + ")");
    return m == 0;  // emOdometry: the raw increment and the motion model are stored
  };
  if (v <= 1) {
    object(Slot::kPosePdf);  // dereferenced at once by MRPT
    estimation(in_.get<std::int32_t>());
    if (v == 1) {
      boolean();  // hasVelocities
      skip(8);    // two floats
      boolean();  // hasEncodersInfo
      skip(8);    // two int32 ticks
    }
    return;
  }
  const bool odometry = estimation(in_.get<std::int32_t>());
  if (odometry) {
    object(Slot::kExact, CLASS_ID(mrpt::poses::CPose2D));
    if (v == 2) {
      skip(44);  // MRPT 0.x options block, replaced by the defaults
    } else {
      const auto model = in_.get<std::int32_t>();
      skip(v == 3 ? 3 * 4 + 2 * 8 : 6 * 4);  // Gaussian model parameters
      const auto particles = in_.get<std::uint32_t>();
      skip(4 * 4);              // Thrun alphas
      if (v >= 5) skip(2 * 4);  // Thrun additional stds
      motionModel(model, particles);
    }
  } else {
    object(Slot::kPosePdf);
  }
  const bool velocities = boolean();
  if (v >= 7) {
    if (velocities) skip(3 * 8);  // TTwist2D
  } else {
    skip(2 * 4);
  }
  const bool encoders = boolean();
  if (v < 7 || encoders) skip(2 * 4);
  if (v >= 6) skip(8);  // timestamp
}

void ObjectChecker::robotMovement3D(std::uint8_t v) {
  const auto m = in_.get<std::uint32_t>();
  if (m > 1) bad("has an unknown estimation method (" + std::to_string(m) + ")");
  object(Slot::kExact, CLASS_ID(mrpt::poses::CPose3DPDFGaussian));
  // hasVelocities: std::vector<bool> (a count, then one byte each, read as != 0);
  // velocities: CVectorFloat (a count, then the floats). MRPT resizes both to the count first.
  const auto flags = in_.get<std::uint32_t>();
  counted(flags, 1, "velocity flags");
  skip(flags);
  const auto speeds = in_.get<std::uint32_t>();
  counted(speeds, 4, "velocities");
  skip(std::size_t{speeds} * 4);
  if (v >= 1) skip(8);  // timestamp
}

void ObjectChecker::bearingRange(std::uint8_t v) {
  skip(2 * 4);               // min, max range
  skip(v >= 3 ? 2 * 4 : 4);  // field of view
  object(Slot::kExact, CLASS_ID(mrpt::poses::CPose3D));
  if (v >= 2) skip(8);  // timestamp
  bool valid_cov = false;
  if (v >= 3) {
    valid_cov = boolean();
    if (!valid_cov) skip(3 * 4);  // sensor stds
  }
  const auto n = in_.get<std::uint32_t>();
  counted(n, valid_cov ? 16 + kMinCov33Bytes : 16, "readings");
  if (!valid_cov) {
    skip(std::size_t{n} * 16);  // range, yaw, pitch (float), landmark ID (int32)
  } else {
    for (std::uint32_t i = 0; i < n; ++i) {
      skip(16);
      matrix(CLASS_ID(mrpt::math::CMatrixD), 3, 3, 8);
    }
  }
  if (v >= 1) text();  // sensor label
}

void ObjectChecker::odometry(std::uint8_t v) {
  object(Slot::kExact, CLASS_ID(mrpt::poses::CPose2D));
  text();   // sensor label
  skip(8);  // timestamp
  if (v >= 1) {
    const bool encoders = boolean();
    if (encoders || v < 2) skip(2 * 4);
    const bool velocities = boolean();
    if (v < 2)
      skip(2 * 4);
    else if (velocities)
      skip(3 * 8);
  }
}

void ObjectChecker::pose2D(std::uint8_t v) { skip(v == 0 ? 3 * 4 : 3 * 8); }

void ObjectChecker::pose3D(std::uint8_t v) {
  switch (v) {
    case 0:
      return matrix(CLASS_ID(mrpt::math::CMatrixF), 4, 4, 4);
    case 1:
      return matrix(CLASS_ID(mrpt::math::CMatrixD), 4, 4, 8);
    case 2:
      return skip(7 * 8);  // x y z and a quaternion
    default:
      return skip(12 * 8);  // x y z and the rotation matrix
  }
}

void ObjectChecker::posePdfGaussian(std::uint8_t v) {
  object(Slot::kExact, CLASS_ID(mrpt::poses::CPose2D));
  switch (v) {
    case 0:
      return matrix(CLASS_ID(mrpt::math::CMatrixF), 3, 3, 4);
    case 1:
      return skip(6 * 4);  // upper triangle, float
    default:
      return skip(6 * 8);
  }
}

void ObjectChecker::posePdfGaussianInf(std::uint8_t) { skip(9 * 8); }

void ObjectChecker::pose3DPdfGaussian(std::uint8_t) {
  object(Slot::kExact, CLASS_ID(mrpt::poses::CPose3D));
  skip(21 * 8);  // upper triangle of the 6x6 covariance
}

void ObjectChecker::matrix(const TRuntimeClassId* cls, std::uint32_t rows, std::uint32_t cols,
                           std::size_t scalar_bytes) {
  // A matrix MRPT reads into a fixed-size one: any other size fails MRPT's assertion after the
  // allocation, or (CPosePDFGaussian v0) is assigned without a check.
  const Header h = header();
  if (h.null) bad("holds a null object where MRPT needs a " + std::string(cls->className));
  if (h.cls != cls) {
    if (!h.cls) bad("holds an object of unknown class " + quoted(h.name));
    bad("holds a " + std::string(h.cls->className) + " where MRPT expects a " + cls->className);
  }
  path_.push_back(cls->className);
  if (h.version != 0)
    bad("is of serialization version " + std::to_string(h.version) + " (MRPT 2.5 reads 0-0)");
  const auto r = in_.get<std::uint32_t>(), c = in_.get<std::uint32_t>();
  if (r != rows || c != cols)
    bad("is " + std::to_string(r) + "x" + std::to_string(c) + " where MRPT expects " +
        std::to_string(rows) + "x" + std::to_string(cols));
  skip(std::size_t{rows} * cols * scalar_bytes);
  if (!h.old_format && in_.get<std::uint8_t>() != kEndFlag)
    bad("does not end where MRPT's layout says (no end flag)");
  path_.pop_back();
}

bool ObjectChecker::boolean() {
  // MRPT copies the byte into a bool: any value but 0 or 1 is undefined behaviour there.
  const auto b = in_.get<std::uint8_t>();
  if (b > 1) bad("holds a boolean stored as " + std::to_string(b));
  return b == 1;
}

void ObjectChecker::text() {
  const auto n = in_.get<std::uint32_t>();
  counted(n, 1, "bytes of text");  // MRPT resizes the string to n first
  skip(n);
}

void ObjectChecker::counted(std::uint64_t n, std::uint64_t each, const char* what) {
  const std::uint64_t need = n * each;  // n < 2^32 and each < 2^16: no overflow
  const std::uint64_t room = in_.room();
  if (need <= room) return;
  if (in_.roomIsEndOfData())
    bad("declares " + std::to_string(n) + " " + what + " but the file ends " +
        std::to_string(room) + " bytes later");
  bad("declares " + std::to_string(n) + " " + what + ", more than the " +
      std::to_string(in_.maxObjectBytes() >> 20) + " MiB an object may take");
}

void ObjectChecker::bad(const std::string& what) const {
  // A predicate of the top-level object ("declares ..."), or of the innermost object below it;
  // RawlogReader puts "a <top-level class>" in front.
  if (path_.size() <= 1) throw ReadFailure(Kind::kCorrupt, what);
  throw ReadFailure(Kind::kCorrupt, "whose " + path_.back() + " " + what);
}

void ObjectChecker::badHeader(const std::string& alone, const std::string& inside) const {
  if (path_.empty()) throw ReadFailure(Kind::kCorrupt, alone);
  bad(inside);
}

}  // namespace budget_slam::dataset::rawlog
