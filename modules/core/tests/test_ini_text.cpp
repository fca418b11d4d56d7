// The ini reader that checks a file before MRPT parses it (core/IniText.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/IniText.h"
#include "budget_slam/core/Text.h"

using namespace budget_slam;
namespace fs = std::filesystem;

namespace {

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

std::string checkError(const std::string& text) {
  return errorOf([&] { checkedIniText(text, "a.ini"); });
}

std::string loadError(const std::string& text) {
  mrpt::config::CConfigFileMemory ini;
  return errorOf([&] { loadIniText(ini, text, "a.ini"); });
}

std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::string kRoot = BUDGET_SLAM_SOURCE_DIR;

}  // namespace

TEST(IniText, AcceptsMrptIniFilesAndTheShippedOnes) {
  for (const std::string f :
       {"tests/data/EKF-SLAM_test_2d.ini", "config.ini", "rawlogs/victoria_park.ini",
        "rawlogs/paper_synthetic.ini", "rawlogs/rooms.ini", "rawlogs/park.ini",
        "rawlogs/mrclam7_robot1.ini"}) {
    mrpt::config::CConfigFileMemory ini;
    EXPECT_NO_THROW(loadIniText(ini, slurp(kRoot + "/" + f), f)) << f;
    std::vector<std::string> sections;
    ini.getAllSections(sections);
    EXPECT_FALSE(sections.empty()) << f;
  }
}

TEST(IniText, ReadsWhatMrptReads) {
  mrpt::config::CConfigFileMemory ini;
  loadIniText(ini,
              "\xEF\xBB\xBF# comment with ${UNDEFINED} is not expanded\n"
              "// a line comment = not a key\n"
              "@define RANGE 0.25\n"
              "[RangeBearingKFSLAM]\r\n"
              "std_sensor_range = ${RANGE}   // metres\n"
              "std_sensor_yaw_deg = $eval{2*RANGE}\n"
              "stds_Q_no_odo = 0.1 \\\n   0.1 2\n"
              "[Other] ; trailing comment\n",
              "a.ini");
  EXPECT_EQ(ini.read_string("RangeBearingKFSLAM", "std_sensor_range", ""), "0.25");
  EXPECT_DOUBLE_EQ(ini.read_double("RangeBearingKFSLAM", "std_sensor_yaw_deg", 0), 0.5);
  EXPECT_EQ(ini.read_string("RangeBearingKFSLAM", "stds_Q_no_odo", ""), "0.1    0.1 2");
  std::vector<std::string> keys;
  ini.getAllKeys("RangeBearingKFSLAM", keys);
  EXPECT_EQ(keys.size(), 3u);  // the "//" line is a comment, not a key
}

TEST(IniText, DuplicatedKeyNamesBothLines) {
  EXPECT_EQ(checkError("[LandmarkBudget]\nmax_landmarks = 5\nseed = 1\nMAX_LANDMARKS=6\n"),
            "a.ini: line 4: duplicated key [LandmarkBudget] MAX_LANDMARKS (first set at line 2)");
  // The same section opened twice still holds each key once.
  EXPECT_EQ(checkError("[A]\nx=1\n[B]\ny=1\n[a]\nx=2\n"),
            "a.ini: line 6: duplicated key [a] x (first set at line 2)");
  EXPECT_EQ(checkError("[A]\nx=1\n[B]\nx=1\n"), "no error");
}

TEST(IniText, BinaryAndNonTextFilesAreRefused) {
  EXPECT_EQ(checkError(std::string("[A]\nx = 1\0\n", 10)),
            "a.ini: line 2: a NUL byte, not a text file");
  EXPECT_EQ(checkError("[A]\nx = \x01\n"), "a.ini: line 2: control byte 0x01, not a text file");
  EXPECT_EQ(checkError("[A]\nname = caf\xE9\n"),
            "a.ini: line 2: byte 0xe9 at column 11 is not UTF-8 text, not an ini file");
  EXPECT_EQ(checkError("[A]\nname = caf\xC3\xA9\n"), "no error");  // UTF-8 is fine
  std::mt19937 rng(7);
  std::string bytes(3000, '\0');
  for (auto& c : bytes) c = static_cast<char>(rng() & 0xFF);
  EXPECT_NE(checkError(bytes).find(", not a"), std::string::npos) << checkError(bytes);
}

TEST(IniText, HugeLinesAndFilesAreRefused) {
  EXPECT_EQ(checkError("[A]\nx = " + std::string(20000, '1') + "\n"),
            "a.ini: line 2: longer than 16384 bytes, not an ini file");
  EXPECT_EQ(checkError(std::string(kMaxIniBytes + 1, '#')),
            "a.ini: larger than 1 MiB, not an ini file");
}

TEST(IniText, ProseAndFilesWithoutSectionsAreNotIni) {
  EXPECT_EQ(checkError(""), "a.ini: holds no [section], not an ini file");
  EXPECT_EQ(checkError("# only comments\n\n"), "a.ini: holds no [section], not an ini file");
  EXPECT_EQ(checkError("x = 1\n[A]\n"), "a.ini: line 1: key 'x' before any [section]");
  EXPECT_EQ(
      checkError("[A]\nThe quick brown fox jumps over the lazy dog, every day of the week.\n"),
      "a.ini: line 2: neither [section], key = value nor a comment: 'The quick brown fox "
      "jumps over the lazy...'");
  EXPECT_EQ(checkError("[A]\nIt is = not a key\n"), "a.ini: line 2: 'It is' is not a key name");
  EXPECT_EQ(checkError("[A]\n= 3\n"), "a.ini: line 2: '= 3' has no key before =");
  EXPECT_EQ(checkError("[A\nx=1\n"), "a.ini: line 1: '[A': no ] closes it");
  EXPECT_EQ(checkError("[]\n"), "a.ini: line 1: '[]' is not a section name");
  EXPECT_EQ(checkError("[A] x=1\n"), "a.ini: line 1: text after the section name: 'x=1'");
  // 1 MB of prose (a README given as -c) fails at its first line.
  std::string prose;
  while (prose.size() < 1000000) prose += "This file is documentation, not a configuration.\n";
  EXPECT_EQ(checkError(prose),
            "a.ini: line 1: neither [section], key = value nor a comment: 'This file is "
            "documentation, not a config...'");
}

TEST(IniText, VariableExpansionFailuresAreErrorsNotTerminate) {
  EXPECT_EQ(checkError("[A]\nx = ${NOPE}\n"),
            "a.ini: line 2: unknown variable ${NOPE} (no @define NOPE above it)");
  EXPECT_EQ(checkError("[A]\nx = ${OPEN\n"), "a.ini: line 2: unclosed ${ (no } after it)");
  EXPECT_EQ(checkError("[A]\nx = $eval{1+2\n"), "a.ini: line 2: unclosed $eval{ (no } after it)");
  EXPECT_EQ(checkError("[A]\nx = $env{HOME\n"), "a.ini: line 2: unclosed $env{ (no } after it)");
  EXPECT_EQ(checkError("[A]\nx = $eval{" + std::string(300, '1') + "}\n"),
            "a.ini: line 2: $eval{...} longer than 256 characters");
  EXPECT_EQ(checkError("[A]\nx = ${LATER}\n@define LATER 1\n"),
            "a.ini: line 2: unknown variable ${LATER} (no @define LATER above it)");
  EXPECT_EQ(checkError("@define\n[A]\n"), "a.ini: line 1: expected @define NAME VALUE");
  EXPECT_EQ(checkError("[A]\nx = 1 @define Y 2\n"), "a.ini: line 2: @define must start its line");
  // What MRPT's expression compiler refuses is still one line, from loadIniText.
  const std::string bad_eval = loadError("[A]\nx = $eval{1+*}\n");
  EXPECT_EQ(bad_eval.rfind("a.ini: ", 0), 0u) << bad_eval;
  EXPECT_EQ(bad_eval.find('\n'), std::string::npos) << bad_eval;
}

TEST(IniText, ReadIniFileRefusesFoldersMissingAndHugeFiles) {
  const fs::path d = fs::temp_directory_path() / "budget_slam_ini_text";
  fs::remove_all(d);
  fs::create_directories(d);
  EXPECT_EQ(errorOf([&] { readIniFile(d.string(), "config file 'D'"); }),
            "config file 'D': is a folder, not a file");
  EXPECT_EQ(errorOf([&] { readIniFile((d / "none.ini").string(), "config file 'N'"); }),
            "config file 'N': no such file or not readable");
  {
    std::ofstream big(d / "big.ini", std::ios::binary);
    big << std::string(kMaxIniBytes + 10, 'x');
  }
  EXPECT_EQ(errorOf([&] { readIniFile((d / "big.ini").string(), "config file 'B'"); }),
            "config file 'B': larger than 1 MiB, not an ini file");
  std::ofstream(d / "ok.ini") << "[A]\nx=1\n";
  EXPECT_EQ(readIniFile((d / "ok.ini").string(), "x"), "[A]\nx=1\n");
}

TEST(IniText, ValuesGivenOutsideAnIniAreOneLineOfText) {
  EXPECT_NO_THROW(checkIniValue("0.25 // m", "--set 'A.x=0.25'"));
  EXPECT_EQ(errorOf([] { checkIniValue("1\n[Evil]", "--set 'A.x'"); }),
            "--set 'A.x': control byte 0x0a in the value");
  EXPECT_EQ(errorOf([] { checkIniValue("\xFF", "--set 'A.x'"); }),
            "--set 'A.x': byte 0xff is not UTF-8 text");
  EXPECT_EQ(errorOf([] { checkIniValue("${HOME}", "--set 'A.x'"); }),
            "--set 'A.x': ${...} is expanded in ini files only, not in a value given here");
}

TEST(IniText, CopyNeverExpandsTwice) {
  mrpt::config::CConfigFileMemory from, to;
  from.write("A", "x", "${NOT_A_VARIABLE}");
  copyIni(from, to);
  EXPECT_EQ(to.read_string("A", "x", ""), "${NOT_A_VARIABLE}");
}

// Deterministic robustness: mutants of a real ini (byte flips, insertions, cuts, duplicated
// lines) end in a parsed ini or a ConfigError, never another exception or a crash.
TEST(IniText, MutantsEndInAnIniOrAConfigError) {
  const std::string base = slurp(kRoot + "/tests/data/EKF-SLAM_test_2d.ini");
  std::mt19937 rng(2024);
  const std::string specials[] = {"${", "}",    "$eval{", "$env{", "@define ", "[",  "]",
                                  "=",  "\\\n", "\n",     "\0",    "\xFF",     "//", "#"};
  int parsed = 0, refused = 0;
  for (int k = 0; k < 3000; ++k) {
    std::string s = base;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = rng() % (s.size() + 1);
      switch (rng() % 4) {
        case 0:
          if (at < s.size()) s[at] = static_cast<char>(rng() & 0xFF);
          break;
        case 1: {
          const std::string& sp = specials[rng() % (sizeof specials / sizeof specials[0])];
          s.insert(at, sp.empty() ? std::string(1, '\0') : sp);
          break;
        }
        case 2:
          s.resize(at);
          break;
        default: {
          const std::size_t from = rng() % (s.size() + 1);
          const std::size_t eol = s.find('\n', from);
          s.insert(at, s.substr(from, eol == std::string::npos ? 40 : eol - from + 1));
        }
      }
    }
    mrpt::config::CConfigFileMemory ini;
    try {
      loadIniText(ini, s, "m.ini");
      ++parsed;
    } catch (const ConfigError& e) {
      ++refused;
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      EXPECT_TRUE(isValidUtf8(what)) << what;
    }
  }
  EXPECT_EQ(parsed + refused, 3000);
  EXPECT_GT(parsed, 100);
  EXPECT_GT(refused, 100);
}
