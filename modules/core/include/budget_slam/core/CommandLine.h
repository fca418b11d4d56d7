#pragma once
// The command-line rules shared by budget-slam, budget-simulate and budget-convert
// (docs/OUTPUTS.md "Exit codes"): help and version print once on stdout and exit 0; a bad
// command line is one line on stderr naming the flag, and exit 2.
#include <tclap/CmdLine.h>

#include <cerrno>
#include <cstring>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>

namespace budget_slam {

/// Exit codes of every executable.
enum ExitCode : int {
  kExitOk = 0,              ///< done
  kExitFailed = 1,          ///< the run or conversion failed (bad data, bad ini values, ...)
  kExitBadCommandLine = 2,  ///< unknown command or flag, bad flag value, unreadable -c file
  kExitNotFound = 3,  ///< localize: waking up, the robot was not found on the map (no pose guessed)
  kExitInterrupted = 130,  ///< Ctrl-C or SIGTERM
};

/// TCLAP's usage and version text, kept instead of printed, so that the caller prints it once
/// (TCLAP prints it itself and then throws ExitException).
class CapturedUsage : public TCLAP::StdOutput {
 public:
  explicit CapturedUsage(std::string examples_text = "") : examples(std::move(examples_text)) {}
  void usage(TCLAP::CmdLineInterface& cmd) override {
    std::ostringstream os;
    os << "USAGE:\n\n";
    _shortUsage(cmd, os);
    os << "\n\nWhere:\n\n";
    _longUsage(cmd, os);
    if (!examples.empty()) os << "\nEXAMPLES:\n\n" << examples;
    text = os.str();
  }
  /// Example command lines, one a line, shown after the options by --help.
  std::string examples;
  void version(TCLAP::CmdLineInterface& cmd) override {
    const std::string name = cmd.getProgramName();  // "budget-slam run": the program's name only
    text = name.substr(0, name.find(' ')) + " version " + cmd.getVersion() + "\n";
  }
  std::string text;
};

/// One line for a TCLAP parse error, naming the flag when TCLAP knows it:
/// "Couldn't read argument value from string 'x' (Argument: -r (--robot))".
inline std::string describe(const TCLAP::ArgException& e) {
  const std::string id = e.argId();
  const bool named = id.find_first_not_of(' ') != std::string::npos;
  return e.error() + (named ? " (" + id + ")" : std::string());
}

/// Flushes `out` (stdout). When it cannot take the output (a closed pipe, `| head`: SIGPIPE is
/// ignored, core/StopSignals.h, so the write fails instead of killing the program), writes one
/// line on `err`, "<program>: error: cannot write to stdout (Broken pipe)<note>", and returns
/// false: the program then exits 1, as coreutils' tools do.
inline bool flushStdout(std::ostream& out, std::ostream& err, const std::string& program,
                        const std::string& note = "") {
  errno = 0;
  out.flush();
  if (out) return true;
  const int e = errno;
  err << program << ": error: cannot write to stdout (" << (e ? std::strerror(e) : "closed") << ")"
      << note << std::endl;
  return false;
}

}  // namespace budget_slam
