#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/report/CsvWriter.h"
#include "budget_slam/report/OutputFolder.h"
#include "budget_slam/report/RunFiles.h"

using namespace budget_slam;
using namespace budget_slam::report;
namespace fs = std::filesystem;

namespace {
std::string slurp(const std::string& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("budget_slam_report_" + name);
  fs::remove_all(d);
  return d;
}
}  // namespace

TEST(OutputFolder, RefusesNonEmptyWithoutForceAndNeverDeletes) {
  const auto d = tempDir("folder");
  fs::create_directories(d);
  std::ofstream(d / "keep.txt") << "user data";
  try {
    OutputFolder f(d.string(), false);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              "output folder '" + d.string() + "' is not empty (use --force to write into it)");
  }
  OutputFolder f(d.string(), true);
  std::ofstream(f.file("states/step_3.txt")) << "x";
  EXPECT_TRUE(fs::exists(d / "keep.txt"));
  EXPECT_TRUE(fs::exists(d / "states" / "step_3.txt"));
  EXPECT_NO_THROW(OutputFolder((d / "new_sub").string(), false));
}

TEST(CsvWriter, WritesHeaderRowsAndQuotesAndChecksWidth) {
  const auto d = tempDir("csv");
  fs::create_directories(d);
  const std::string p = (d / "a.csv").string();
  {
    CsvWriter csv(p, {"a", "b", "c"});
    csv.cell(0.1).cell(static_cast<long long>(-3)).cell(std::string("x,y")).endRow();
    csv.cell(1e-300).cell(std::size_t{7}).cell(std::string("q\"t")).endRow();
    csv.cell(1.0);
    EXPECT_THROW(csv.endRow(), std::logic_error);
  }
  EXPECT_EQ(slurp(p), "a,b,c\n0.1,-3,\"x,y\"\n1e-300,7,\"q\"\"t\"\n1");
  EXPECT_EQ(formatDouble(std::nan("")), "nan");
}

TEST(CsvWriter, ANumberThatDoesNotApplyIsAnEmptyField) {
  // NaN is "does not apply": an empty field, as pandas and numpy.genfromtxt read missing values;
  // infinities are values and stay.
  const auto d = tempDir("csv_missing");
  fs::create_directories(d);
  const std::string p = (d / "m.csv").string();
  {
    CsvWriter csv(p, {"run", "ate_m", "nees_mean", "time_s"});
    csv.cell(std::string("mi")).cell(0.5).cell(std::nan("")).cell(std::nan("")).endRow();
    csv.cell(std::string("x"))
        .cell(std::numeric_limits<double>::infinity())
        .cell(-std::numeric_limits<double>::infinity())
        .cell(2.0)
        .endRow();
  }
  EXPECT_EQ(slurp(p), "run,ate_m,nees_mean,time_s\nmi,0.5,,\nx,inf,-inf,2\n");
}

TEST(RunFiles, TumHasEightColumnsAndUnitQuaternions) {
  const auto d = tempDir("tum");
  fs::create_directories(d);
  const std::string p = (d / "trajectory.tum").string();
  writeTrajectoryTum(p, {{0, 1.5, {1, 2, M_PI / 2}}, {1, 2.5, {3, 4, -3.0}}});
  std::istringstream in(slurp(p));
  std::string line;
  int rows = 0;
  double last_t = -1;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::vector<double> v;
    for (double x; ls >> x;) v.push_back(x);
    ASSERT_EQ(v.size(), 8u);
    EXPECT_GT(v[0], last_t);
    last_t = v[0];
    EXPECT_NEAR(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7], 1.0, 1e-12);
    ++rows;
  }
  EXPECT_EQ(rows, 2);
  EXPECT_EQ(slurp(p).substr(0, 29), "1.5 1 2 0 0 0 0.7071067811865");
}
