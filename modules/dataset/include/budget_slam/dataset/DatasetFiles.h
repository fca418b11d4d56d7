#pragma once
#include <string>

#include "budget_slam/dataset/ConvertedDataset.h"

namespace budget_slam::dataset {

/// Throws InputError "output '<rawlog>': the rawlog name must end in .rawlog" unless it does
/// (the ground-truth and sidecar names are derived from it).
void checkRawlogName(const std::string& rawlog);

/// Writes `rawlog` (gzip MRPT rawlog), next to it `<stem>_ground_truth.txt` and
/// `<stem>_ground_truth_robot_path.txt` when the dataset has them, and the sidecar `<stem>.ini`.
/// The rawlog name must end in ".rawlog". Errors are InputError naming the file.
void saveDataset(const ConvertedDataset& dataset, const std::string& rawlog);

}  // namespace budget_slam::dataset
