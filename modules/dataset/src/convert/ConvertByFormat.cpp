#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/Converters.h"

namespace budget_slam::dataset {
namespace {

void expectInputs(const std::string& format, const std::vector<std::string>& inputs, std::size_t lo,
                  std::size_t hi, const std::string& what) {
  if (inputs.size() < lo || inputs.size() > hi)
    throw ConfigError("--format " + format + " takes " + what + ", got " +
                      std::to_string(inputs.size()) + " input(s)");
}

}  // namespace

ConvertedDataset convertByFormat(const std::string& format, const std::vector<std::string>& inputs,
                                 int robot, int frame_robot) {
  if (format == "isam") {
    expectInputs(format, inputs, 1, 1, "one file (victoria_park.txt)");
    return convertIsam(inputs[0]);
  }
  if (format == "g2o") {
    expectInputs(format, inputs, 1, 1, "one .g2o file");
    return convertG2o(inputs[0]);
  }
  if (format == "utias") {
    expectInputs(format, inputs, 1, 1, "one MRCLAM dataset folder");
    return convertUtias(inputs[0], robot, frame_robot);
  }
  if (format == "freiburg") {
    expectInputs(format, inputs, 1, 2, "world.dat and sensor_data.dat, or their folder");
    if (inputs.size() == 2) return convertFreiburg(inputs[0], inputs[1]);
    const std::string dir = inputs[0].back() == '/' ? inputs[0] : inputs[0] + "/";
    return convertFreiburg(dir + "world.dat", dir + "sensor_data.dat");
  }
  throw ConfigError("unknown format '" + format + "' (known: isam, g2o, utias, freiburg)");
}

}  // namespace budget_slam::dataset
