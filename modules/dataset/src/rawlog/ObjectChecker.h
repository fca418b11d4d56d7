#pragma once
#include <mrpt/rtti/CObject.h>

#include <cstdint>
#include <string>
#include <vector>

#include "ObjectStream.h"

namespace budget_slam::dataset::rawlog {

/// Checks one serialized MRPT object against the layout MRPT 2.5's deserializers read, for the
/// classes budget-slam reads, before any MRPT code sees its bytes:
///
///   object  = header payload end-flag(0x88)
///   header  = (0x80 | name length <= 120) name version     (or MRPT < 0.5.5's 4-byte length,
///             name, int32 version, and no end flag)
///
/// The class at every position must be one MRPT would accept there and budget-slam reads; every
/// version must be one MRPT knows; every count or length is checked against the bytes the object
/// may still take (ObjectStream::room) before the bytes are taken; booleans and enums must hold a
/// value of their type; objects MRPT would dereference must not be null; matrices must have the
/// size MRPT assigns them to. After the check, MRPT's own deserializer reads exactly these
/// bytes, so it allocates only what real bytes back and follows no path the check did not.
///
/// Classes: CActionCollection, CActionRobotMovement2D (v0-7), CActionRobotMovement3D,
/// CSensoryFrame, CObservationBearingRange (v0-3), CObservationOdometry, and inside them CPose2D,
/// CPose3D, CPosePDFGaussian, CPosePDFGaussianInf, CPose3DPDFGaussian, CMatrixD, CMatrixF.
class ObjectChecker {
 public:
  explicit ObjectChecker(ObjectStream& in) : in_(in) {}

  /// Checks the top-level object starting at the stream's cursor and leaves the cursor after it.
  /// Returns its class, nullptr for a stored null object. Throws ReadFailure.
  const mrpt::rtti::TRuntimeClassId* checkTopLevel();

  /// Class name of the top-level object being checked, "" until its header was read and known.
  const std::string& topLevelName() const { return top_name_; }

  /// Thrun-model particle count allowed in a CActionRobotMovement2D (MRPT's default is 300):
  /// MRPT draws that many samples when it reads the action.
  static constexpr std::uint32_t kMaxParticles = 10000;

 private:
  enum class Slot { kTopLevel, kAction, kObservation, kPosePdf, kExact };
  struct Header {
    std::string name;
    const mrpt::rtti::TRuntimeClassId* cls = nullptr;
    bool old_format = false;
    bool null = false;
    std::uint8_t version = 0;
  };

  Header header();
  /// One object at a position that takes `slot` (for kExact, exactly `exact`).
  const mrpt::rtti::TRuntimeClassId* object(Slot slot,
                                            const mrpt::rtti::TRuntimeClassId* exact = nullptr);
  void refuseClass(Slot slot, const Header& h, const mrpt::rtti::TRuntimeClassId* exact);
  void payload(const mrpt::rtti::TRuntimeClassId* cls, std::uint8_t version);

  void actionCollection(std::uint8_t v);
  void sensoryFrame(std::uint8_t v);
  void robotMovement2D(std::uint8_t v);
  void robotMovement3D(std::uint8_t v);
  void bearingRange(std::uint8_t v);
  void odometry(std::uint8_t v);
  void pose2D(std::uint8_t v);
  void pose3D(std::uint8_t v);
  void posePdfGaussian(std::uint8_t v);
  void posePdfGaussianInf(std::uint8_t v);
  void pose3DPdfGaussian(std::uint8_t v);
  void matrix(const mrpt::rtti::TRuntimeClassId* cls, std::uint32_t rows, std::uint32_t cols,
              std::size_t scalar_bytes);
  void motionModel(std::int32_t model, std::uint32_t particles);

  void skip(std::size_t bytes) { in_.take(bytes); }
  bool boolean();
  void text();
  /// Throws unless `n` items of at least `each` bytes fit in what the object may still take.
  void counted(std::uint64_t n, std::uint64_t each, const char* what);
  [[noreturn]] void bad(const std::string& what) const;
  /// A bad object header: `alone` for a top-level object, `inside` (a predicate) below one.
  [[noreturn]] void badHeader(const std::string& alone, const std::string& inside) const;

  ObjectStream& in_;
  std::string top_name_;
  std::vector<std::string> path_;  // class names from the top-level object to the current one
};

}  // namespace budget_slam::dataset::rawlog
