// budget-convert: a public planar landmark-SLAM dataset -> MRPT rawlog + ground truth + sidecar
// ini. All the work is in budget_slam::dataset (Converters.h, DatasetFiles.h).
#include <tclap/CmdLine.h>

#include <iostream>
#include <limits>
#include <set>

#include "budget_slam/core/CommandLine.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/Converters.h"
#include "budget_slam/dataset/DatasetFiles.h"

int main(int argc, char** argv) {
  using namespace budget_slam;
  CapturedUsage usage(  // outlives cmd, which only borrows it
      "   budget-convert --format isam data/datasets/victoria_park_gtsam/victoria_park.txt.gz "
      "-o vp.rawlog\n"
      "      GTSAM's Victoria Park text file (odometry and range-bearing lines)\n"
      "   budget-convert --format isam --steps 3500: "
      "data/datasets/victoria_park_gtsam/victoria_park.txt.gz -o vp_from3500.rawlog\n"
      "      the same from step 3500 on, renumbered from 0\n"
      "   budget-convert --format utias --robot 2 --frame-robot 1 "
      "data/datasets/utias_mrclam/MRCLAM_Dataset7 -o mrclam7_robot2.rawlog\n"
      "      UTIAS MRCLAM robot 2, ground truth in robot 1's world frame\n"
      "   budget-convert --format g2o data/datasets/g2o_sample/simulation-pose-landmark.g2o.gz "
      "-o g2o.rawlog\n"
      "   budget-convert --format freiburg data/datasets/freiburg_slam_course -o freiburg.rawlog\n"
      "      (a folder holding world.dat and sensor_data.dat, gzipped or not)\n"
      "   Each writes the rawlog, its ground truth when the dataset has one, and a sidecar .ini\n"
      "   with the sensor noise, which budget-slam reads after -c.\n");
  try {
    TCLAP::CmdLine cmd(
        "Converts a planar landmark-SLAM dataset into a gzip MRPT rawlog, its ground-truth files "
        "(when the dataset has ground truth) and a sidecar .ini with the sensor noise.",
        ' ', "0.1");
    std::vector<std::string> formats = {"isam", "g2o", "utias", "freiburg"};
    TCLAP::ValuesConstraint<std::string> format_values(formats);
    TCLAP::ValueArg<std::string> format("f", "format", "input format", true, "", &format_values,
                                        cmd);
    std::vector<int> robots = {1, 2, 3, 4, 5};
    TCLAP::ValuesConstraint<int> robot_values(robots);
    TCLAP::ValueArg<int> robot("r", "robot", "UTIAS MRCLAM robot number", false, 1, &robot_values,
                               cmd);
    TCLAP::ValueArg<int> frame_robot(
        "", "frame-robot",
        "UTIAS: ground truth in the frame of this robot's true start pose, so that the robots of "
        "one dataset share a world frame (default: the converted robot's own)",
        false, 0, "N", cmd);
    TCLAP::ValueArg<std::string> steps(
        "", "steps",
        "keep steps FROM (inclusive) to TO (exclusive) of the conversion, renumbered from 0, "
        "with their times and ground truth; either end may be left out (e.g. 3500:)",
        false, "", "FROM:TO", cmd);
    TCLAP::ValueArg<std::string> out("o", "out", "output rawlog (name ends in .rawlog)", true, "",
                                     "out.rawlog", cmd);
    TCLAP::UnlabeledMultiArg<std::string> inputs("INPUT", "input file(s) or folder (see --format)",
                                                 true, "INPUT", cmd);
    cmd.setExceptionHandling(false);
    cmd.setOutput(&usage);
    std::vector<std::string> args(argv, argv + argc);
    args[0] = "budget-convert";  // the usage names the program, not the path it was run by
    cmd.parse(args);
    // INPUT takes every unlabeled word: a word that looks like a flag is an unknown flag.
    for (const auto& in : inputs.getValue())
      if (in.size() > 1 && in[0] == '-') throw UsageError("unknown flag '" + in + "'");

    try {
      dataset::checkRawlogName(out.getValue());  // before a long conversion
    } catch (const Error& e) {
      throw UsageError(e.what());
    }
    std::size_t from = 0, to = std::numeric_limits<std::size_t>::max();
    if (steps.isSet()) {
      const std::string& s = steps.getValue();
      const auto colon = s.find(':');
      const auto number = [&](const std::string& part, std::size_t def) {
        if (part.empty()) return def;
        if (part.find_first_not_of("0123456789") != std::string::npos || part.size() > 15)
          throw TCLAP::ArgParseException("expected FROM:TO, non-negative integers, got '" + s + "'",
                                         "--steps");
        return static_cast<std::size_t>(std::stoull(part));
      };
      if (colon == std::string::npos)
        throw TCLAP::ArgParseException("expected FROM:TO, non-negative integers, got '" + s + "'",
                                       "--steps");
      from = number(s.substr(0, colon), 0);
      to = number(s.substr(colon + 1), to);
    }
    auto dataset = dataset::convertByFormat(format.getValue(), inputs.getValue(), robot.getValue(),
                                            frame_robot.getValue());
    if (steps.isSet()) dataset = dataset::selectSteps(std::move(dataset), from, to);
    dataset::saveDataset(dataset, out.getValue());
    std::size_t sightings = 0;
    std::set<LandmarkId> ids;
    for (const auto& s : dataset.steps)
      if (s.scan)
        for (const auto& r : s.scan->readings) {
          ++sightings;
          ids.insert(r.id);
        }
    std::cout << out.getValue() << ": " << dataset.steps.size() << " steps, " << sightings
              << " sightings of " << ids.size() << " landmarks"
              << (dataset.ground_truth.empty() ? "" : ", with ground truth") << "\n";
    return 0;
  } catch (const TCLAP::ExitException& e) {
    std::cout << usage.text;  // --help or --version, once
    return kExitOk;
  } catch (const TCLAP::ArgException& e) {
    std::cerr << "budget-convert: " << describe(e) << "; see budget-convert --help\n";
    return kExitBadCommandLine;
  } catch (const budget_slam::ConfigError& e) {
    // Every option comes from the command line: a bad one is a bad command line.
    std::cerr << "budget-convert: " << e.what() << "; see budget-convert --help\n";
    return kExitBadCommandLine;
  } catch (const budget_slam::Error& e) {
    std::cerr << "budget-convert: " << e.what() << "\n";
    return kExitFailed;
  } catch (const std::exception& e) {
    std::string what = e.what();
    std::cerr << "budget-convert: internal error: " << what.substr(0, what.find('\n')) << "\n";
    return kExitFailed;
  }
}
