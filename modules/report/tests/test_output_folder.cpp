// The folder a run writes into (OutputFolder: never mixes two runs, locked while written, an
// unstarted run's leftovers replaced), and report's files on a full disk (DiskSpaceForTests).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "TempFiles.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/report/CsvWriter.h"
#include "budget_slam/report/FolderLock.h"
#include "budget_slam/report/OutputFolder.h"
#include "budget_slam/report/RunFiles.h"

using namespace budget_slam;
using namespace budget_slam::report;
using namespace budget_slam::test;
namespace fs = std::filesystem;

TEST(CsvWriter, AFailedRowIsNotHalfWritten) {
  const auto d = tempDir("output_folder_csv_fail");
  const std::string p = (d / "steps.csv").string();
  CsvWriter csv(p, {"a", "b"});
  std::string error;
  {
    DiskSpaceForTests disk(7 + 5);
    csv.cell(1.5).cell(std::string("xy")).endRow();                                 // 7 bytes
    error = errorOf([&] { csv.cell(123456.25).cell(std::string("z")).endRow(); });  // 12 more
  }
  EXPECT_EQ(error, "cannot write '" + p + "' (No space left on device)");
  EXPECT_EQ(slurp(p), "a,b\n1.5,xy\n");
}

TEST(RunFiles, SummaryIsValidUtf8WhateverTheErrorTextHolds) {
  const auto d = tempDir("output_folder_utf8");
  const std::string p = (d / "summary.json").string();
  // A corrupt class name echoed by an error message: bytes that are not UTF-8.
  writeJson(p, {{"status", "failed"},
                {"error", std::string("class 'CObs\xff\xfe"
                                      "x' unknown")}});
  const auto j = nlohmann::json::parse(slurp(p));
  EXPECT_EQ(j["status"], "failed");
  EXPECT_EQ(j["error"], "class 'CObs\xEF\xBF\xBD\xEF\xBF\xBDx' unknown");  // U+FFFD each
}

TEST(OutputFolder, AForcedRunMovesTheEarlierRunAside) {
  const auto d = tempDir("output_folder_forced");
  std::ofstream(d / "summary.json") << "{}\n";
  std::ofstream(d / "ground_truth.tum") << "0 0 0 0 0 0 0 1\n";
  std::ofstream(d / "steps.csv.tmp") << "cut";
  fs::create_directories(d / "states");
  std::ofstream(d / "states" / "step_3.txt") << "x";
  std::ofstream(d / "notes.txt") << "mine";

  auto f = std::make_unique<OutputFolder>(d.string(), true);
  const std::string earlier = f->earlierRun();
  ASSERT_EQ(earlier.rfind("earlier_run_", 0), 0u) << earlier;
  const fs::path moved = d / earlier;
  for (const char* name : {"summary.json", "ground_truth.tum", "steps.csv.tmp", "states"}) {
    EXPECT_TRUE(fs::exists(moved / name)) << name;
    EXPECT_FALSE(fs::exists(d / name)) << name;
  }
  EXPECT_TRUE(fs::exists(moved / "states" / "step_3.txt"));
  EXPECT_EQ(slurp(d / "notes.txt"), "mine");  // not ours: left where it is
  // The folder now holds the user's file, the earlier run, the space set aside for the summary and
  // the lock while the run lives.
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(d)) names.insert(e.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"notes.txt", earlier, "summary.json.tmp",
                                          FolderLock::kFileName}));
  std::ofstream(d / "summary.json") << "{}\n";
  f.reset();  // the run ends without writing its summary: its reservation and lock go
  names.clear();
  for (const auto& e : fs::directory_iterator(d)) names.insert(e.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"notes.txt", earlier, "summary.json"}));

  // A second forced run keeps both earlier runs apart.
  OutputFolder g(d.string(), true);
  EXPECT_NE(g.earlierRun(), earlier);
  EXPECT_TRUE(fs::exists(d / g.earlierRun() / "summary.json"));
  EXPECT_TRUE(fs::exists(d / earlier / "summary.json"));
}

// One writer at a time: a second OutputFolder on a folder in use is refused, naming the holder.
TEST(OutputFolder, AFolderInUseIsRefused) {
  const auto d = tempDir("output_folder_in_use");
  auto first = std::make_unique<OutputFolder>(d.string(), false);
  const std::string error = errorOf([&] { OutputFolder second(d.string(), true); });
  EXPECT_EQ(error, "output folder '" + d.string() + "' is in use by process " +
                       std::to_string(::getpid()) + " (it holds " + d.string() + "/" +
                       FolderLock::kFileName +
                       "); wait for it to end or give another output folder");
  OutputFolder copy = *first;  // copies share the lock
  first.reset();
  EXPECT_TRUE(fs::exists(d / FolderLock::kFileName));
}

// A run that ended before its first step ("started": false) made nothing worth keeping: the next
// run replaces its files without --force; anything else of the folder stays.
TEST(OutputFolder, AnUnstartedRunIsReplaced) {
  const auto d = tempDir("output_folder_unstarted");
  std::ofstream(d / "summary.json") << "{\"status\": \"failed\", \"started\": false}\n";
  std::ofstream(d / "config_used.ini") << "[LandmarkBudget]\n";
  fs::create_directories(d / "reference");
  std::ofstream(d / "reference" / "summary.json") << "{}\n";
  {
    OutputFolder f(d.string(), false);
    EXPECT_EQ(f.earlierRun(), "");
  }
  EXPECT_TRUE(fs::is_empty(d));
  // With a file of the user's beside it, the folder is still not empty.
  std::ofstream(d / "summary.json") << "{\"status\": \"failed\", \"started\": false}\n";
  std::ofstream(d / "notes.txt") << "mine";
  EXPECT_EQ(errorOf([&] { OutputFolder f(d.string(), false); }),
            "output folder '" + d.string() + "' is not empty (use --force to write into it)");
  EXPECT_EQ(slurp(d / "notes.txt"), "mine");
  EXPECT_FALSE(fs::exists(d / "summary.json"));
  // A started run's summary keeps its folder as it is.
  fs::remove(d / "notes.txt");
  std::ofstream(d / "summary.json") << "{\"status\": \"failed\", \"started\": true}\n";
  EXPECT_EQ(errorOf([&] { OutputFolder f(d.string(), false); }),
            "output folder '" + d.string() + "' is not empty (use --force to write into it)");
}
