// libFuzzer target: the run configuration as the application builds it from an ini text and
// --set overrides (loadIniText and loadRunConfig: the text checks, parsing, overlays, the key
// schema, every option loader). Input: leading lines "--set Section.key=value" become overrides,
// the rest is the ini text. Allowed outcomes: a configuration or one ConfigError line. A finding is
// anything else: a crash, a sanitizer report, another exception (an MRPT stack dump reaching the
// user), a hang.
#include <cstddef>
#include <cstdint>
#include <string>

#include "BudgetSlamApp.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/runs/RunConfig.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  budget_slam::runs::RunRequest cli;
  cli.common.rawlog = "/nonexistent/fuzz.rawlog";  // no sidecar ini, no file read
  cli.common.outdir = "/nonexistent/fuzz_out";  // never created: runs::loadRunConfig only names it
  const std::string kSet = "--set ";
  while (text.compare(0, kSet.size(), kSet) == 0) {
    const auto eol = text.find('\n');
    cli.common.sets.push_back(
        text.substr(kSet.size(), eol == std::string::npos ? eol : eol - kSet.size()));
    text.erase(0, eol == std::string::npos ? text.size() : eol + 1);
  }
  try {
    mrpt::config::CConfigFileMemory params;
    budget_slam::loadIniText(params, text, "fuzz.ini");  // as BudgetSlamApp reads -c
    budget_slam::runs::loadRunConfig(params, cli.common, budget_slam::runs::configFlags(cli),
                                     "fuzz.ini");
  } catch (const budget_slam::Error& e) {
    for (const char* p = e.what(); *p; ++p)
      if (*p == '\n') __builtin_trap();
  }
  return 0;
}
