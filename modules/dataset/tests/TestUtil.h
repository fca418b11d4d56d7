#pragma once
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>

#include "budget_slam/core/Error.h"

namespace budget_slam::dataset::test {

/// A fresh directory under $TMPDIR (or /tmp), removed with its contents at the end of the test.
class TempDir {
 public:
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string templ = std::string(base && *base ? base : "/tmp") + "/budget_slam_test_XXXXXX";
    if (!::mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed");
    path_ = templ;
  }
  ~TempDir() { std::system(("rm -rf '" + path_ + "'").c_str()); }
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

inline std::string writeFile(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline bool fileExists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

/// The InputError message `fn` throws ("" when it throws none).
inline std::string inputErrorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// Root of the repository and the public datasets.
inline std::string sourceDir() { return BUDGET_SLAM_SOURCE_DIR; }
/// The project's gzipped copies of the public datasets (data/README.md).
inline std::string datasetsDir() { return sourceDir() + "/data/datasets"; }

/// Runs a shell command, returns its exit status.
inline int run(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

/// build/bin/<tool>.
inline std::string bin(const std::string& tool) {
  return std::string(BUDGET_SLAM_BINARY_DIR) + "/bin/" + tool;
}

/// What a tool run printed, its exit status and how long it took.
struct ToolResult {
  int status;
  std::string out, err;
  double seconds;
};

/// Runs `command` (a shell line) with a 60 s limit (a hang is a failure, not a stuck test);
/// stdout and stderr kept in `tmp`.
inline ToolResult runTool(const TempDir& tmp, const std::string& command) {
  const std::string out = tmp.file("stdout"), err = tmp.file("stderr");
  const auto t0 = std::chrono::steady_clock::now();
  const int status = run("timeout -s KILL 60 " + command + " > '" + out + "' 2> '" + err + "'");
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return {status, readFile(out), readFile(err), s};
}

}  // namespace budget_slam::dataset::test
