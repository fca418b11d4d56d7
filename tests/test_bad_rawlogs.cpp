// Corrupt and unusual rawlogs through `budget-slam run`: one error line naming the file and the
// step, exit 1, the outputs of the steps done, and summary.json (valid UTF-8) saying why.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include "AppTestUtil.h"

using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

/// run on `rawlog` with reducer oldest and a cap of 15.
AppResult runCapped(const fs::path& rawlog, const fs::path& out) {
  return runOn(rawlog.string(), out, {"--reducer", "oldest", "--cap", "15"});
}

/// Exit 1, `message` as the one error line and as summary.json's error, and `steps` steps in
/// steps.csv, trajectory.tum and summary.json.
void expectFailedAfter(const AppResult& r, const fs::path& out, const std::string& message,
                       std::size_t steps) {
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(isErrorLine(r.err, message));
  ASSERT_TRUE(fs::exists(out / "summary.json")) << r.err;
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["status"], "failed");
  EXPECT_EQ(s["error"], message);
  EXPECT_EQ(s["counts"]["steps"], steps);
  EXPECT_EQ(readCsv(out / "steps.csv").size(), steps);
  const std::string tum = slurp(out / "trajectory.tum");
  EXPECT_EQ(static_cast<std::size_t>(std::count(tum.begin(), tum.end(), '\n')), steps);
}

std::string objectHeader(const std::string& cls, std::uint8_t version) {
  return std::string(1, static_cast<char>(0x80 | cls.size())) + cls +
         std::string(1, static_cast<char>(version));
}

std::string gunzip(const std::string& path) {
  mrpt::io::CFileGZInputStream in(path);
  std::string bytes;
  char buf[65536];
  for (std::size_t got; (got = in.Read(buf, sizeof buf)) > 0;) bytes.append(buf, got);
  return bytes;
}

}  // namespace

TEST(BadRawlogs, GzipCrcFailureIsAnErrorNotASilentEnd) {
  // zlib's gzread, under MRPT's CFileGZInputStream, ends quietly when the CRC check fails: the
  // run said `ok` without its last steps.
  const auto out = freshDir("crc");
  const auto path = out.parent_path() / "crc.rawlog";
  std::string gz = slurp(kDemo);
  gz[gz.size() - 8] ^= 0x20;  // the CRC-32 of the gzip trailer
  std::ofstream(path, std::ios::binary) << gz;
  expectFailedAfter(runCapped(path, out), out,
                    "rawlog '" + path.string() +
                        "': truncated or corrupt at step 249 (damaged gzip data, zlib: "
                        "incorrect data check)",
                    249);
}

TEST(BadRawlogs, HugeDeclaredCountFailsBeforeAllocating) {
  // CActionCollection::serializeFrom resizes its deque to the stored count: 23 GB before.
  const auto out = freshDir("huge_count");
  const auto path = out.parent_path() / "huge_count.rawlog";
  const std::string plain = gunzip(kDemo);
  const std::string cut =
      plain.substr(0, plain.rfind(objectHeader("mrpt::obs::CActionCollection", 0)));
  std::ofstream(path, std::ios::binary) << cut << objectHeader("mrpt::obs::CActionCollection", 0)
                                        << std::string("\xf0\xff\xff\x7f") << std::string(64, '\0');
  expectFailedAfter(runCapped(path, out), out,
                    "rawlog '" + path.string() +
                        "': truncated or corrupt at step 249 (a mrpt::obs::CActionCollection "
                        "declares 2147483632 actions but the file ends 64 bytes later)",
                    249);
}

TEST(BadRawlogs, CorruptClassNameBytesKeepSummaryJsonValid) {
  // The error text once echoed the raw bytes, and writing summary.json failed on invalid UTF-8.
  const auto out = freshDir("bad_class_name");
  const auto path = out.parent_path() / "bad_class_name.rawlog";
  std::string plain = gunzip(kDemo);
  const auto at = plain.find("mrpt::obs::CSensoryFrame", plain.size() / 2);
  ASSERT_NE(at, std::string::npos);
  plain[at + 12] = static_cast<char>(0xe9);  // "mrpt::obs::C\xe9ensoryFrame"
  std::ofstream(path, std::ios::binary) << plain;
  const auto r = runCapped(path, out);
  ASSERT_EQ(r.exit_code, 1);
  const auto s = readJson(out / "summary.json");  // throws on invalid JSON
  EXPECT_EQ("budget-slam: error: " + s["error"].get<std::string>() + "\n", r.err);
  EXPECT_TRUE(
      isErrorLine(r.err, "rawlog '" + path.string() +
                             "': truncated or corrupt at step 125 (an object of unknown class "
                             "'mrpt::obs::C\\xe9ensoryFrame')"));
  EXPECT_EQ(readCsv(out / "steps.csv").size(), 125u);
}

TEST(BadRawlogs, ObservationsOnlyRawlogRuns) {
  // MRPT's other rawlog format: bare observations, odometry as absolute CObservationOdometry
  // poses (as MRPT's apps read it). The demo rewritten that way runs every bearing-range step.
  const auto out = freshDir("observations_format");
  const auto path = out.parent_path() / "observations_format.rawlog";
  std::size_t scans = 0;
  {
    mrpt::io::CFileGZInputStream in(kDemo);
    auto ia = mrpt::serialization::archiveFrom(in);
    mrpt::io::CFileGZOutputStream o(path.string());
    auto oa = mrpt::serialization::archiveFrom(o);
    mrpt::obs::CActionCollection::Ptr act;
    mrpt::obs::CSensoryFrame::Ptr sf;
    std::size_t entry = 0;
    mrpt::poses::CPose2D odometry;
    while (mrpt::obs::CRawlog::readActionObservationPair(ia, act, sf, entry)) {
      if (auto move = act->getBestMovementEstimation()) {
        odometry = odometry + move->poseChange->getMeanVal();
        mrpt::obs::CObservationOdometry odo;
        odo.odometry = odometry;
        oa << odo;
      }
      auto br = sf->getObservationByClass<mrpt::obs::CObservationBearingRange>();
      ASSERT_TRUE(br);
      oa << *br;
      ++scans;
    }
  }
  const auto r = runCapped(path, out);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(readJson(out / "summary.json")["status"], "ok");
  EXPECT_EQ(readCsv(out / "steps.csv").size(), scans);
}

TEST(BadRawlogs, ARawlogThatSwitchesFormMidwayIsRefusedAtTheEntry) {
  // The demo's first 100 action-frame pairs, then the rest in the observations-only form (bare
  // CObservationOdometry and CObservationBearingRange): the second half was dropped without a
  // word (exit 0, status ok; issue 35). Now refused at the entry where the form changes, with the
  // outputs of the 100 steps read before it.
  const auto out = freshDir("switched_form");
  const auto path = out.parent_path() / "switched_form.rawlog";
  constexpr std::size_t kPairs = 100;
  {
    mrpt::io::CFileGZInputStream in(kDemo);
    auto ia = mrpt::serialization::archiveFrom(in);
    mrpt::io::CFileGZOutputStream o(path.string());
    auto oa = mrpt::serialization::archiveFrom(o);
    mrpt::obs::CActionCollection::Ptr act;
    mrpt::obs::CSensoryFrame::Ptr sf;
    std::size_t entry = 0, pairs = 0;
    mrpt::poses::CPose2D odometry;
    while (mrpt::obs::CRawlog::readActionObservationPair(ia, act, sf, entry)) {
      if (pairs++ < kPairs) {
        oa << *act << *sf;
        continue;
      }
      if (auto move = act->getBestMovementEstimation())
        odometry = odometry + move->poseChange->getMeanVal();
      mrpt::obs::CObservationOdometry odo;
      odo.odometry = odometry;
      oa << odo << *sf->getObservationByClass<mrpt::obs::CObservationBearingRange>();
    }
  }
  const auto r = runCapped(path, out);
  expectFailedAfter(r, out,
                    "rawlog '" + path.string() + "': step " + std::to_string(kPairs) +
                        " holds a bare mrpt::obs::CObservationOdometry (entry " +
                        std::to_string(2 * kPairs) +
                        " of the file) after actions-observations data: the file switches to the "
                        "observations-only form there, and budget-slam reads one form a file",
                    kPairs);
}
