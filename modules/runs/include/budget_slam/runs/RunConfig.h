#pragma once
#include <mrpt/config/CConfigFileMemory.h>

#include <optional>
#include <string>
#include <vector>

#include "budget_slam/engine/MappingOptions.h"
#include "budget_slam/localization/LocalizationOptions.h"
#include "budget_slam/reducers/BudgetOptions.h"
#include "budget_slam/report/ReportOptions.h"
#include "budget_slam/runs/Request.h"

namespace budget_slam::runs {

/// The settings of one invocation, merged in order (later wins): the ini (`params`), the rawlog's
/// sidecar `<rawlog>.ini` when it sits next to the rawlog, --set overrides, then the flags
/// --reducer, --cap and --backend. Checked against the known sections and keys.
struct RunConfig {
  mrpt::config::CConfigFileMemory ini;  ///< merged; written as config_used.ini
  MappingOptions mapping;
  reducers::BudgetOptions budget;
  LocalizationOptions localization;  ///< [Localization] (localize, compare --relocalize)
  report::ReportOptions report;      ///< [Report]: figure formats, progress lines
  std::string rawlog;                ///< resolved path of the input rawlog
  std::string sidecar;               ///< sidecar ini applied, "" if none
  std::string outdir;
  /// What the merge replaced that the user wrote (a sidecar's key over the ini's): one line each,
  /// for stderr as "budget-slam: warning: <line>".
  std::vector<std::string> warnings;
};

/// What a command's own flags put into its configuration, over the ini, the sidecar and the
/// --sets (later wins): a run's --reducer, --backend and --cap, a comparison's --backend and --cap.
struct ConfigFlags {
  std::string reducer;     ///< --reducer ("" = not given)
  std::string backend;     ///< --backend ("" = not given)
  std::optional<Cap> cap;  ///< --cap, when given
  /// Where --max-steps goes: [MappingApplication] (run, compare) or [Localization] (localize).
  std::string max_steps_section = MappingOptions::kSection;
  /// The ini's reducer checked against the cap (checkCapFor); compare checks each of its reducers
  /// instead.
  bool check_cap = true;
};

/// The merged configuration of `common` and `flags` over `params`. Throws ConfigError whose
/// message names the file, flag or key at fault.
RunConfig loadRunConfig(const mrpt::config::CConfigFileMemory& params, const RequestCommon& common,
                        const ConfigFlags& flags, const std::string& config_label);
/// The flags of each command's request (its reducer, backend and cap; localize's --max-steps in
/// [Localization]).
ConfigFlags configFlags(const RunRequest& request);
ConfigFlags configFlags(const CompareRequest& request);
ConfigFlags configFlags(const LocalizeRequest& request);
/// The configuration of a request: `context`'s -c text, when it has one, parsed into
/// context.params first (core/IniText.h: a bad text is a ConfigError naming the line), then
/// loadRunConfig with the request's flags and context.config_label.
RunConfig loadRunConfig(const RunRequest& request, RequestContext& context);
RunConfig loadRunConfig(const CompareRequest& request, RequestContext& context);
RunConfig loadRunConfig(const LocalizeRequest& request, RequestContext& context);

/// config_used.ini's text: `ini` (the merged configuration) with the default of every key of
/// every section budget-slam reads that it does not give, under a comment saying so.
std::string configUsed(const mrpt::config::CConfigFileBase& ini);

/// Throws ConfigError unless `set` reads Section.key=value (--set).
void checkSet(const std::string& set);

/// Throws UsageError "--backend x: must be one of ekf, graph" unless the backend registry holds
/// `backend`.
void checkBackendFlag(const std::string& backend);

/// Throws ConfigError, naming --cap or the ini key, when the run's cap is `none` and `reducer`
/// (with its options from rc.ini) needs a cap (reducers::checkCap); and, naming --cap, when
/// `flag_cap` gives a number and `reducer` is none (which keeps every landmark; compare's
/// reference is no reducer it checks).
void checkCapFor(const RunConfig& rc, const std::optional<Cap>& flag_cap,
                 const std::string& reducer, const std::string& config_label);

}  // namespace budget_slam::runs
