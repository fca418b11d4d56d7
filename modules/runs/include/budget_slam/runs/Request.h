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

/// What a caller asked for, typed (docs/ARCHITECTURE.md "Command line"): the command line parses
/// into it, the Python module fills it from its arguments. With the ini it is all a run, a
/// comparison or a localization is given (loadRunConfig merges the two).
struct Request {
  std::string command;  ///< run | compare | localize
  std::string config;   ///< -c; "" = keep params as set by the caller, or ./config.ini
  std::string rawlog, outdir, reducer, backend;
  std::optional<Cap> cap;                ///< --cap, when given
  std::vector<std::string> sets;         ///< --set Section.key=value
  std::vector<std::string> reducers;     ///< compare: --reducers a,b,c
  unsigned threads = 0;                  ///< compare: --threads, 0 = one a core
  bool offline_optimum = false;          ///< compare: --offline-optimum
  std::optional<std::size_t> max_steps;  ///< --max-steps (0 = all)
  std::vector<std::uint64_t> seeds;      ///< compare: --seeds, empty = the ini's seed
  bool quiet = false, force = false;
  std::string map_dir;                    ///< localize: --map RUN_DIR
  std::optional<std::string> start_pose;  ///< localize: --start-pose x,y,yaw_deg (none: derive)
  std::string reference_trajectory;       ///< localize, compare: --reference-trajectory
  std::vector<std::string> relocalize;    ///< compare: --relocalize a.rawlog,b.rawlog
  std::string resume;                     ///< run: --resume RUN_DIR ("" = a first session)
  std::size_t skip_steps = 0;  ///< run: --skip-steps N (the rawlog's first N steps unread)
  bool wake_up = false;        ///< run: --wake-up (find the robot on the resumed map)
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
