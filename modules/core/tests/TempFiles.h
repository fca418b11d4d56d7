#pragma once
// Helpers of the file-writing tests (core's and report's): a fresh folder, a file's bytes, the
// Error a call throws.
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "budget_slam/core/Error.h"

namespace budget_slam::test {

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A fresh, empty folder `budget_slam_<name>` under the temp folder.
inline std::filesystem::path tempDir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("budget_slam_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

/// The message of the Error `f` throws, "no error" when it throws none.
inline std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace budget_slam::test
