#include "budget_slam/report/OutputFolder.h"

#include <filesystem>

#include "budget_slam/core/Error.h"

namespace fs = std::filesystem;

namespace budget_slam::report {

OutputFolder::OutputFolder(std::string path, bool force) : path_(std::move(path)) {
  std::error_code ec;
  if (fs::exists(path_, ec)) {
    if (!fs::is_directory(path_, ec))
      throw ConfigError("output folder '" + path_ + "' exists and is not a folder");
    if (!force && !fs::is_empty(path_, ec))
      throw ConfigError("output folder '" + path_ +
                        "' is not empty (use --force to write into it)");
  }
  fs::create_directories(path_, ec);
  if (ec)
    throw ConfigError("output folder '" + path_ + "' cannot be created (" + ec.message() + ")");
}

std::string OutputFolder::file(const std::string& name) const {
  const fs::path p = fs::path(path_) / name;
  std::error_code ec;
  if (p.has_parent_path()) fs::create_directories(p.parent_path(), ec);
  return p.string();
}

}  // namespace budget_slam::report
