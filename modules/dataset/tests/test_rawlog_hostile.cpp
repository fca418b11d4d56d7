// RawlogReader on corrupt and hostile input: every failure is one InputError line naming the
// file and the step, raised before MRPT allocates what the file declares or dereferences what it
// lacks; the shipped rawlogs read exactly as MRPT's own CRawlog reads them.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussianInf.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstring>

#include "TestUtil.h"
#include "budget_slam/dataset/RawlogReader.h"

using namespace budget_slam;
using namespace budget_slam::dataset;
using namespace budget_slam::dataset::test;
using mrpt::obs::CActionCollection;
using mrpt::obs::CActionRobotMovement2D;
using mrpt::obs::CObservationBearingRange;
using mrpt::obs::CObservationOdometry;
using mrpt::obs::CSensoryFrame;

namespace {

std::string serialized(const mrpt::serialization::CSerializable& o) {
  mrpt::io::CMemoryStream m;
  auto a = mrpt::serialization::archiveFrom(m);
  a << o;
  return std::string(static_cast<const char*>(m.getRawBufferData()), m.getTotalBytesCount());
}

/// An MRPT 2.5 object header: length byte | 0x80, the class name, the version.
std::string header(const std::string& cls, std::uint8_t version) {
  return std::string(1, static_cast<char>(0x80 | cls.size())) + cls +
         std::string(1, static_cast<char>(version));
}

std::string u32(std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }

const std::string kEnd = "\x88";

/// One action (a Gaussian odometry increment) and one frame (two bearing-range readings).
std::string goodPair(double dx = 0.5) {
  CActionCollection acts;
  CActionRobotMovement2D move;
  move.computeFromOdometry(mrpt::poses::CPose2D(dx, 0, 0),
                           CActionRobotMovement2D::TMotionModelOptions());
  acts.insert(move);
  CSensoryFrame sf;
  auto br = CObservationBearingRange::Create();
  br->sensedData.resize(2);
  br->sensedData[0].range = 2.0f;
  br->sensedData[0].landmarkID = 1;
  br->sensedData[1].range = 3.0f;
  br->sensedData[1].yaw = 0.5f;
  br->sensedData[1].landmarkID = 2;
  sf.insert(br);
  return serialized(acts) + serialized(sf);
}

/// The InputError message of reading every step of `bytes` ("" when none), and the steps read.
std::pair<std::string, std::size_t> readBytes(const std::string& bytes,
                                              const std::string& label = "x.rawlog") {
  std::size_t steps = 0;
  const std::string msg = inputErrorOf([&] {
    RawlogReader reader(label, bytes);
    while (reader.next()) ++steps;
  });
  return {msg, steps};
}

std::string demoPlain() {
  mrpt::io::CFileGZInputStream in(sourceDir() + "/rawlogs/kf-slam_demo.rawlog");
  std::string bytes;
  char buf[65536];
  for (std::size_t got; (got = in.Read(buf, sizeof buf)) > 0;) bytes.append(buf, got);
  return bytes;
}

}  // namespace

TEST(RawlogHostile, GoodPairReads) {
  const auto [msg, steps] = readBytes(goodPair() + goodPair());
  EXPECT_EQ(msg, "");
  EXPECT_EQ(steps, 2u);
}

TEST(RawlogHostile, HugeActionCountIsRefusedBeforeAllocating) {
  // MRPT resizes its deque to the stored count first: 2^32-1 actions took 23 GB.
  const std::string cls = "mrpt::obs::CActionCollection";
  const std::string bytes = goodPair() + header(cls, 0) + u32(0xffffffffu) + kEnd;
  EXPECT_EQ(readBytes(bytes).first,
            "rawlog 'x.rawlog': truncated or corrupt at step 1 (a mrpt::obs::CActionCollection "
            "declares 4294967295 actions but the file ends 1 bytes later)");
  EXPECT_EQ(readBytes(bytes).second, 1u);
}

TEST(RawlogHostile, HugeCountInsideAGzipFileIsBoundedByTheObjectLimit) {
  // The uncompressed size of a gzip stream is not known ahead: the per-object limit bounds it.
  const std::string bytes =
      goodPair() + header("mrpt::obs::CSensoryFrame", 2) + u32(0x7fffffffu) + kEnd;
  TempDir tmp;
  const std::string path = tmp.file("big.rawlog");
  writeFile(path + ".plain", bytes);
  ASSERT_EQ(run("gzip -c '" + path + ".plain' > '" + path + "'"), 0);
  std::size_t steps = 0;
  const auto msg = inputErrorOf([&] {
    RawlogReader reader(path);
    while (reader.next()) ++steps;
  });
  EXPECT_EQ(msg, "rawlog '" + path +
                     "': truncated or corrupt at step 1 (a mrpt::obs::CSensoryFrame declares "
                     "2147483647 observations, more than the 16 MiB an object may take)");
  EXPECT_EQ(steps, 1u);
}

TEST(RawlogHostile, NullPoseInsideAnOldActionIsRefused) {
  // CActionRobotMovement2D v0 reads a CPosePDF and calls getMean() on it: null was a SIGSEGV.
  const std::string action = header("mrpt::obs::CActionRobotMovement2D", 0) +
                             std::string(1, static_cast<char>(0x80 | 7)) + "nullptr" + kEnd +
                             u32(0) + kEnd;
  const std::string bytes =
      goodPair() + header("mrpt::obs::CActionCollection", 0) + u32(1) + action + kEnd;
  EXPECT_EQ(readBytes(bytes).first,
            "rawlog 'x.rawlog': truncated or corrupt at step 1 (a mrpt::obs::CActionCollection "
            "whose mrpt::obs::CActionRobotMovement2D holds a null object where MRPT needs one)");
}

TEST(RawlogHostile, UnboundedMotionModelParticlesAreRefused) {
  CActionCollection acts;
  CActionRobotMovement2D move;
  move.computeFromOdometry(mrpt::poses::CPose2D(0.5, 0, 0),
                           CActionRobotMovement2D::TMotionModelOptions());
  // What the file may claim: Thrun's model with 10^8 particles, drawn when MRPT reads it.
  move.motionModelConfiguration.modelSelection = CActionRobotMovement2D::mmThrun;
  move.motionModelConfiguration.thrunModel.nParticlesCount = 100000000;
  acts.insert(move);
  const std::string bytes = serialized(acts) + goodPair().substr(serialized(acts).size());
  EXPECT_EQ(readBytes(bytes).first,
            "rawlog 'x.rawlog': truncated or corrupt at step 0 (a mrpt::obs::CActionCollection "
            "whose mrpt::obs::CActionRobotMovement2D asks for 100000000 motion-model particles "
            "(1-10000 are read))");
}

TEST(RawlogHostile, ClassNameBytesAreQuotedPrintable) {
  // Bytes of a corrupt class name must not reach summary.json as invalid UTF-8.
  const std::string bytes = goodPair() + header("mrpt::obs::CAct\xff\xfeon", 0) + kEnd;
  const auto msg = readBytes(bytes).first;
  EXPECT_EQ(msg,
            "rawlog 'x.rawlog': truncated or corrupt at step 1 (an object of unknown class "
            "'mrpt::obs::CAct\\xff\\xfeon')");
}

TEST(RawlogHostile, BooleanOutsideZeroOrOneIsRefused) {
  // MRPT copies the byte into a bool. CActionRobotMovement2D v7 ends with hasVelocities (false
  // here, so no twist follows), hasEncoderInfo (false), the 8-byte timestamp and its end flag;
  // the collection's end flag comes last.
  std::string bytes = goodPair();
  const std::size_t acts_end = bytes.find("mrpt::obs::CSensoryFrame") - 1;
  const std::size_t has_velocities = acts_end - 1 - 1 - 8 - 1 - 1;
  ASSERT_EQ(bytes[has_velocities], 0);
  bytes[has_velocities] = 2;
  EXPECT_EQ(readBytes(bytes).first,
            "rawlog 'x.rawlog': truncated or corrupt at step 0 (a mrpt::obs::CActionCollection "
            "whose mrpt::obs::CActionRobotMovement2D holds a boolean stored as 2)");
}

TEST(RawlogHostile, GzipCrcFailureIsAnErrorAfterTheStepsBeforeIt) {
  // zlib's gzread (MRPT's CFileGZInputStream) takes a failed CRC for the end of the file.
  std::string gz = readFile(sourceDir() + "/rawlogs/kf-slam_demo.rawlog");
  gz[gz.size() - 8] ^= 0x01;  // the CRC-32 in the gzip trailer
  const auto [msg, steps] = readBytes(gz, "crc.rawlog");
  EXPECT_EQ(msg,
            "rawlog 'crc.rawlog': truncated or corrupt at step 249 (damaged gzip data, zlib: "
            "incorrect data check)");
  EXPECT_EQ(steps, 249u);
}

TEST(RawlogHostile, GzipCutShortNamesTheObjectItCut) {
  const std::string gz = readFile(sourceDir() + "/rawlogs/kf-slam_demo.rawlog");
  const auto [msg, steps] = readBytes(gz.substr(0, gz.size() - 4), "cut.rawlog");
  EXPECT_EQ(msg,
            "rawlog 'cut.rawlog': truncated or corrupt at step 249 (the file ends before "
            "the end of its gzip data)");
  EXPECT_EQ(steps, 249u);
}

TEST(RawlogHostile, ObservationsFormatTakesOdometryFromOdometryObservations) {
  // MRPT's other format: bare observations, odometry as absolute CObservationOdometry poses.
  std::string bytes;
  const mrpt::poses::CPose2D poses[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, M_PI / 2}};
  for (const auto& p : poses) {
    CObservationOdometry odo;
    odo.odometry = p;
    CObservationBearingRange br;
    br.sensedData.resize(1);
    br.sensedData[0].range = 1.0f;
    br.sensedData[0].landmarkID = 7;
    bytes += serialized(odo) + serialized(br);
  }
  RawlogReader reader("obs.rawlog", bytes);
  std::vector<Step> steps;
  while (auto s = reader.next()) steps.push_back(std::move(*s));
  ASSERT_EQ(steps.size(), 3u);
  EXPECT_TRUE(reader.observationsFormat());
  EXPECT_FALSE(steps[0].odometry);  // the first reading only sets where the robot starts
  ASSERT_TRUE(steps[1].odometry && steps[2].odometry);
  EXPECT_NEAR(steps[1].odometry->mean.x, 1.0, 1e-12);
  // (1,1,90°) ⊖ (1,0,0): one metre to the robot's left, turned 90°.
  EXPECT_NEAR(steps[2].odometry->mean.x, 0.0, 1e-12);
  EXPECT_NEAR(steps[2].odometry->mean.y, 1.0, 1e-12);
  EXPECT_NEAR(steps[2].odometry->mean.phi, M_PI / 2, 1e-12);
  for (const auto& s : steps) ASSERT_TRUE(s.scan) << s.index;
  EXPECT_EQ(reader.bearingRangeSteps(), 3u);
}

TEST(RawlogHostile, StopCheckEndsReadingInsideAnObject) {
  const std::string plain = demoPlain();
  RawlogReader reader("demo.rawlog", plain);
  int polls = 0;
  reader.setStopCheck([&] { return ++polls > 3; });
  std::size_t steps = 0;
  while (reader.next()) ++steps;
  EXPECT_TRUE(reader.stopped());
  EXPECT_LT(steps, 10u);
  EXPECT_FALSE(reader.next());  // stays stopped
}

TEST(RawlogHostile, ReadsTheShippedRawlogsAsMrptDoes) {
  // Reference: MRPT's own reader and pairing rule (CRawlog::readActionObservationPair).
  for (const std::string name : {"kf-slam_demo", "victoria_park", "rooms"}) {
    const std::string path = sourceDir() + "/rawlogs/" + name + ".rawlog";
    mrpt::io::CFileGZInputStream in(path);
    auto arch = mrpt::serialization::archiveFrom(in);
    RawlogReader reader(path);
    std::size_t pos = 0, k = 0;
    CActionCollection::Ptr acts;
    CSensoryFrame::Ptr sf;
    while (mrpt::obs::CRawlog::readActionObservationPair(arch, acts, sf, pos)) {
      const Step want = parseStep(acts, sf, k, 0);
      const auto got = reader.next();
      ASSERT_TRUE(got) << name << " step " << k;
      ASSERT_EQ(got->odometry.has_value(), want.odometry.has_value()) << name << " " << k;
      if (want.odometry) {
        EXPECT_EQ(got->odometry->mean.x, want.odometry->mean.x);
        EXPECT_EQ(got->odometry->mean.y, want.odometry->mean.y);
        EXPECT_EQ(got->odometry->mean.phi, want.odometry->mean.phi);
        EXPECT_TRUE(got->odometry->cov == want.odometry->cov) << name << " " << k;
      }
      ASSERT_EQ(got->scan.has_value(), want.scan.has_value()) << name << " " << k;
      if (want.scan) {
        ASSERT_EQ(got->scan->readings.size(), want.scan->readings.size());
        for (std::size_t i = 0; i < want.scan->readings.size(); ++i) {
          EXPECT_EQ(got->scan->readings[i].range, want.scan->readings[i].range);
          EXPECT_EQ(got->scan->readings[i].yaw, want.scan->readings[i].yaw);
          EXPECT_EQ(got->scan->readings[i].id, want.scan->readings[i].id);
        }
      }
      ++k;
    }
    EXPECT_FALSE(reader.next()) << name;
    EXPECT_GT(k, 100u) << name;
  }
}

TEST(RawlogHostile, EveryLayoutTheCheckWalksIsTheOneMrptWrites) {
  // The check walks each class's fields as MRPT 2.5 reads them; after the check MRPT must read
  // exactly the bytes walked (the decoder throws otherwise). Written by MRPT itself here: the
  // optional branches (3D actions with velocities, scan-matching actions with their own pose
  // distribution, odometry with encoders and velocities, per-reading covariances, labels).
  CActionCollection acts;
  mrpt::obs::CActionRobotMovement3D move3d;
  move3d.poseChange.mean = mrpt::poses::CPose3D(0.5, 0.1, 0, 0.2, 0, 0);
  move3d.hasVelocities = {true, false, true, false, false, true};
  move3d.velocities.resize(6);
  move3d.velocities.fill(0.25f);
  acts.insert(move3d);
  CActionRobotMovement2D matched;
  matched.estimationMethod = CActionRobotMovement2D::emScan2DMatching;
  auto inf = mrpt::poses::CPosePDFGaussianInf::Create();
  inf->mean = mrpt::poses::CPose2D(0.4, 0, 0.1);
  inf->cov_inv.setIdentity();
  matched.poseChange = mrpt::poses::CPosePDF::Ptr(inf);
  matched.hasVelocities = true;
  matched.hasEncodersInfo = true;
  acts.insert(matched);

  CSensoryFrame sf;
  auto odo = CObservationOdometry::Create();
  odo->odometry = mrpt::poses::CPose2D(1, 2, 0.3);
  odo->hasEncodersInfo = true;
  odo->hasVelocities = true;
  odo->sensorLabel = "ODOMETRY";
  sf.insert(odo);
  auto br = CObservationBearingRange::Create();
  br->validCovariances = true;
  br->sensorLabel = "LANDMARKS";
  br->sensedData.resize(2);
  for (int i = 0; i < 2; ++i) {
    br->sensedData[i].range = 2.0f + i;
    br->sensedData[i].landmarkID = i;
    br->sensedData[i].covariance.setIdentity();
  }
  sf.insert(br);

  const std::string bytes = serialized(acts) + serialized(sf);
  RawlogReader reader("layouts.rawlog", bytes);
  const auto step = reader.next();
  ASSERT_TRUE(step);
  ASSERT_TRUE(step->scan);
  EXPECT_EQ(step->scan->readings.size(), 2u);
  EXPECT_EQ(step->action->size(), 2u);
  EXPECT_FALSE(reader.next());
}
