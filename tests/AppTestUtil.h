#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "BudgetSlamApp.h"

namespace budget_slam::testing {

inline const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;
inline const std::string kDemo = kRoot + "/rawlogs/kf-slam_demo.rawlog";
inline const std::string kMrptIni = kRoot + "/tests/data/EKF-SLAM_test_2d.ini";

/// A fresh, empty folder under the system temp folder (its parent is created, it is not).
inline std::filesystem::path freshDir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / "budget_slam_tests" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d.parent_path());
  return d;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline nlohmann::json readJson(const std::filesystem::path& p) {
  return nlohmann::json::parse(slurp(p));
}

/// The cells of one CSV line, empty ones included ("a,,b," is {"a", "", "b", ""}); a cell in
/// double quotes may hold commas and "" for a quote (RFC 4180, no line breaks inside).
inline std::vector<std::string> csvCells(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"')
      cells.back().push_back('"'), ++i;
    else if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted)
      cells.emplace_back();
    else
      cells.back().push_back(c);
  }
  return cells;
}

/// Rows of a CSV file with a header, as strings.
inline std::vector<std::vector<std::string>> readCsv(const std::filesystem::path& p) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(slurp(p));
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) rows.push_back(csvCells(line));
  return rows;
}

/// A CSV file read with its header, its cells found by column name.
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  /// The column's index; -1 when the header has no such column.
  int column(const std::string& name) const {
    for (std::size_t c = 0; c < header.size(); ++c)
      if (header[c] == name) return static_cast<int>(c);
    return -1;
  }
  /// Row `row`'s cell of column `name` (throws std::out_of_range when either is missing).
  const std::string& at(std::size_t row, const std::string& name) const {
    const int c = column(name);
    if (c < 0) throw std::out_of_range("no column " + name);
    return rows.at(row).at(static_cast<std::size_t>(c));
  }
};

inline CsvTable readCsvTable(const std::filesystem::path& p) {
  CsvTable t;
  std::istringstream in(slurp(p));
  std::string line;
  if (std::getline(in, line)) t.header = csvCells(line);
  while (std::getline(in, line)) t.rows.push_back(csvCells(line));
  return t;
}

/// What a stderr line of budget-slam says after its program name (docs/OUTPUTS.md "Command line
/// and exit codes"): a failure "error: ", a warning "warning: ", a note "note: "; a stop request
/// and a bad command line say their message alone.
enum class Said { Error, Warning, Note, Interrupted, CommandLine };

inline const char* tagOf(Said said) {
  switch (said) {
    case Said::Error:
      return "error: ";
    case Said::Warning:
      return "warning: ";
    case Said::Note:
      return "note: ";
    default:
      return "";
  }
}

/// The one helper for what a command wrote on stderr: exactly one line, "<program>: ", the tag
/// of `said`, then `message`. A failure names the part that differs (line count, program, tag,
/// message) rather than two whole texts.
inline ::testing::AssertionResult isOneLine(const std::string& err, Said said,
                                            const std::string& message,
                                            const std::string& program = "budget-slam") {
  const auto fail = [&](const std::string& what) {
    return ::testing::AssertionFailure() << what << "\n  stderr: " << err;
  };
  if (err.empty() || err.back() != '\n') return fail("not a whole line");
  if (err.find('\n') != err.size() - 1) return fail("more than one line");
  const std::string head = program + ": ";
  if (err.compare(0, head.size(), head) != 0) return fail("does not start with '" + head + "'");
  const std::string tag = tagOf(said);
  const std::string rest = err.substr(head.size(), err.size() - 1 - head.size());
  if (rest.compare(0, tag.size(), tag) != 0 ||
      (tag.empty() && (rest.rfind("error: ", 0) == 0 || rest.rfind("warning: ", 0) == 0)))
    return fail("not tagged '" + tag + "'");
  if (rest.substr(tag.size()) != message)
    return fail("message differs:\n  expected: " + message +
                "\n  actual:   " + rest.substr(tag.size()));
  return ::testing::AssertionSuccess();
}

/// The lines of `err`, each with its '\n' (a last line without one too), for isOneLine.
inline std::vector<std::string> linesOf(const std::string& err) {
  std::vector<std::string> lines;
  for (std::size_t at = 0; at < err.size();) {
    const std::size_t end = err.find('\n', at);
    const std::size_t next = end == std::string::npos ? err.size() : end + 1;
    lines.push_back(err.substr(at, next - at));
    at = next;
  }
  return lines;
}

/// isOneLine for a failure: exit 1 and "budget-slam: error: <message>".
inline ::testing::AssertionResult isErrorLine(const std::string& err, const std::string& message) {
  return isOneLine(err, Said::Error, message);
}

/// Result of an executable run as a subprocess.
struct Process {
  int exit_code = -1;
  std::string out, err;
};

/// Runs build/bin/<command line> in `cwd` (a shell line starting with the executable's name and
/// its closing quote, e.g. "budget-slam' run -c x": arguments are quoted by the caller), stdout
/// and stderr captured (so stderr is not a terminal).
inline Process runBinary(const std::string& command_line, const std::filesystem::path& cwd) {
  const auto out = cwd / "stdout.txt", err = cwd / "stderr.txt";
  const std::string sh = "cd '" + cwd.string() + "' && '" + BUDGET_SLAM_BINARY_DIR + "/bin/" +
                         command_line + " > '" + out.string() + "' 2> '" + err.string() + "'";
  const int status = std::system(sh.c_str());
  Process p;
  p.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  p.out = slurp(out);
  p.err = slurp(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return p;
}

/// Result of one in-process run of the application.
struct AppResult {
  int exit_code = -1;
  std::string out, err;
};

/// Runs `budget-slam <args...>` in-process, as main() would.
inline AppResult runApp(const std::vector<std::string>& args,
                        std::function<void(app::BudgetSlamApp&)> prepare = {}) {
  AppResult r;
  app::BudgetSlamApp a;
  std::ostringstream out, err;
  a.out = &out;
  a.err = &err;
  std::vector<std::string> argv = {"budget-slam"};
  argv.insert(argv.end(), args.begin(), args.end());
  try {
    a.initialize(argv);
  } catch (const std::exception& e) {
    r.exit_code = 2;
    r.err = std::string("budget-slam: ") + e.what() + "\n";
    return r;
  }
  if (prepare) prepare(a);
  r.exit_code = a.run();
  r.out = out.str();
  r.err = err.str();
  return r;
}

/// `budget-slam run -c <config> -i <rawlog> -o <out> --quiet <extra...>` in-process.
inline AppResult runOn(const std::string& rawlog, const std::filesystem::path& out,
                       std::vector<std::string> extra = {}, const std::string& config = kMrptIni) {
  std::vector<std::string> args = {"run",  "-c", config,       "-i",
                                   rawlog, "-o", out.string(), "--quiet"};
  args.insert(args.end(), extra.begin(), extra.end());
  return runApp(args);
}

/// A run that failed: exit 1, `message` as the one error line and as summary.json's error.
inline void expectFailedRun(const AppResult& r, const std::filesystem::path& out,
                            const std::string& message) {
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(isErrorLine(r.err, message));
  ASSERT_TRUE(std::filesystem::exists(out / "summary.json")) << r.err;
  const auto s = readJson(out / "summary.json");
  EXPECT_EQ(s["status"], "failed");
  EXPECT_EQ(s["error"], message);
}

}  // namespace budget_slam::testing
