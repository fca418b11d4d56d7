// Mutants of the converters' four formats (budget-convert) and of a map folder (budget-slam
// localize), fixed seeds (issue 23; docs/RELIABILITY.md "Mutation tests"). Mutations: byte
// flips, inserts, deletes, cuts, appended junk, and structural edits (a line duplicated, dropped
// or swapped; a number replaced by an extreme one: 1e308, nan, -9223372036854775809, ...). Each
// mutant runs the executable in a child process under a 3 GiB address space and a 60 s alarm.
// Asserted for every mutant: no signal (a hang dies by SIGALRM); exit 0, or exit 1 with exactly
// one printable line and never "internal error"; peak RSS under 1 GiB. For a conversion that
// succeeds: the rawlog reads back whole, every reading and odometry step within the bounds, and
// its sidecar ini passes budget-slam's checks; no temporary file left. For a localization: its
// summary.json is valid and says what the exit code says.
#include <gtest/gtest.h>
#include <zlib.h>

#include <chrono>
#include <cmath>
#include <random>
#include <regex>

#include "AppTestUtil.h"
#include "ChildProcess.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/dataset/RawlogReader.h"
#include "budget_slam/runs/RunConfig.h"

using namespace budget_slam;
using namespace budget_slam::testing;
namespace fs = std::filesystem;

namespace {

constexpr int kMutants = 100;         // a format, and for the map folder
constexpr long kMaxRssKiB = 1 << 20;  // 1 GiB
constexpr std::size_t kParallel = 2;  // CI has 2 cores
// The time budget is CPU time, which a loaded machine does not stretch (wall time it does: the
// suite's 180 s limit failed on a shared 2-core machine, issue 35): each mutant's child at most
// kCpuPerChildS, all of them at most kCpuPerMutantS a mutant on average. The wall-clock limit of
// the test (tests/CMakeLists.txt) only catches a hang, with room for a load of 4 and more.
constexpr double kCpuPerChildS = 20;
constexpr double kCpuPerMutantS = 1.5;

const std::string kData = kRoot + "/data/datasets";

/// A gzipped (or plain) text file's first `max_lines` lines.
std::string head(const std::string& path, std::size_t max_lines = SIZE_MAX) {
  gzFile f = gzopen(path.c_str(), "rb");
  std::string text;
  char buf[4096];
  std::size_t lines = 0;
  while (f && lines < max_lines && gzgets(f, buf, sizeof buf)) {
    text += buf;
    lines += !text.empty() && text.back() == '\n';
  }
  if (f) gzclose(f);
  return text;
}

/// The lines of `text` whose first number (a time) is at most `t`.
std::string until(const std::string& text, double t) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);)
    if (line.empty() || line[0] == '#' || std::atof(line.c_str()) <= t) out += line + "\n";
  return out;
}

/// Values a hostile file puts where a number goes.
const std::vector<std::string> kExtremes = {"1e308",
                                            "-1e308",
                                            "1e309",
                                            "nan",
                                            "inf",
                                            "-inf",
                                            "1e23",
                                            "-9223372036854775809",
                                            "9223372036854775808",
                                            "4294967296",
                                            "2147483648",
                                            "-1",
                                            "0",
                                            "-0",
                                            "1e-300",
                                            "",
                                            "abc",
                                            "0x1p999",
                                            "1e5",
                                            "-1e6",
                                            "3.4e38",
                                            "1e-45"};

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t at = 0;
  while (at < text.size()) {
    const auto end = text.find('\n', at);
    lines.push_back(text.substr(at, end == std::string::npos ? std::string::npos : end - at + 1));
    if (end == std::string::npos) break;
    at = end + 1;
  }
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l;
  return s;
}

/// One mutation of `text`; `what` says which.
std::string mutate(std::string text, std::mt19937& rng, std::string& what) {
  const auto pick = [&](std::size_t n) {
    return std::uniform_int_distribution<std::size_t>(0, n == 0 ? 0 : n - 1)(rng);
  };
  const auto byte = [&] {
    return static_cast<char>(std::uniform_int_distribution<int>(0, 255)(rng));
  };
  if (text.empty()) text = "\n";
  switch (pick(8)) {
    case 0: {  // byte flips
      const int n = 1 + static_cast<int>(pick(4));
      for (int k = 0; k < n; ++k) text[pick(text.size())] ^= static_cast<char>(1 + pick(255));
      what = "flip " + std::to_string(n);
      break;
    }
    case 1: {  // insert random bytes
      std::string junk(1 + pick(16), '\0');
      for (auto& c : junk) c = byte();
      text.insert(pick(text.size() + 1), junk);
      what = "insert " + std::to_string(junk.size());
      break;
    }
    case 2: {  // delete a range
      const std::size_t at = pick(text.size()), n = 1 + pick(64);
      text.erase(at, n);
      what = "delete " + std::to_string(n);
      break;
    }
    case 3:  // cut
      text.resize(pick(text.size()));
      what = "cut at " + std::to_string(text.size());
      break;
    case 4: {  // append junk
      std::string junk(1 + pick(4096), '\0');
      for (auto& c : junk) c = byte();
      text += junk;
      what = "append " + std::to_string(junk.size());
      break;
    }
    case 5: {  // a line duplicated, dropped or swapped
      auto lines = splitLines(text);
      if (lines.size() < 2) break;
      const std::size_t a = pick(lines.size()), b = pick(lines.size());
      const std::size_t op = pick(3);
      if (op == 0) lines.insert(lines.begin() + static_cast<long>(a), lines[a]);
      if (op == 1) lines.erase(lines.begin() + static_cast<long>(a));
      if (op == 2) std::swap(lines[a], lines[b]);
      text = joinLines(lines);
      what = std::string(op == 0 ? "duplicate" : op == 1 ? "drop" : "swap") + " line";
      break;
    }
    default: {  // a number (two thirds of the structural edits) replaced by an extreme one
      static const std::regex number(R"([-+]?[0-9]+(\.[0-9]*)?([eE][-+]?[0-9]+)?)");
      std::vector<std::pair<std::size_t, std::size_t>> spans;
      for (auto it = std::sregex_iterator(text.begin(), text.end(), number);
           it != std::sregex_iterator(); ++it)
        spans.emplace_back(static_cast<std::size_t>(it->position()),
                           static_cast<std::size_t>(it->length()));
      if (spans.empty()) break;
      const auto [at, n] = spans[pick(spans.size())];
      const std::string& v = kExtremes[pick(kExtremes.size())];
      text.replace(at, n, v);
      what = "number -> '" + v + "'";
      break;
    }
  }
  return text;
}

/// A format's files, by name inside its input folder, and the budget-convert arguments.
struct Format {
  std::string name;
  std::map<std::string, std::string> files;
  /// budget-convert's input arguments given the mutant's folder.
  std::function<std::vector<std::string>(const fs::path&)> inputs;
};

std::vector<Format> formats() {
  const std::string mr = kData + "/utias_mrclam/MRCLAM_Dataset7/";
  const std::string odo = head(mr + "Robot1_Odometry.dat.gz", 3000);
  double t_end = 0;
  for (const auto& l : splitLines(odo))
    if (!l.empty() && l[0] != '#') t_end = std::atof(l.c_str());
  return {
      {"isam",
       {{"vp.txt", head(kData + "/victoria_park_gtsam/victoria_park.txt.gz", 2000)}},
       [](const fs::path& d) { return std::vector<std::string>{(d / "vp.txt").string()}; }},
      {"g2o",
       {{"s.g2o", head(kData + "/g2o_sample/simulation-pose-landmark.g2o.gz")}},
       [](const fs::path& d) { return std::vector<std::string>{(d / "s.g2o").string()}; }},
      {"utias",
       {{"Barcodes.dat", head(mr + "Barcodes.dat.gz")},
        {"Landmark_Groundtruth.dat", head(mr + "Landmark_Groundtruth.dat.gz")},
        {"Robot1_Odometry.dat", odo},
        {"Robot1_Groundtruth.dat", until(head(mr + "Robot1_Groundtruth.dat.gz"), t_end)},
        {"Robot1_Measurement.dat", until(head(mr + "Robot1_Measurement.dat.gz"), t_end)}},
       [](const fs::path& d) { return std::vector<std::string>{d.string()}; }},
      {"freiburg",
       {{"world.dat", head(kData + "/freiburg_slam_course/world.dat.gz")},
        {"sensor_data.dat", head(kData + "/freiburg_slam_course/sensor_data.dat.gz")}},
       [](const fs::path& d) { return std::vector<std::string>{d.string()}; }},
  };
}

/// Writes `files` into `dir`, one of them (or two, one time in four) mutated.
std::string writeMutant(const fs::path& dir, std::map<std::string, std::string> files,
                        std::mt19937& rng) {
  fs::create_directories(dir);
  std::vector<std::string> names;
  for (const auto& [n, t] : files) names.push_back(n);
  std::string what;
  const int edits = std::uniform_int_distribution<int>(0, 3)(rng) == 0 ? 2 : 1;
  for (int k = 0; k < edits; ++k) {
    const auto& n = names[std::uniform_int_distribution<std::size_t>(0, names.size() - 1)(rng)];
    std::string w;
    files[n] = mutate(files[n], rng, w);
    what += (what.empty() ? "" : ", ") + n + ": " + w;
  }
  for (const auto& [n, t] : files) std::ofstream(dir / n, std::ios::binary) << t;
  return what;
}

std::size_t countLines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

bool printableLine(const std::string& s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if ((c < 0x20 || c == 0x7f) && !(c == '\n' && i + 1 == s.size())) return false;
  }
  return true;
}

/// What a converted dataset must be: a rawlog that reads back whole within the bounds, and a
/// sidecar budget-slam accepts. "" when it is, else why not.
std::string checkConverted(const fs::path& rawlog) {
  try {
    dataset::RawlogReader reader(rawlog.string());
    while (auto s = reader.next()) {
      if (s->odometry) {
        const auto& m = s->odometry->mean;
        if (!(std::abs(m.x) <= limits::kMaxStepTranslation &&
              std::abs(m.y) <= limits::kMaxStepTranslation && std::abs(m.phi) <= limits::kMaxAngle))
          return "step " + std::to_string(s->index) + ": odometry beyond the bounds";
        if (!s->odometry->cov.allFinite()) return "step " + std::to_string(s->index) + ": cov";
      }
      if (s->scan)
        for (const auto& r : s->scan->readings)
          if (!(r.range > 0 && r.range <= limits::kMaxRange &&
                std::abs(r.yaw) <= limits::kMaxAngle))
            return "step " + std::to_string(s->index) + ": a reading beyond the bounds";
    }
    mrpt::config::CConfigFileMemory params;
    loadIniText(params, slurp(kMrptIni), kMrptIni);
    runs::RunRequest cli;
    cli.common.rawlog = rawlog.string();
    cli.common.outdir = (rawlog.parent_path() / "never_made").string();
    // the sidecar and its values checked
    runs::loadRunConfig(params, cli.common, runs::configFlags(cli), kMrptIni);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

/// A mutant's end: exit 0 with nothing on stderr, or exit 1 with one printable line of
/// `program`'s, never an internal error. Returns whether it was refused.
bool expectEndedWell(const ChildExit& r, const std::string& err, const std::string& program) {
  if (r.code == 0) {
    EXPECT_EQ(err, "");
    return false;
  }
  EXPECT_EQ(r.code, 1) << err;
  EXPECT_EQ(countLines(err), 1u) << err;
  EXPECT_EQ(err.rfind(program + ": ", 0), 0u) << err;
  EXPECT_TRUE(printableLine(err)) << err;
  EXPECT_EQ(err.find("internal error"), std::string::npos) << err;
  return true;
}

}  // namespace

TEST(InputMutants, ConverterMutantsFailCleanlyOrConvertWithinBounds) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto dir = freshDir("converter_mutants_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  long peak = 0;
  std::uint32_t seed = 23;  // fixed seeds, one a format
  for (const auto& format : formats()) {
    SCOPED_TRACE(format.name);
    std::mt19937 rng(seed++);
    std::vector<std::string> what(kMutants);
    std::vector<fs::path> in(kMutants), out(kMutants);
    for (int k = 0; k < kMutants; ++k) {
      in[k] = dir / (format.name + "_" + std::to_string(k));
      out[k] = dir / (format.name + "_" + std::to_string(k) + "_out");
      fs::create_directories(out[k]);
      what[k] = writeMutant(in[k], format.files, rng);
    }
    std::map<std::string, int> outcome;
    double cpu = 0;
    runChildren(
        kMutants, kParallel,
        [&](std::size_t k) {
          std::vector<std::string> args = {"-f", format.name};
          for (const auto& a : format.inputs(in[k])) args.push_back(a);
          args.insert(args.end(), {"-o", (out[k] / "c.rawlog").string()});
          return startChild(binary("budget-convert"), args, (out[k] / "err").string(),
                            hostileLimits);
        },
        [&](std::size_t k, const ChildExit& r) {
          SCOPED_TRACE(format.name + " mutant " + std::to_string(k) + " (" + what[k] + ")");
          peak = std::max(peak, r.max_rss_kib);
          EXPECT_LT(r.max_rss_kib, kMaxRssKiB);
          EXPECT_LT(r.cpu_s, kCpuPerChildS);
          cpu += r.cpu_s;
          const std::string err = slurp(out[k] / "err");
          ASSERT_FALSE(r.signaled()) << "signal " << -r.code << ": " << err;
          for (const auto& e : fs::directory_iterator(out[k]))
            EXPECT_NE(e.path().extension(), ".tmp") << e.path();
          if (expectEndedWell(r, err, "budget-convert")) {
            EXPECT_FALSE(fs::exists(out[k] / "c.rawlog"));
            ++outcome["refused"];
          } else {
            EXPECT_EQ(checkConverted(out[k] / "c.rawlog"), "");
            ++outcome["converted"];
          }
        });
    std::cout << format.name << " mutants: " << outcome["converted"] << " converted, "
              << outcome["refused"] << " refused; " << cpu << " s CPU\n";
    EXPECT_LT(cpu, kMutants * kCpuPerMutantS) << format.name;
  }
  std::cout << "peak RSS of a conversion: " << peak / 1024 << " MiB; "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()
            << " s\n";
  if (!HasFailure() && !std::getenv("KEEP_MUTANTS")) fs::remove_all(dir);
}

TEST(InputMutants, MapFolderMutantsFailCleanlyOrLocalize) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto dir = freshDir("map_mutants_" + std::to_string(::getpid()));
  const auto map = dir / "map";
  const auto made = runApp({"run", "-c", kMrptIni, "-i", kDemo, "-o", map.string(), "--quiet",
                            "--reducer", "oldest", "--cap", "15"});
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const std::map<std::string, std::string> files = {{"landmarks.csv", slurp(map / "landmarks.csv")},
                                                    {"summary.json", slurp(map / "summary.json")}};
  std::mt19937 rng(25);
  std::vector<std::string> what(kMutants);
  std::vector<fs::path> in(kMutants), out(kMutants);
  for (int k = 0; k < kMutants; ++k) {
    in[k] = dir / ("map_" + std::to_string(k));
    out[k] = dir / ("loc_" + std::to_string(k));
    what[k] = writeMutant(in[k], files, rng);
  }
  std::map<std::string, int> outcome;
  long peak = 0;
  double cpu = 0;
  runChildren(
      kMutants, kParallel,
      [&](std::size_t k) {
        return startChild(binary("budget-slam"),
                          {"localize", "-c", kMrptIni, "-i", kDemo, "--map", in[k].string(), "-o",
                           out[k].string(), "--quiet", "--set", "Localization.max_steps=60"},
                          out[k].string() + ".err", hostileLimits);
      },
      [&](std::size_t k, const ChildExit& r) {
        SCOPED_TRACE("map mutant " + std::to_string(k) + " (" + what[k] + ")");
        peak = std::max(peak, r.max_rss_kib);
        EXPECT_LT(r.max_rss_kib, kMaxRssKiB);
        EXPECT_LT(r.cpu_s, kCpuPerChildS);
        cpu += r.cpu_s;
        const std::string err = slurp(out[k].string() + ".err");
        ASSERT_FALSE(r.signaled()) << "signal " << -r.code << ": " << err;
        ++outcome[expectEndedWell(r, err, "budget-slam: error") ? "refused" : "localized"];
        ASSERT_TRUE(fs::exists(out[k] / "summary.json")) << err;
        const auto s = readJson(out[k] / "summary.json");
        EXPECT_EQ(s["status"], r.code == 0 ? "ok" : "failed");
        if (r.code == 1) {
          EXPECT_EQ("budget-slam: error: " + s["error"].get<std::string>() + "\n", err);
        }
      });
  std::cout << "map folder mutants: " << outcome["localized"] << " localized, "
            << outcome["refused"] << " refused; peak RSS " << peak / 1024 << " MiB; " << cpu
            << " s CPU; "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()
            << " s\n";
  EXPECT_LT(cpu, kMutants * kCpuPerMutantS);
  if (!HasFailure() && !std::getenv("KEEP_MUTANTS")) fs::remove_all(dir);
}
