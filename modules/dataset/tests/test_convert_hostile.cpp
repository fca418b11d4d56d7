// budget-convert and budget-simulate under hostile input and on files they did not write
// (issue 23, cases 1-3; docs/RELIABILITY.md "Converters and simulator"): one line naming file,
// line and field, an exit code, no file replaced, nothing read without bound, no impossible value
// let through.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <csignal>
#include <random>

#include "TestUtil.h"

using namespace budget_slam::dataset::test;

namespace {

std::string q(const std::string& s) { return "'" + s + "'"; }

std::string convert(const std::string& format, const std::string& input, const std::string& out,
                    const std::string& extra = "") {
  return bin("budget-convert") + " -f " + format + " " + q(input) + " -o " + q(out) + extra;
}

/// A small valid iSAM file: three steps, two landmarks.
const std::string kIsam =
    "ODOMETRY 0 1 1 0 0 0.01 0 0 0.01 0 0.01\n"
    "LANDMARK 1 5 2 1 0.1 0 0.1\n"
    "ODOMETRY 1 2 1 0 0.1 0.01 0 0 0.01 0 0.01\n"
    "LANDMARK 2 5 1 1 0.1 0 0.1\n"
    "LANDMARK 2 6 1 -1 0.1 0 0.1\n"
    "ODOMETRY 2 3 1 0 0 0.01 0 0 0.01 0 0.01\n";

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

}  // namespace

// Case 1: an output that exists is never replaced without --force, an input never, and --force
// keeps what was there.
TEST(ConvertOwnership, AnExistingOutputIsNotReplaced) {
  TempDir tmp;
  const auto in = writeFile(tmp.file("vp.txt"), kIsam);
  const auto out = tmp.file("out.rawlog");
  writeFile(out, "not mine\n");
  auto r = runTool(tmp, convert("isam", in, out));
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "budget-convert: output '" + out +
                       "' exists; give --force to write anyway (it is then kept as '" + out +
                       ".~1~')\n");
  EXPECT_EQ(readFile(out), "not mine\n");
  EXPECT_FALSE(fileExists(tmp.file("out.ini")));

  // A foreign sidecar or ground truth beside a new rawlog would go with it: refused too.
  for (const std::string other :
       {"o2.ini", "o2_ground_truth.txt", "o2_ground_truth_robot_path.txt"}) {
    SCOPED_TRACE(other);
    writeFile(tmp.file(other), "theirs\n");
    r = runTool(tmp, convert("isam", in, tmp.file("o2.rawlog")));
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("output '" + tmp.file(other) + "' exists"), std::string::npos) << r.err;
    EXPECT_EQ(readFile(tmp.file(other)), "theirs\n");
    EXPECT_FALSE(fileExists(tmp.file("o2.rawlog")));
    ::unlink(tmp.file(other).c_str());
  }

  // --force: written, and every file that was there kept as a numbered backup.
  writeFile(tmp.file("out_ground_truth.txt"), "stale\n");
  r = runTool(tmp, convert("isam", in, out, " --force"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(readFile(out + ".~1~"), "not mine\n");
  EXPECT_EQ(readFile(tmp.file("out_ground_truth.txt.~1~")), "stale\n");
  EXPECT_FALSE(fileExists(tmp.file("out_ground_truth.txt")));  // iSAM has none: not left beside
  EXPECT_NE(r.out.find("the earlier file is kept as " + out + ".~1~\n"), std::string::npos)
      << r.out;
  const std::string first = readFile(out);
  r = runTool(tmp, convert("isam", in, out, " --force"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(readFile(out + ".~2~"), first);
  EXPECT_EQ(readFile(out + ".~1~"), "not mine\n");
}

TEST(ConvertOwnership, TheInputIsNeverAnOutput) {
  TempDir tmp;
  const auto in = writeFile(tmp.file("in.rawlog"), kIsam);
  for (const std::string force : {"", " --force"}) {
    SCOPED_TRACE(force);
    const auto r = runTool(tmp, convert("isam", in, in, force));
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.err, "budget-convert: output '" + in + "' is the input '" + in +
                         "' (nothing is written over what is read); see budget-convert --help\n");
    EXPECT_EQ(readFile(in), kIsam);
    EXPECT_FALSE(fileExists(in + ".~1~"));
  }
  // A folder input: none of its files is an output.
  const std::string dir = tmp.file("course");
  ::mkdir(dir.c_str(), 0755);
  writeFile(dir + "/world.dat", "1 2 3\n");
  writeFile(dir + "/sensor_data.dat", "ODOMETRY 0 1 0\nSENSOR 1 2 0.1\n");
  writeFile(dir + "/world.ini", "keep\n");
  const auto r = runTool(tmp, convert("freiburg", dir, dir + "/world.rawlog", " --force"));
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "budget-convert: output '" + dir + "/world.ini' is the input '" + dir +
                       "/world.ini' (nothing is written over what is read); see budget-convert "
                       "--help\n");
}

TEST(ConvertOwnership, SimulateNeverReplacesAFileEither) {
  TempDir tmp;
  writeFile(tmp.file("s.ini"), "mine\n");
  const std::string cmd =
      bin("budget-simulate") + " --scenario paper-synthetic -o " + q(tmp.file("s.rawlog"));
  auto r = runTool(tmp, cmd);
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "budget-simulate: output '" + tmp.file("s.ini") +
                       "' exists; give --force to write anyway (it is then kept as '" +
                       tmp.file("s.ini") + ".~1~')\n");
  EXPECT_FALSE(fileExists(tmp.file("s.rawlog")));
  r = runTool(tmp, cmd + " --force");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(readFile(tmp.file("s.ini.~1~")), "mine\n");
  EXPECT_NE(readFile(tmp.file("s.ini")).find("[RangeBearingKFSLAM]"), std::string::npos);
}

// Case 2: an endless line and a binary file end at once in one line.
TEST(ConvertBounds, AnEndlessLineOrABinaryFileIsOneLineAtOnce) {
  TempDir tmp;
  for (const std::string format : {"isam", "g2o"}) {
    SCOPED_TRACE(format);
    const auto r = runTool(tmp, convert(format, "/dev/zero", tmp.file("z.rawlog")));
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err, "budget-convert: /dev/zero:1: a NUL byte at column 1, not a text file\n");
    EXPECT_LT(r.seconds, 10);
  }
  // An endless line of text: cut at the longest line a data file may have.
  writeFile(tmp.file("long.txt"), "ODOMETRY " + std::string(200000, '1') + "\n");
  auto r = runTool(tmp, convert("isam", tmp.file("long.txt"), tmp.file("l.rawlog")));
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "budget-convert: " + tmp.file("long.txt") +
                       ":1: line longer than 65536 bytes, not a data file\n");
  // 4 kB of random bytes: one printable line, no byte of the file echoed.
  std::mt19937 rng(3);
  std::string junk(4096, '\0');
  for (auto& c : junk) c = static_cast<char>(rng() & 0xff);
  junk[0] = 'O';  // not a NUL first, so that the check of what follows is what is tested
  const auto bin_file = writeFile(tmp.file("junk.g2o"), junk);
  r = runTool(tmp, convert("g2o", bin_file, tmp.file("j.rawlog")));
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("budget-convert: " + bin_file + ":1: ", 0), 0u) << r.err;
  for (const char c : r.err) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7f)) << r.err;
  // UTIAS and Freiburg read their files through the same reader.
  const std::string dir = tmp.file("utias");
  ::mkdir(dir.c_str(), 0755);
  ::symlink("/dev/zero", (dir + "/Barcodes.dat").c_str());
  for (const char* other : {"Landmark_Groundtruth.dat", "Robot1_Odometry.dat",
                            "Robot1_Groundtruth.dat", "Robot1_Measurement.dat"})
    writeFile(dir + "/" + other, "");  // every file there: the first one read is refused
  r = runTool(tmp, convert("utias", dir, tmp.file("u.rawlog")));
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "budget-convert: " + dir +
                       "/Barcodes.dat:1: a NUL byte at column 1, not a "
                       "text file\n");
  EXPECT_LT(r.seconds, 10);
}

// Case 3: impossible values are refused where they are read, naming file, line and field.
TEST(ConvertBounds, ImpossibleValuesNameFileLineAndField) {
  TempDir tmp;
  struct Case {
    std::string format, text, message;
  };
  const std::vector<Case> cases = {
      {"freiburg", "ODOMETRY 0 1 0\nSENSOR 1 2 1e308\n",
       ":2: bearing = 1e308 is out of range (|bearing| must be at most 12.5664)"},
      {"isam", "ODOMETRY 0 1 1e23 0 0 0.01 0 0 0.01 0 0.01\n",
       ":1: dx = 1e23 is out of range (|dx| must be at most 1000)"},
      {"freiburg", "ODOMETRY 0 1 0\nSENSOR -9223372036854775809 2 0.1\n",
       ":2: landmark id is not an integer: '-9223372036854775809'"},
      {"freiburg", "ODOMETRY 0 1 0\nSENSOR 4294967296 2 0.1\n",
       ":2: landmark id = 4294967296 is not a landmark id (0 to 2147483647)"},
      {"isam", "ODOMETRY 0 1 1 0 0 0.01 0 0 0.01 0 0.01\nLANDMARK 1 5 1e300 1 0.1 0 0.1\n",
       ":2: x = 1e300 is out of range (|x| must be at most 100000)"},
      {"isam", "ODOMETRY 0 1 1 0 0 1e30 0 0 0.01 0 0.01\n",
       ":1: covariance(1,1) = 1e30 is out of range (|covariance(1,1)| must be at most 1e+24)"},
      {"isam", "ODOMETRY 0 1 1 0 0 0.01 0 0 0.01 0 0.01\nLANDMARK 1 5 2 1 1e-300 0 0.1\n",
       ":2: variance v1 must be at least 1e-23, found '1e-300'"},
      {"g2o",
       "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_XY 7 3 4\n"
       "EDGE_SE2 0 1 1 0 0 1e-30 0 0 1e-30 0 1e-30\n",
       ":4: information matrix is nearly singular (its inverse, the covariance, has an entry "
       "that is not finite or above 1e24)"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    std::string input;
    if (c.format == "freiburg") {
      const std::string dir = tmp.file("fb");
      ::mkdir(dir.c_str(), 0755);
      writeFile(dir + "/world.dat", "1 2 3\n");
      input = writeFile(dir + "/sensor_data.dat", c.text);
      input = dir;
    } else {
      input = writeFile(tmp.file("in." + c.format), c.text);
    }
    const std::string file = c.format == "freiburg" ? input + "/sensor_data.dat" : input;
    const auto r = runTool(tmp, convert(c.format, input, tmp.file("o.rawlog")));
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err, "budget-convert: " + file + c.message + "\n");
    EXPECT_FALSE(fileExists(tmp.file("o.rawlog")));
  }
}

// Ctrl-C (or SIGTERM) ends a conversion with exit 130, one line, and no file written.
TEST(ConvertSignals, AStopRequestLeavesNoFile) {
  TempDir tmp;
  // An input without end: comment lines (which no record bound counts) through a FIFO.
  const std::string fifo = tmp.file("endless.txt");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  // The writer tells the test, through a pipe, once the converter is reading: the stop request
  // must come while it reads, not before it has set up its handlers (a loaded machine can take
  // longer than any fixed wait to start it).
  int reading[2];
  ASSERT_EQ(::pipe(reading), 0);
  const pid_t writer = ::fork();
  ASSERT_GE(writer, 0);
  if (writer == 0) {
    std::signal(SIGPIPE, SIG_DFL);
    ::close(reading[0]);
    std::FILE* f = std::fopen(fifo.c_str(), "w");
    std::string block;
    while (block.size() < 65536) block += "# a comment that never ends\n";
    bool told = false;
    while (f && std::fwrite(block.data(), 1, block.size(), f) == block.size()) {
      if (!told && std::fflush(f) == 0) told = ::write(reading[1], "r", 1) == 1;
    }
    ::_exit(0);
  }
  ::close(reading[1]);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::freopen(tmp.file("err").c_str(), "w", stderr);
    ::execl(bin("budget-convert").c_str(), "budget-convert", "-f", "isam", fifo.c_str(), "-o",
            tmp.file("o.rawlog").c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  char byte = 0;
  ASSERT_EQ(::read(reading[0], &byte, 1), 1) << "the converter never read its input";
  ::close(reading[0]);
  ::usleep(100000);  // it has read a block; let it run into the endless comments
  ::kill(child, SIGINT);
  ::usleep(50000);
  ::kill(child, SIGTERM);  // a second signal ends it the same way
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ::kill(writer, SIGKILL);
  ::waitpid(writer, nullptr, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const std::string err = readFile(tmp.file("err"));
  EXPECT_EQ(lines(err), 1) << err;
  EXPECT_EQ(err.rfind("budget-convert: interrupted by Ctrl-C while reading " + fifo + ":", 0), 0u)
      << err;
  EXPECT_FALSE(fileExists(tmp.file("o.rawlog")));
  EXPECT_FALSE(fileExists(tmp.file("o.rawlog.tmp")));
}
