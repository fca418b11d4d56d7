#include "budget_slam/report/OutputFolder.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/report/FolderLock.h"

namespace fs = std::filesystem;

namespace budget_slam::report {
namespace {

constexpr const char* kEarlierPrefix = "earlier_run_";
/// A summary.json larger than this is not one budget-slam wrote.
constexpr std::uintmax_t kMaxSummaryBytes = 1u << 20;

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

bool isLockFile(const fs::path& p) { return p.filename() == FolderLock::kFileName; }

bool isOurs(const fs::directory_entry& e) {
  const std::string name = e.path().filename().string();
  if (name.rfind(kEarlierPrefix, 0) == 0) return false;  // history of earlier forced runs
  if (isLockFile(e.path())) return false;                // the lock, never moved
  const auto& names = OutputFolder::outputNames();
  std::string base = name;
  if (endsWith(base, ".tmp")) base.resize(base.size() - 4);  // an atomic write cut short
  if (std::find(names.begin(), names.end(), base) != names.end()) return true;
  return isRunFolder(e.path());
}

/// True when `dir/summary.json` is one a run wrote when it ended before its first step.
bool unstartedSummary(const fs::path& dir) {
  const fs::path summary = dir / "summary.json";
  std::error_code ec;
  if (!fs::is_regular_file(summary, ec) || fs::file_size(summary, ec) > kMaxSummaryBytes)
    return false;
  std::ifstream in(summary);
  const auto j = nlohmann::json::parse(in, nullptr, false);
  return j.is_object() && j.contains("started") && j["started"] == false;
}

/// Removes what an unstarted run left in `dir` (its outputs, and compare's run folders, which an
/// unstarted compare left unstarted too); files of anyone else stay. True when nothing of the
/// run is left.
bool removeUnstarted(const fs::path& dir) {
  std::error_code ec;
  bool all = true;
  std::vector<fs::directory_entry> entries(fs::directory_iterator(dir, ec), {});
  for (const auto& e : entries) {
    if (!isOurs(e)) continue;
    if (e.is_directory(ec) && isRunFolder(e.path())) {
      if (removeUnstarted(e.path())) fs::remove(e.path(), ec);  // only when left empty
      continue;
    }
    fs::remove_all(e.path(), ec);
    all = all && !ec;
  }
  return all;
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

/// Entries of `dir` other than its lock file.
bool holdsAnything(const std::string& dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (!isLockFile(e.path())) return true;
  return false;
}

}  // namespace

struct OutputFolder::Hold {
  explicit Hold(const std::string& path) : lock(path) {}
  ~Hold() { releaseFileSpace(summary); }  // before the lock goes
  FolderLock lock;
  std::string summary;  ///< path of summary.json, whose space is set aside
};

const std::vector<std::string>& OutputFolder::outputNames() {
  static const std::vector<std::string> names = {
      "summary.json",     "steps.csv",          "evictions.csv",
      "trajectory.tum",   "landmarks.csv",      "map.png",
      "config_used.ini",  "ground_truth.tum",   "map.3Dscene",
      "states",           "comparison.csv",     "comparison.md",
      "comparison.png",   "reference",          "reference.tum",
      "relocalize",       "relocalization.csv", "offline_optimum.csv",
      "session_state.txt"};
  return names;
}

OutputFolder::OutputFolder(std::string path, bool force) : path_(std::move(path)) {
  std::error_code ec;
  if (fs::exists(path_, ec) && !fs::is_directory(path_, ec))
    throw ConfigError("output folder '" + path_ + "' exists and is not a folder");
  fs::create_directories(path_, ec);
  if (ec)
    throw ConfigError("output folder '" + path_ + "' cannot be created (" + ec.message() + ")");
  hold_ = std::make_shared<Hold>(path_);  // from here on, no other run writes here
  if (unstartedSummary(path_)) removeUnstarted(path_);
  if (holdsAnything(path_)) {
    if (!force)
      throw ConfigError("output folder '" + path_ +
                        "' is not empty (use --force to write into it)");
    moveEarlierRun();
  }
  hold_->summary = file("summary.json");
  if (!reserveFileSpace(hold_->summary, kSummaryReserve)) reserveFileSpace(hold_->summary, 4096);
  hold_->lock.announce();
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
