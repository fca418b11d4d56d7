#pragma once
#include <mrpt/config/CConfigFileMemory.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace budget_slam::runs {

/// --cap, typed: a number of landmarks >= 1, or none (no cap). The flag's text is parsed once, by
/// parseCap (RequestChecks.h), whoever filled the request; the merged ini gets text().
struct Cap {
  std::optional<std::size_t> landmarks;  ///< none: no cap
  /// "none" or the number, as config_used.ini records it.
  std::string text() const { return landmarks ? std::to_string(*landmarks) : "none"; }
};

/// What every command is asked with (docs/ARCHITECTURE.md "Command line"): its files and the
/// overrides of the ini. Each command's request holds one.
struct RequestCommon {
  std::string config;             ///< -c; "" = keep params as set by the caller, or ./config.ini
  std::string rawlog;             ///< -i; "" = the ini's [MappingApplication] rawlog_file
  std::string outdir;             ///< -o; "" = the ini's [MappingApplication] logOutput_dir
  std::vector<std::string> sets;  ///< --set Section.key=value, in order
  std::optional<std::size_t> max_steps;  ///< --max-steps (0 = all); none: the ini's
  bool quiet = false;                    ///< --quiet: no progress, no summary on stdout
  bool force = false;                    ///< --force: write into a non-empty output folder
};

/// `run`'s request, typed: the command line parses into it, the Python module fills it. With the
/// ini it is all a run is given (loadRunConfig merges the two).
struct RunRequest {
  RequestCommon common;
  std::string reducer;         ///< --reducer ("" = the ini's)
  std::string backend;         ///< --backend ("" = the ini's)
  std::optional<Cap> cap;      ///< --cap, when given
  std::string resume;          ///< --resume RUN_DIR ("" = a first session)
  std::size_t skip_steps = 0;  ///< --skip-steps N (the rawlog's first N steps unread)
  bool wake_up = false;        ///< --wake-up (find the robot on the resumed map)
};

/// `compare`'s request: one run a reducer (and seed) against the unreduced reference.
struct CompareRequest {
  RequestCommon common;
  std::string backend;                  ///< --backend ("" = the ini's)
  std::optional<Cap> cap;               ///< --cap, when given
  std::vector<std::string> reducers;    ///< --reducers a,b,c (empty: every one but none)
  std::vector<std::uint64_t> seeds;     ///< --seeds, empty = the ini's seed
  unsigned threads = 0;                 ///< --threads, 0 = one a core
  bool offline_optimum = false;         ///< --offline-optimum
  std::vector<std::string> relocalize;  ///< --relocalize a.rawlog,b.rawlog
  std::string reference_trajectory;     ///< --reference-trajectory (with --relocalize)
};

/// `localize`'s request: a traversal (common.rawlog) localized in a run's final map.
struct LocalizeRequest {
  RequestCommon common;
  std::string map_dir;                    ///< --map RUN_DIR
  std::optional<std::string> start_pose;  ///< --start-pose x,y,yaw_deg (none: derive)
  bool wake_up = false;                   ///< --wake-up: find the robot on the map
  std::string reference_trajectory;       ///< --reference-trajectory
};

/// What a request runs with besides its flags: the ini and who runs it.
struct RequestContext {
  mrpt::config::CConfigFileMemory params;  ///< the ini as the caller holds it (no config_text)
  /// The -c file's text, parsed into `params` first (core/IniText.h): a bad text fails the
  /// command as a bad value does (one line, summary.json in the output folder).
  std::optional<std::string> config_text;
  std::string config_label = "config";  ///< the ini's name in messages and summary.json
  std::string writer;                   ///< "budget-slam <version>": the session state's writer
};

}  // namespace budget_slam::runs
