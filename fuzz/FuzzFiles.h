#pragma once
// Helpers of the fuzz targets that read files: an input split into files at separator lines, a
// scratch folder of the process written afresh each input, and the one-line message contract.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "budget_slam/core/Text.h"

namespace budget_slam::fuzz {

/// The line between two files of one input.
constexpr std::string_view kSeparator = "%%%% next file %%%%\n";

/// `bytes` cut at each separator line into at most `n` files (the last takes the rest; missing
/// ones are empty).
inline std::vector<std::string> splitFiles(std::string_view bytes, std::size_t n) {
  std::vector<std::string> files;
  while (files.size() + 1 < n) {
    const auto at = bytes.find(kSeparator);
    if (at == std::string_view::npos) break;
    files.emplace_back(bytes.substr(0, at));
    bytes.remove_prefix(at + kSeparator.size());
  }
  files.emplace_back(bytes);
  files.resize(n);
  return files;
}

/// A folder of this process under /dev/shm (else the temp folder), emptied; removed at exit.
inline std::filesystem::path scratch(const std::string& name) {
  struct Folder {
    std::filesystem::path path;
    ~Folder() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static Folder folder = [&] {
    std::error_code ec;
    std::filesystem::path base = "/dev/shm";
    if (!std::filesystem::is_directory(base, ec)) base = std::filesystem::temp_directory_path();
    return Folder{base / ("budget_slam_fuzz_" + name + "_" + std::to_string(::getpid()))};
  }();
  std::error_code ec;
  std::filesystem::remove_all(folder.path, ec);
  std::filesystem::create_directories(folder.path);
  return folder.path;
}

inline void writeFile(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

/// The message contract of every Error: one line of valid UTF-8 without a control character
/// (core/Text.h printable(): the file's other bytes escaped), so that it is one line on any
/// terminal and can go into summary.json.
inline void requireOneLine(const char* what) {
  const std::string_view s(what);
  if (!budget_slam::isValidUtf8(s) || budget_slam::printable(s) != s) __builtin_trap();
}

}  // namespace budget_slam::fuzz
