#include "budget_slam/dataset/DatasetFiles.h"

#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/RawlogWriter.h"
#include "budget_slam/dataset/SidecarIni.h"

namespace budget_slam::dataset {

void checkRawlogName(const std::string& rawlog) {
  const std::string ext = ".rawlog";
  const auto slash = rawlog.find_last_of('/');
  const std::size_t name = slash == std::string::npos ? 0 : slash + 1;
  if (rawlog.size() <= name + ext.size() ||
      rawlog.compare(rawlog.size() - ext.size(), ext.size(), ext))
    throw InputError("output '" + rawlog + "': the rawlog name must end in .rawlog");
}

void saveDataset(const ConvertedDataset& dataset, const std::string& rawlog) {
  checkRawlogName(rawlog);
  writeRawlog(rawlog, dataset.steps);
  if (!dataset.ground_truth.landmarks.empty())
    saveGroundTruthLandmarks(groundTruthLandmarksPathFor(rawlog), dataset.ground_truth.landmarks);
  if (!dataset.ground_truth.path.empty())
    saveGroundTruthPath(groundTruthRobotPathFor(rawlog), dataset.ground_truth.path);
  writeSidecarIni(sidecarIniPathFor(rawlog), dataset.noise, dataset.notes);
}

}  // namespace budget_slam::dataset
