// RunLife: how every command (run, compare, localize) ends, whatever failed and wherever.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/engine/RunLife.h"
#include "budget_slam/engine/SummaryJson.h"

namespace budget_slam::runs {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const auto d = fs::temp_directory_path() / "budget_slam_tests" / "run_life" / name;
  fs::remove_all(d);
  fs::create_directories(d.parent_path());
  return d;
}

TEST(RunLife, WithoutAFolderItIsTheOneLineAndNothingIsWritten) {
  RunGiven given;
  given.config = "c.ini";
  RunLife life(given);
  const auto end = life.end("bad\nvalue", RunStatus::Failed, ErrorKind::Config);
  EXPECT_EQ(end.line, "bad\\x0avalue");  // one printable line
  EXPECT_EQ(end.outcome.status, RunStatus::Failed);
  EXPECT_EQ(end.outcome.kind, ErrorKind::Config);
  EXPECT_EQ(end.outcome.given.config, std::optional<std::string>("c.ini"));
  EXPECT_EQ(end.outcome.given.started, std::optional<bool>(false));
  EXPECT_EQ(life.path(), "");
}

TEST(RunLife, AFolderOpenedToSayWhyHoldsTheSummaryWithTheGivenBlock) {
  const auto dir = scratch("say_why");
  RunGiven given;
  given.rawlog = "x.rawlog";
  RunLife life(given);
  ASSERT_TRUE(life.openToSayWhy(dir.string(), false));
  const auto end = life.end("no rawlog", RunStatus::Failed, ErrorKind::Input);
  EXPECT_EQ(end.line, "no rawlog");
  const SummaryFile f = readSummary((dir / "summary.json").string());
  EXPECT_EQ(f.outcome.status, RunStatus::Failed);
  EXPECT_EQ(f.outcome.error, "no rawlog");
  EXPECT_EQ(f.json.at("rawlog"), "x.rawlog");
  EXPECT_EQ(f.json.at("started"), false);
}

TEST(RunLife, AnEmptyOutdirOrAFileInTheWayOpensNoFolder) {
  RunLife none;
  EXPECT_FALSE(none.openToSayWhy("", false));
  const auto file = scratch("a_file");
  std::ofstream(file) << "x";
  RunLife blocked;
  EXPECT_FALSE(blocked.openToSayWhy(file.string(), false));
  EXPECT_EQ(blocked.end("why", RunStatus::Failed, ErrorKind::Input).line, "why");
}

TEST(RunLife, TheFinisherEndsTheRunButTheStatusAskedForStays) {
  const auto dir = scratch("finisher");
  RunLife life;
  life.open(dir.string(), false);
  int calls = 0;
  life.setFinisher([&](RunOutcome& o) {
    ++calls;
    EXPECT_EQ(o.error, "interrupted by SIGINT after step 3");
    o.fail(RunStatus::Failed, ErrorKind::Output, "what the engine made of it");
    return std::string("summary.json: no space left on device");
  });
  const auto end =
      life.end("interrupted by SIGINT after step 3", RunStatus::Interrupted, ErrorKind::Stopped);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(end.outcome.status, RunStatus::Interrupted);
  EXPECT_EQ(end.outcome.kind, ErrorKind::Stopped);
  EXPECT_EQ(end.line, "interrupted by SIGINT after step 3; summary.json: no space left on device");
  EXPECT_FALSE(fs::exists(dir / "summary.json"));  // the finisher wrote it, or said why not
}

TEST(RunLife, AFinisherThatThrowsIsSaidWithTheLine) {
  RunLife life;
  life.setFinisher([](RunOutcome&) -> std::string { throw Error("trajectory.tum: disk full"); });
  const auto end = life.end("diverged", RunStatus::Failed, ErrorKind::Diverged);
  EXPECT_EQ(end.line, "diverged; trajectory.tum: disk full");
  EXPECT_EQ(end.outcome.kind, ErrorKind::Diverged);
}

TEST(RunLife, AnEarlierRunMovedAsideIsInTheGivenBlockAndTheNote) {
  const auto dir = scratch("earlier");
  {
    RunLife first;
    first.open(dir.string(), false);
    first.setFinisher([&](RunOutcome& o) {  // a run that made steps: a result worth keeping
      o.given.started = true;
      return first.writeSummaryHere(o);
    });
    first.end("first", RunStatus::Failed, ErrorKind::Input);
  }
  RunLife second;
  second.open(dir.string(), true);
  ASSERT_TRUE(second.given().earlier_run_moved_to);
  const std::string moved = *second.given().earlier_run_moved_to;
  EXPECT_EQ(second.earlierRunNote(),
            second.path() + " held an earlier run; its files were moved to " + moved + "/");
  second.end("second", RunStatus::Failed, ErrorKind::Input);
  EXPECT_EQ(readSummary((dir / "summary.json").string()).json.at("earlier_run_moved_to"), moved);
}

}  // namespace
}  // namespace budget_slam::runs
