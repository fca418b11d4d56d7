// Byte-flip mutants of MRPT's kf-slam demo rawlog (plain and gzip, fixed seed) through
// `budget-slam run`: each ends with exit 0 and sane outputs, or exit 1 with one error line and
// summary.json saying why; never a signal, never more than 1 GiB resident. Each mutant runs in
// a forked child (the application in-process, as main() would run it) so that a crash or a
// runaway allocation is seen as what it is; wait4() gives the child's peak RSS.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <map>
#include <random>

#include "AppTestUtil.h"

using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

constexpr int kMutantsPerForm = 100;  // plain and gzip: 200 in all
constexpr long kMaxRssKiB = 1 << 20;  // 1 GiB
constexpr int kParallel = 2;          // children at once (CI has 2 cores)

struct Mutant {
  std::string name;
  fs::path rawlog, out, err;
  int status = 0;
  long max_rss_kib = 0;
};

std::string gunzip(const std::string& path) {
  mrpt::io::CFileGZInputStream in(path);
  std::string bytes;
  char buf[65536];
  for (std::size_t got; (got = in.Read(buf, sizeof buf)) > 0;) bytes.append(buf, got);
  return bytes;
}

void writeGzip(const fs::path& path, const std::string& bytes) {
  mrpt::io::CFileGZOutputStream out(path.string());
  out.Write(bytes.data(), bytes.size());
}

/// 1 to 4 bytes of `bytes` XOR-ed with a non-zero byte.
std::string flipped(std::string bytes, std::mt19937& rng) {
  std::uniform_int_distribution<std::size_t> pos(0, bytes.size() - 1);
  std::uniform_int_distribution<int> count(1, 4), mask(1, 255);
  for (int k = count(rng); k > 0; --k) bytes[pos(rng)] ^= static_cast<char>(mask(rng));
  return bytes;
}

/// Runs the application on the mutant in a child process; never returns in the child.
pid_t start(const Mutant& m) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  // A safety net for the machine should a mutant still make the reader allocate without
  // bound (the RSS check below is the assertion).
  const rlimit as{rlim_t{4} << 30, rlim_t{4} << 30};
  ::setrlimit(RLIMIT_AS, &as);
  const auto r = runApp({"run", "-c", kMrptIni, "-i", m.rawlog.string(), "-o", m.out.string(),
                         "--quiet", "--reducer", "oldest", "--cap", "15"});
  std::ofstream(m.err) << r.err;
  std::fflush(nullptr);
  ::_exit(r.exit_code);
}

std::size_t lines(const fs::path& p) {
  const std::string s = slurp(p);
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

void check(const Mutant& m) {
  SCOPED_TRACE(m.name);
  ASSERT_FALSE(WIFSIGNALED(m.status)) << "signal " << WTERMSIG(m.status);
  ASSERT_TRUE(WIFEXITED(m.status));
  const int code = WEXITSTATUS(m.status);
  EXPECT_LT(m.max_rss_kib, kMaxRssKiB);
  const std::string err = slurp(m.err);
  if (code == 0) {
    EXPECT_EQ(err, "");
  } else {
    ASSERT_EQ(code, 1) << err;
    EXPECT_EQ(err.rfind("budget-slam: error: ", 0), 0u) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(err.find("internal error"), std::string::npos) << err;
    EXPECT_EQ(err.find("out of memory"), std::string::npos) << err;
  }
  ASSERT_TRUE(fs::exists(m.out / "summary.json")) << err;
  const auto summary = nlohmann::json::parse(slurp(m.out / "summary.json"));  // throws if invalid
  EXPECT_EQ(summary["status"], code == 0 ? "ok" : "failed");
  if (code == 1)
    EXPECT_EQ("budget-slam: error: " + summary["error"].get<std::string>() + "\n", err);
  // Outputs of the steps done: no cut line; a run that ended well has one trajectory row a
  // step and only finite numbers in it.
  for (const char* f : {"steps.csv", "trajectory.tum"}) {
    if (!fs::exists(m.out / f)) continue;
    const std::string s = slurp(m.out / f);
    if (!s.empty()) EXPECT_EQ(s.back(), '\n') << f;
  }
  if (code == 0) {
    EXPECT_EQ(lines(m.out / "steps.csv") - 1, lines(m.out / "trajectory.tum"));
    const std::string tum = slurp(m.out / "trajectory.tum");
    EXPECT_EQ(tum.find("nan"), std::string::npos);
    EXPECT_EQ(tum.find("inf"), std::string::npos);
  }
}

}  // namespace

TEST(Mutants, ByteFlippedDemoRawlogsFailCleanlyOrRun) {
  const auto dir = freshDir("mutants");
  fs::create_directories(dir);
  const std::string gz = slurp(kDemo), plain = gunzip(kDemo);
  ASSERT_GT(plain.size(), gz.size());

  // Plain mutants; gzip mutants alternate between flipped compressed bytes (zlib's checks
  // fail) and flipped content compressed anew (a valid gzip stream of corrupt objects).
  std::mt19937 rng(11);
  std::vector<Mutant> mutants;
  for (int k = 0; k < 2 * kMutantsPerForm; ++k) {
    Mutant m;
    const bool zipped = k % 2 == 1;
    m.name = (zipped ? "gzip_" : "plain_") + std::to_string(k / 2);
    m.rawlog = dir / (m.name + ".rawlog");
    m.out = dir / (m.name + "_out");
    m.err = dir / (m.name + ".err");
    if (!zipped)
      std::ofstream(m.rawlog, std::ios::binary) << flipped(plain, rng);
    else if (k % 4 == 1)
      std::ofstream(m.rawlog, std::ios::binary) << flipped(gz, rng);
    else
      writeGzip(m.rawlog, flipped(plain, rng));
    mutants.push_back(m);
  }

  // The RSS measurement itself: a child that touches 256 MiB must be seen above 256 MiB.
  {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      std::vector<char> big(std::size_t{256} << 20, 1);
      ::_exit(big[12345] == 1 ? 0 : 1);
    }
    int status = 0;
    rusage use{};
    ASSERT_EQ(::wait4(pid, &status, 0, &use), pid);
    ASSERT_GT(use.ru_maxrss, 256 * 1024);
  }

  std::map<pid_t, std::size_t> running;
  std::size_t next = 0;
  while (next < mutants.size() || !running.empty()) {
    while (next < mutants.size() && running.size() < kParallel) {
      const pid_t pid = start(mutants[next]);
      ASSERT_GT(pid, 0);
      running[pid] = next++;
    }
    int status = 0;
    rusage use{};
    const pid_t pid = ::wait4(-1, &status, 0, &use);
    ASSERT_GT(pid, 0);
    auto& m = mutants[running.at(pid)];
    running.erase(pid);
    m.status = status;
    m.max_rss_kib = use.ru_maxrss;
  }

  std::map<std::string, int> outcomes;
  long peak = 0;
  for (const auto& m : mutants) {
    check(m);
    peak = std::max(peak, m.max_rss_kib);
    const bool ok = WIFEXITED(m.status) && WEXITSTATUS(m.status) == 0;
    ++outcomes[m.name.substr(0, m.name.find('_')) + (ok ? " ok" : " failed")];
  }
  for (const auto& [what, n] : outcomes) std::cout << "mutants " << what << ": " << n << "\n";
  std::cout << "peak RSS of a mutant run: " << peak / 1024 << " MiB\n";
  if (!HasFailure()) fs::remove_all(dir);
}
