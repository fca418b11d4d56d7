#include "budget_slam/dataset/DatasetFiles.h"

#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/RawlogWriter.h"
#include "budget_slam/dataset/SidecarIni.h"

namespace budget_slam::dataset {

void saveDataset(const ConvertedDataset& dataset, const std::string& rawlog) {
  const std::string ext = ".rawlog";
  if (rawlog.size() <= ext.size() || rawlog.compare(rawlog.size() - ext.size(), ext.size(), ext))
    throw InputError("output '" + rawlog + "': the rawlog name must end in .rawlog");
  writeRawlog(rawlog, dataset.steps);
  if (!dataset.ground_truth.landmarks.empty())
    saveGroundTruthLandmarks(groundTruthLandmarksPathFor(rawlog), dataset.ground_truth.landmarks);
  if (!dataset.ground_truth.path.empty())
    saveGroundTruthPath(groundTruthRobotPathFor(rawlog), dataset.ground_truth.path);
  writeSidecarIni(sidecarIniPathFor(rawlog), dataset.noise, dataset.notes);
}

}  // namespace budget_slam::dataset
