#include "budget_slam/dataset/DatasetFiles.h"

#include <filesystem>
#include <memory>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/dataset/GroundTruth.h"
#include "budget_slam/dataset/SidecarIni.h"

namespace fs = std::filesystem;

namespace budget_slam::dataset {
namespace {

/// `<path>.~N~` with the smallest N not taken.
std::string backupName(const std::string& path) {
  std::error_code ec;
  for (int n = 1;; ++n) {
    const std::string b = path + ".~" + std::to_string(n) + "~";
    if (!fs::exists(fs::symlink_status(b, ec))) return b;
  }
}

bool exists(const std::string& path) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}

std::string existsMessage(const std::string& path) {
  return "output '" + path + "' exists; give --force to write anyway (it is then kept as '" +
         backupName(path) + "')";
}

/// The files an input names: itself (and its .gz, which the readers take when it is missing), or
/// the files directly inside an input folder.
std::vector<fs::path> inputFiles(const std::vector<std::string>& inputs) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& in : inputs) {
    if (fs::is_directory(in, ec)) {
      for (const auto& e : fs::directory_iterator(in, ec)) files.push_back(e.path());
    } else {
      files.emplace_back(in);
      files.emplace_back(in + ".gz");
    }
  }
  return files;
}

}  // namespace

void checkRawlogName(const std::string& rawlog) {
  const std::string ext = ".rawlog";
  const auto slash = rawlog.find_last_of('/');
  const std::size_t name = slash == std::string::npos ? 0 : slash + 1;
  if (rawlog.size() <= name + ext.size() ||
      rawlog.compare(rawlog.size() - ext.size(), ext.size(), ext))
    throw InputError("output '" + rawlog + "': the rawlog name must end in .rawlog");
}

std::vector<std::string> datasetFiles(const std::string& rawlog) {
  return {rawlog, groundTruthLandmarksPathFor(rawlog), groundTruthRobotPathFor(rawlog),
          sidecarIniPathFor(rawlog)};
}

void checkOutputFiles(const std::string& rawlog, const std::vector<std::string>& inputs,
                      bool force) {
  checkRawlogName(rawlog);
  const auto ins = inputFiles(inputs);
  for (const auto& out : datasetFiles(rawlog)) {
    if (!exists(out)) continue;
    std::error_code ec;
    for (const auto& in : ins)
      if (fs::equivalent(out, in, ec))
        throw UsageError("output '" + out + "' is the input '" + in.string() +
                         "' (nothing is written over what is read)");
    if (!force) throw InputError(existsMessage(out));
  }
}

std::vector<std::string> saveDatasetFiles(RawlogWriter& rawlog, const GroundTruth& truth,
                                          const SensorNoise& noise,
                                          const std::vector<std::string>& notes, bool force) {
  const auto names = datasetFiles(rawlog.path());
  // Every file whole under its temporary name first.
  std::vector<std::unique_ptr<PendingFile>> others;
  const auto pending = [&](const std::string& path, const std::string& text) {
    others.push_back(std::make_unique<PendingFile>(path));
    others.back()->write(text);
  };
  if (!truth.landmarks.empty()) pending(names[1], groundTruthLandmarksText(truth.landmarks));
  if (!truth.path.empty()) pending(names[2], groundTruthPathText(truth.path));
  pending(names[3], sidecarIniText(noise, notes));
  PendingFile& main = rawlog.finish();
  // The last moment a stop request is honoured: what follows is quick, and all or nothing.
  Cancellation::check();

  std::vector<std::string> backups;
  for (const auto& name : names) {
    if (!exists(name)) continue;
    if (!force) throw InputError(existsMessage(name));
    const std::string b = backupName(name);
    std::error_code ec;
    fs::rename(name, b, ec);
    if (ec)
      throw InputError("output '" + name + "' exists and cannot be kept as '" + b + "' (" +
                       ec.message() + ")");
    backups.push_back(b);
  }
  main.commitNew();
  for (auto& f : others) f->commitNew();
  return backups;
}

std::vector<std::string> saveDataset(const ConvertedDataset& dataset, const std::string& rawlog,
                                     bool force) {
  checkRawlogName(rawlog);
  RawlogWriter writer(rawlog);
  for (const auto& s : dataset.steps) {
    Cancellation::check();
    writer.write(s);
  }
  return saveDatasetFiles(writer, dataset.ground_truth, dataset.noise, dataset.notes, force);
}

}  // namespace budget_slam::dataset
