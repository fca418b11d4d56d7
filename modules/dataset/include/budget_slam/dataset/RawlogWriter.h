#pragma once
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/FileWrite.h"
#include "budget_slam/core/Step.h"

namespace budget_slam::dataset {

/// Writes a gzip-compressed MRPT rawlog in the actions-observations form that MRPT's kf-slam and
/// rawlog-edit read: per step its CActionCollection, then its CSensoryFrame. The output depends
/// on the steps only (gzip header without time stamp), so the same steps give the same bytes.
/// The file is written under a temporary name and appears whole or not at all (core/FileWrite.h):
/// a writer destroyed before close() or finish() leaves nothing behind. Errors are Error naming
/// the file ("cannot write '<path>' (No space left on device)").
class RawlogWriter {
 public:
  explicit RawlogWriter(const std::string& path);
  ~RawlogWriter();
  RawlogWriter(const RawlogWriter&) = delete;
  RawlogWriter& operator=(const RawlogWriter&) = delete;

  /// Writes step.action and step.frame; when either is null it is built from the parsed fields
  /// (makeAction / makeFrame).
  void write(const Step& step);
  /// Ends the rawlog and puts it at its path, replacing what is there.
  void close();
  /// Ends the rawlog and returns its file, still under its temporary name: the caller commits it
  /// with the files that go with it (saveDataset).
  PendingFile& finish();
  std::size_t stepsWritten() const { return steps_; }
  const std::string& path() const { return path_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
  std::size_t steps_ = 0;
};

/// Writes all steps into `path` (replacing it).
void writeRawlog(const std::string& path, const std::vector<Step>& steps);

}  // namespace budget_slam::dataset
