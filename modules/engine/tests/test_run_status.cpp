// The one mapping from how something ended to the exit code, and the status words of
// summary.json.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/engine/RunOutcome.h"
#include "budget_slam/engine/RunStatus.h"

namespace budget_slam::runs {
namespace {

const ErrorKind kKinds[] = {ErrorKind::None,    ErrorKind::CommandLine, ErrorKind::Config,
                            ErrorKind::Input,   ErrorKind::Diverged,    ErrorKind::Output,
                            ErrorKind::Stopped, ErrorKind::Internal};

TEST(ExitCode, EveryStatusAndKind) {
  for (const ErrorKind k : kKinds) {
    SCOPED_TRACE(errorKindName(k));
    EXPECT_EQ(exitCode(RunStatus::Ok, k), 0);
    EXPECT_EQ(exitCode(RunStatus::Interrupted, k), 130);
    EXPECT_EQ(exitCode(RunStatus::NotFound, k), 3);
    EXPECT_EQ(exitCode(RunStatus::Failed, k), k == ErrorKind::CommandLine ? 2 : 1);
  }
}

TEST(ExitCode, OfAnOutcome) {
  RunOutcome o;
  EXPECT_EQ(exitCode(o), 0);
  o.fail(RunStatus::Failed, ErrorKind::Output, "x: no space left on device");
  EXPECT_EQ(exitCode(o), 1);
  o.fail(RunStatus::Interrupted, ErrorKind::Stopped, "interrupted by SIGINT");
  EXPECT_EQ(exitCode(o), 130);
}

TEST(RunStatusWords, AreSummaryJsonsAndReadBack) {
  EXPECT_STREQ(statusName(RunStatus::Ok), "ok");
  EXPECT_STREQ(statusName(RunStatus::Failed), "failed");
  EXPECT_STREQ(statusName(RunStatus::Interrupted), "interrupted");
  EXPECT_STREQ(statusName(RunStatus::NotFound), "not_found");
  for (const auto s :
       {RunStatus::Ok, RunStatus::Failed, RunStatus::Interrupted, RunStatus::NotFound})
    EXPECT_EQ(parseStatus(statusName(s)), s);
  EXPECT_EQ(parseStatus("OK"), std::nullopt);
  EXPECT_EQ(parseStatus(""), std::nullopt);
}

TEST(ErrorKindOf, TheExceptionsType) {
  EXPECT_EQ(errorKindOf(UsageError("--cap x")), ErrorKind::CommandLine);
  EXPECT_EQ(errorKindOf(ConfigError("[LandmarkBudget] seed")), ErrorKind::Config);
  EXPECT_EQ(errorKindOf(InputError("a.rawlog: truncated")), ErrorKind::Input);
  EXPECT_EQ(errorKindOf(Interrupted("interrupted by SIGINT")), ErrorKind::Stopped);
  EXPECT_EQ(errorKindOf(std::bad_alloc()), ErrorKind::Internal);
  EXPECT_EQ(errorKindOf(std::logic_error("bug")), ErrorKind::Internal);
}

TEST(ErrorKindNames, AreDistinct) {
  std::set<std::string> names;
  for (const ErrorKind k : kKinds) names.insert(errorKindName(k));
  EXPECT_EQ(names.size(), std::size(kKinds));
}

}  // namespace
}  // namespace budget_slam::runs
