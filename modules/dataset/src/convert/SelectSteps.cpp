#include <string>

#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/Converters.h"

namespace budget_slam::dataset {

ConvertedDataset selectSteps(ConvertedDataset d, std::size_t from, std::size_t to) {
  const std::size_t n = d.steps.size();
  if (to > n) to = n;
  if (from >= to)
    throw ConfigError("--steps " + std::to_string(from) + ":" + std::to_string(to) +
                      ": no step of the " + std::to_string(n) + " selected");
  std::vector<Step> kept(std::make_move_iterator(d.steps.begin() + static_cast<long>(from)),
                         std::make_move_iterator(d.steps.begin() + static_cast<long>(to)));
  for (std::size_t k = 0; k < kept.size(); ++k) kept[k].index = k;
  // The path's row k + 1 is the pose of step k, row 0 the start: rows from .. to.
  if (d.ground_truth.path.size() == n + 1)
    d.ground_truth.path =
        std::vector<Pose2>(d.ground_truth.path.begin() + static_cast<long>(from),
                           d.ground_truth.path.begin() + static_cast<long>(to) + 1);
  d.steps = std::move(kept);
  d.notes.push_back("Steps " + std::to_string(from) + " to " + std::to_string(to - 1) + " of the " +
                    std::to_string(n) + " converted (--steps " + std::to_string(from) + ":" +
                    std::to_string(to) + "), renumbered from 0; times, odometry and readings as " +
                    "converted; the first step starts from the pose step " + std::to_string(from) +
                    " started from.");
  return d;
}

}  // namespace budget_slam::dataset
