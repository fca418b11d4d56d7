#include "budget_slam/runs/RunConfig.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniSchema.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/ekf/MrptIniKeys.h"
#include "budget_slam/engine/BuiltinBackends.h"
#include "budget_slam/localization/LocalizationOptions.h"
#include "budget_slam/metrics/MetricsOptions.h"
#include "budget_slam/reducers/BudgetManager.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/wakeup/WakeUpOptions.h"

namespace fs = std::filesystem;

namespace budget_slam::runs {
namespace {

IniSchema knownKeys() {
  IniSchema schema;
  // The backends' sections first: MRPT's kf-slam keys lead [MappingApplication]'s list.
  for (const auto* e : builtinBackends().entries())
    for (const auto& s : e->sections) schema.addSection(s.name, s.keys());
  schema.addSection(MappingOptions::kSection, MappingOptions::keys());
  schema.addSection(reducers::BudgetOptions::kSection, reducers::BudgetOptions::keys());
  schema.addSection(metrics::MetricsOptions::kSection, metrics::MetricsOptions::keys());
  schema.addSection(LocalizationOptions::kSection, LocalizationOptions::keys());
  schema.addSection(report::ReportOptions::kSection, report::ReportOptions::keys());
  schema.addSection(wakeup::WakeUpOptions::kSection, wakeup::WakeUpOptions::keys());
  for (const auto* e : reducers::builtinReducers().entries())
    for (const auto& s : e->sections) schema.addSection(s.name, s.keys());
  // An MRPT ini shared with MRPT's other applications (simul-landmarks...) keeps their sections.
  for (const auto& s : ekf::mrptOtherAppSections()) schema.addForeignSection(s);
  return schema;
}

/// Where the value of each key came from, for messages (issue 25): the -c file, the rawlog's
/// sidecar, a --set or a flag; later sources replace earlier ones, as their values do.
class KeyOrigins {
 public:
  void note(const std::string& section, const std::string& key, const std::string& origin) {
    origin_[{lowerAscii(section), lowerAscii(key)}] = origin;
  }
  /// Every key of `ini`.
  void noteAll(const mrpt::config::CConfigFileBase& ini, const std::string& origin) {
    std::vector<std::string> sections, keys;
    ini.getAllSections(sections);
    for (const auto& s : sections) {
      ini.getAllKeys(s, keys);
      for (const auto& k : keys) note(s, k, origin);
      note(s, "", origin);  // the section itself (an unknown section)
    }
  }
  /// Where `section`/`key` came from; `fallback` when nothing said.
  std::string of(const std::string& section, const std::string& key,
                 const std::string& fallback) const {
    const auto it = origin_.find({lowerAscii(section), lowerAscii(key)});
    return it == origin_.end() ? fallback : it->second;
  }

 private:
  std::map<std::pair<std::string, std::string>, std::string> origin_;
};

/// --set overrides a key budget-slam reads: its section must be one (another application's
/// section would be set for nothing), and its value one line of text.
void applySet(mrpt::config::CConfigFileMemory& ini, const std::string& set, const IniSchema& schema,
              KeyOrigins& origins) {
  checkSet(set);
  const auto dot = set.find('.'), eq = set.find('=');
  const std::string section = set.substr(0, dot), value = set.substr(eq + 1);
  const std::string key = set.substr(dot + 1, eq - dot - 1);
  const std::string flag = "--set '" + printable(set) + "'";
  if (!schema.hasSection(section))
    throw ConfigError(flag + ": " + schema.unknownSection(printable(section)),
                      ConfigErrorKind::UnknownSection, flag);
  try {
    checkIniValue(value, flag);
  } catch (const ConfigError& e) {
    throw ConfigError(e.what(), ConfigErrorKind::BadValue, flag);
  }
  ini.write(section, key, value);
  origins.note(section, key, flag);
}

/// Loads every option of every section once, so that a bad value is an error before anything
/// runs, whichever backend and reducer will read it: each registry entry checks its own sections
/// (each loader names section, key and value).
void checkValues(const mrpt::config::CConfigFileBase& ini) {
  for (const auto* e : builtinBackends().entries()) e->validate(ini);
  metrics::MetricsOptions().loadFromConfigFile(ini, metrics::MetricsOptions::kSection);
  // [WakeUp] whether or not this run wakes up (a run without --wake-up, a localize with a start).
  wakeup::WakeUpOptions().loadFromConfigFile(ini, wakeup::WakeUpOptions::kSection);
  for (const auto* e : reducers::builtinReducers().entries()) e->validate(ini);
}

/// Two ini values that say the same: the same text, or the same number ("0.10" and "0.1").
bool sameValue(const std::string& a, const std::string& b) {
  if (a == b) return true;
  char *end_a = nullptr, *end_b = nullptr;
  const double x = std::strtod(a.c_str(), &end_a), y = std::strtod(b.c_str(), &end_b);
  return !a.empty() && !b.empty() && *end_a == '\0' && *end_b == '\0' && x == y;
}

/// A warning a key the sidecar sets over another value of the user's ini (docs/OUTPUTS.md,
/// "Sidecar ini"): the sidecar wins, as documented, but never silently. A key a --set gives
/// (`sets`, Section.key=value) is the user's again: no warning.
std::vector<std::string> sidecarOverrides(const mrpt::config::CConfigFileBase& user,
                                          const mrpt::config::CConfigFileBase& side,
                                          const std::string& user_label, const std::string& sidecar,
                                          const std::vector<std::string>& sets) {
  const auto set_by_flag = [&](const std::string& section, const std::string& key) {
    for (const auto& s : sets)
      if (s.rfind(section + "." + key + "=", 0) == 0) return true;
    return false;
  };
  std::vector<std::string> warnings;
  std::vector<std::string> sections;
  side.getAllSections(sections);
  for (const auto& section : sections) {
    std::vector<std::string> keys;
    side.getAllKeys(section, keys);
    for (const auto& key : keys) {
      if (!user.keyExists(section, key) || set_by_flag(section, key)) continue;
      const std::string mine = user.read_string(section, key, "", false);
      const std::string theirs = side.read_string(section, key, "", false);
      if (sameValue(mine, theirs)) continue;
      warnings.push_back(sidecar + " (the rawlog's sidecar) sets [" + section + "] " + key + " = " +
                         printable(theirs) + " over " + user_label + "'s " + printable(mine) +
                         "; --set " + section + "." + key + "=" + printable(mine) + " keeps yours");
    }
  }
  return warnings;
}

/// One layer of the configuration checked alone (its sections, keys and values), so that a bad
/// value names the file that holds it, even when a later layer replaces it.
void checkLayer(const mrpt::config::CConfigFileBase& layer, const IniSchema& schema) {
  schema.validate(layer);
  reducers::BudgetOptions().loadFromConfigFile(layer, reducers::BudgetOptions::kSection);
  checkValues(layer);
}

std::string resolveRawlog(const std::string& from_ini, const std::string& config_path) {
  if (from_ini.empty() || fs::path(from_ini).is_absolute() || fs::exists(from_ini)) return from_ini;
  if (!config_path.empty()) {
    const fs::path beside = fs::path(config_path).parent_path() / from_ini;
    if (fs::exists(beside)) return beside.string();
  }
  return from_ini;
}

}  // namespace

void checkSet(const std::string& set) {
  const auto dot = set.find('.'), eq = set.find('=');
  const std::string flag = "--set '" + printable(set) + "'";
  if (dot == std::string::npos || eq == std::string::npos || dot == 0 || dot > eq || eq == dot + 1)
    throw ConfigError(flag + ": expected Section.key=value", ConfigErrorKind::Invalid, flag);
}

void checkBackendFlag(const std::string& backend) {
  if (!builtinBackends().has(backend))
    throw UsageError(
        "--backend " + backend + ": must be one of " + builtinBackends().joinedNames(", "),
        ConfigErrorKind::UnknownName, "--backend");
}

void checkCapFor(const RunConfig& rc, const std::optional<Cap>& flag_cap,
                 const std::string& reducer, const std::string& config_label) {
  // A number given with --cap is a request for a capped run; reducer none keeps every landmark,
  // so the run would be unreduced while the user believes it capped (issue 35). compare's none is
  // its unreduced reference, which no cap concerns.
  if (reducer == "none" && flag_cap && flag_cap->landmarks)
    throw ConfigError(
        "--cap " + flag_cap->text() +
            ": reducer none keeps every landmark, so a cap would do nothing; give --reducer NAME "
            "(budget-slam --help lists them), or leave --cap out for the unreduced run",
        ConfigErrorKind::Invalid, "--cap");
  if (rc.budget.max_landmarks) return;
  std::unique_ptr<Reducer> r;
  try {
    r = reducers::builtinReducers().create(reducer, rc.ini, rc.budget.seed);
  } catch (const ConfigError& e) {
    throw ConfigError(config_label + ": " + e.what());
  }
  try {
    reducers::checkCap(rc.budget, r.get());
  } catch (const KeyError& e) {
    // Name where the "none" came from: the flag, or the ini key in its file.
    if (flag_cap) throw ConfigError("--cap none: " + e.why(), e.kind(), "--cap");
    throw ConfigError(config_label + ": " + e.what(), e.kind(), config_label);
  }
}

RunConfig loadRunConfig(const mrpt::config::CConfigFileMemory& params, const RequestCommon& common,
                        const ConfigFlags& flags, const std::string& config_label) {
  RunConfig rc;
  copyIni(params, rc.ini);  // no second ${...} expansion of the values
  const std::string prefix = config_label + ": ";
  KeyOrigins origins;
  origins.noteAll(params, config_label);
  // The rawlog decides which sidecar applies, so read it before the overlays.
  const std::string rawlog_file =
      rc.ini.read_string(MappingOptions::kSection, "rawlog_file", "", false);
  rc.rawlog = common.rawlog.empty() ? resolveRawlog(rawlog_file, common.config) : common.rawlog;
  if (rc.rawlog.empty())
    throw ConfigError("no rawlog: give -i or [MappingApplication] rawlog_file");
  try {
    const IniSchema schema = knownKeys();
    const fs::path sidecar = fs::path(rc.rawlog).replace_extension(".ini");
    if (fs::path(rc.rawlog).extension() == ".rawlog" && fs::exists(sidecar)) {
      rc.sidecar = sidecar.string();
      mrpt::config::CConfigFileMemory side;
      loadIniText(side, readIniFile(rc.sidecar, rc.sidecar), rc.sidecar);
      // Each file's values checked in that file: the sidecar replaces some of the user's, and a
      // bad one on either side must name its own file.
      checkLayer(rc.ini, schema);
      try {
        checkLayer(side, schema);
      } catch (const ConfigError& e) {
        throw ConfigError(rc.sidecar + ": " + e.what(), e.kind(), rc.sidecar);
      }
      rc.warnings = sidecarOverrides(rc.ini, side, config_label, rc.sidecar, common.sets);
      copyIni(side, rc.ini);
      origins.noteAll(side, rc.sidecar);
    }
    for (const auto& s : common.sets) applySet(rc.ini, s, schema, origins);
    if (!flags.reducer.empty()) {
      rc.ini.write(reducers::BudgetOptions::kSection, "reducer", flags.reducer);
      origins.note(reducers::BudgetOptions::kSection, "reducer", "--reducer " + flags.reducer);
    }
    if (flags.cap) {
      rc.ini.write(reducers::BudgetOptions::kSection, "max_landmarks", flags.cap->text());
      origins.note(reducers::BudgetOptions::kSection, "max_landmarks",
                   "--cap " + flags.cap->text());
    }
    if (!flags.backend.empty()) {
      checkBackendFlag(flags.backend);
      rc.ini.write(MappingOptions::kSection, "backend", flags.backend);
    }
    if (!common.rawlog.empty())
      rc.ini.write(MappingOptions::kSection, "rawlog_file", common.rawlog);
    if (common.max_steps)
      rc.ini.write(flags.max_steps_section, "max_steps", std::to_string(*common.max_steps));

    schema.validate(rc.ini);
    rc.mapping.loadFromConfigFile(rc.ini, MappingOptions::kSection);
    rc.budget.loadFromConfigFile(rc.ini, reducers::BudgetOptions::kSection);
    checkValues(rc.ini);
    rc.localization.loadFromConfigFile(rc.ini, LocalizationOptions::kSection);
    rc.report.loadFromConfigFile(rc.ini, report::ReportOptions::kSection);
    reducers::builtinReducers().entry(rc.budget.reducer);  // unknown name: error now
    for (const auto& s : rc.budget.shadow_reducers) reducers::builtinReducers().entry(s);
  } catch (const KeyError& e) {
    // A value or key is named with where it came from: the -c file, the sidecar or the --set.
    const std::string origin = origins.of(e.section(), e.key(), config_label);
    throw ConfigError(origin + ": " + e.what(), e.kind(), origin);
  } catch (const ConfigError& e) {
    // Errors that name their flag or file, and unknown names, speak for themselves; ini errors
    // get the file's name.
    if (!e.origin().empty() || e.kind() == ConfigErrorKind::UnknownName) throw;
    throw ConfigError(prefix + e.what(), e.kind(), config_label);
  }
  rc.outdir = common.outdir.empty() ? rc.mapping.logOutput_dir : common.outdir;
  // compare checks the cap against each reducer it runs (not the ini's reducer).
  if (flags.check_cap) checkCapFor(rc, flags.cap, rc.budget.reducer, config_label);
  return rc;
}

std::string configUsed(const mrpt::config::CConfigFileBase& ini) {
  mrpt::config::CConfigFileMemory used;
  copyIni(ini, used);
  // Every key of every section budget-slam reads, with the value it was read as: the default
  // where no file or flag gave one (issue 35: the sensor noise of a rawlog without a sidecar ran
  // unrecorded). MRPT's kf-slam keys have no default of ours, but the noise they share with the
  // graph backend's table does.
  std::vector<std::pair<std::string, std::vector<OptionInfo>>> tables;
  for (const auto* e : builtinBackends().entries())
    for (const auto& sec : e->sections) tables.emplace_back(sec.name, sec.options);
  tables.emplace_back(MappingOptions::kSection, MappingOptions::describe());
  tables.emplace_back(reducers::BudgetOptions::kSection, reducers::BudgetOptions::describe());
  tables.emplace_back(metrics::MetricsOptions::kSection, metrics::MetricsOptions::describe());
  tables.emplace_back(LocalizationOptions::kSection, LocalizationOptions::describe());
  tables.emplace_back(report::ReportOptions::kSection, report::ReportOptions::describe());
  tables.emplace_back(wakeup::WakeUpOptions::kSection, wakeup::WakeUpOptions::describe());
  for (const auto* e : reducers::builtinReducers().entries())
    for (const auto& sec : e->sections) tables.emplace_back(sec.name, sec.options);
  for (const auto& [section, options] : tables)
    for (const auto& o : options)
      if (o.default_text && !used.keyExists(section, o.key))
        used.write(section, o.key, *o.default_text);
  return "# The configuration this run used: the -c file, the rawlog's sidecar (summary.json's\n"
         "# sidecar_ini), every --set and flag, and the default of every key none of them gave.\n" +
         used.getContent();
}

ConfigFlags configFlags(const RunRequest& request) {
  ConfigFlags flags;
  flags.reducer = request.reducer, flags.backend = request.backend, flags.cap = request.cap;
  return flags;
}

ConfigFlags configFlags(const CompareRequest& request) {
  ConfigFlags flags;
  flags.backend = request.backend, flags.cap = request.cap;
  flags.check_cap = false;  // compare checks the cap against each reducer it runs
  return flags;
}

ConfigFlags configFlags(const LocalizeRequest&) {
  ConfigFlags flags;
  flags.max_steps_section = LocalizationOptions::kSection;
  return flags;
}

namespace {

template <class Request>
RunConfig loadRequestConfig(const Request& request, RequestContext& context) {
  if (context.config_text) {
    context.params.clear();
    loadIniText(context.params, *context.config_text, context.config_label);
  }
  return loadRunConfig(context.params, request.common, configFlags(request), context.config_label);
}

}  // namespace

RunConfig loadRunConfig(const RunRequest& request, RequestContext& context) {
  return loadRequestConfig(request, context);
}

RunConfig loadRunConfig(const CompareRequest& request, RequestContext& context) {
  return loadRequestConfig(request, context);
}

RunConfig loadRunConfig(const LocalizeRequest& request, RequestContext& context) {
  return loadRequestConfig(request, context);
}

}  // namespace budget_slam::runs
