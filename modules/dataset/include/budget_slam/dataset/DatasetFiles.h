#pragma once
#include <string>
#include <vector>

#include "budget_slam/dataset/ConvertedDataset.h"
#include "budget_slam/dataset/RawlogWriter.h"

namespace budget_slam::dataset {

/// Throws InputError "output '<rawlog>': the rawlog name must end in .rawlog" unless it does
/// (the ground-truth and sidecar names are derived from it).
void checkRawlogName(const std::string& rawlog);

/// The files of the dataset `rawlog` names: the rawlog, `<stem>_ground_truth.txt`,
/// `<stem>_ground_truth_robot_path.txt` and the sidecar `<stem>.ini` (docs/DATASETS.md). All four
/// belong to it: budget-slam reads each one that sits next to the rawlog.
std::vector<std::string> datasetFiles(const std::string& rawlog);

/// Before any work (docs/RELIABILITY.md "Converters and simulator"): UsageError when a file of
/// datasetFiles(rawlog) is one of `inputs` or inside an input folder (nothing writes over what it
/// reads, --force or not); without `force`, InputError when one of them exists:
///   "output 'out.ini' exists; give --force to write anyway (it is then kept as 'out.ini.~1~')".
void checkOutputFiles(const std::string& rawlog, const std::vector<std::string>& inputs,
                      bool force);

/// Puts the dataset `rawlog` in place: the rawlog, finished by the caller, with its ground-truth
/// files (those `truth` has) and its sidecar ini. Every file is written under a temporary name
/// first and only then put in place, so that no reader sees a part of one and a failure (a full
/// disk) leaves no new file behind. Nothing is ever replaced: a file of datasetFiles(rawlog) that
/// exists is, with `force`, first renamed to `<name>.~N~` (a numbered backup as GNU's
/// `mv --backup=numbered` makes, never deleted; a stale ground truth would otherwise go with the
/// new rawlog), and without it an InputError. Returns the backups made.
std::vector<std::string> saveDatasetFiles(RawlogWriter& rawlog, const GroundTruth& truth,
                                          const SensorNoise& noise,
                                          const std::vector<std::string>& notes, bool force);

/// writes `dataset`'s steps as `rawlog` and saveDatasetFiles().
std::vector<std::string> saveDataset(const ConvertedDataset& dataset, const std::string& rawlog,
                                     bool force = false);

}  // namespace budget_slam::dataset
