#include "budget_slam/report/OutputFolder.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>

#include "budget_slam/core/Error.h"
#include "budget_slam/report/FileWrite.h"

namespace fs = std::filesystem;

namespace budget_slam::report {
namespace {

constexpr const char* kEarlierPrefix = "earlier_run_";

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// A folder compare made for one of its runs: it holds a run's summary or configuration.
bool isRunFolder(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec) &&
         (fs::exists(p / "summary.json", ec) || fs::exists(p / "config_used.ini", ec) ||
          fs::exists(p / "steps.csv", ec));
}

bool isOurs(const fs::directory_entry& e) {
  const std::string name = e.path().filename().string();
  if (name.rfind(kEarlierPrefix, 0) == 0) return false;  // history of earlier forced runs
  const auto& names = OutputFolder::outputNames();
  std::string base = name;
  if (endsWith(base, ".tmp")) base.resize(base.size() - 4);  // an atomic write cut short
  if (std::find(names.begin(), names.end(), base) != names.end()) return true;
  return isRunFolder(e.path());
}

std::string stamp(fs::file_time_type t) {
  // file_time_type's clock is not system_clock in C++17: convert through "now" on both clocks.
  const auto sys = std::chrono::system_clock::now() +
                   std::chrono::duration_cast<std::chrono::system_clock::duration>(
                       t - fs::file_time_type::clock::now());
  const std::time_t tt = std::chrono::system_clock::to_time_t(sys);
  std::tm tm{};
  localtime_r(&tt, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y%m%d-%H%M%S", &tm);
  return buf;
}

}  // namespace

const std::vector<std::string>& OutputFolder::outputNames() {
  static const std::vector<std::string> names = {
      "summary.json",   "steps.csv", "evictions.csv",    "trajectory.tum",
      "landmarks.csv",  "map.png",   "config_used.ini",  "ground_truth.tum",
      "map.3Dscene",    "states",    "comparison.csv",   "comparison.md",
      "comparison.png", "reference", "session_state.txt"};
  return names;
}

OutputFolder::OutputFolder(std::string path, bool force) : path_(std::move(path)) {
  std::error_code ec;
  if (fs::exists(path_, ec)) {
    if (!fs::is_directory(path_, ec))
      throw ConfigError("output folder '" + path_ + "' exists and is not a folder");
    if (!fs::is_empty(path_, ec)) {
      if (!force)
        throw ConfigError("output folder '" + path_ +
                          "' is not empty (use --force to write into it)");
      moveEarlierRun();
    }
  }
  fs::create_directories(path_, ec);
  if (ec)
    throw ConfigError("output folder '" + path_ + "' cannot be created (" + ec.message() + ")");
  reserveFileSpace(file("summary.json"), kSummaryReserve);
}

void OutputFolder::moveEarlierRun() {
  std::error_code ec;
  std::vector<fs::path> ours;
  fs::file_time_type newest = fs::file_time_type::min();
  for (const auto& e : fs::directory_iterator(path_, ec)) {
    if (!isOurs(e)) continue;
    ours.push_back(e.path());
    newest = std::max(newest, fs::last_write_time(e.path(), ec));
  }
  if (ours.empty()) return;
  const fs::path summary = fs::path(path_) / "summary.json";
  const auto when = fs::exists(summary, ec) ? fs::last_write_time(summary, ec) : newest;

  std::string name = kEarlierPrefix + stamp(when);
  for (int k = 2; fs::exists(fs::path(path_) / name, ec); ++k)
    name = kEarlierPrefix + stamp(when) + "_" + std::to_string(k);
  const fs::path dest = fs::path(path_) / name;
  fs::create_directory(dest, ec);
  if (ec)
    throw ConfigError("output folder '" + path_ + "': cannot make '" + name +
                      "' for the earlier run's files (" + ec.message() + ")");
  for (const auto& p : ours) {
    fs::rename(p, dest / p.filename(), ec);  // same file system: a move, never a copy
    if (ec)
      throw ConfigError("output folder '" + path_ + "': cannot move the earlier run's '" +
                        p.filename().string() + "' into '" + name + "' (" + ec.message() + ")");
  }
  earlier_run_ = name;
}

std::string OutputFolder::file(const std::string& name) const {
  const fs::path p = fs::path(path_) / name;
  std::error_code ec;
  if (p.has_parent_path()) fs::create_directories(p.parent_path(), ec);
  return p.string();
}

}  // namespace budget_slam::report
