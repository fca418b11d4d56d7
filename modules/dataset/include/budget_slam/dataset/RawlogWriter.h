#pragma once
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/Step.h"

namespace budget_slam::dataset {

/// Writes a gzip-compressed MRPT rawlog in the actions-observations form that MRPT's kf-slam and
/// rawlog-edit read: per step its CActionCollection, then its CSensoryFrame. The output depends
/// on the steps only (gzip header without time stamp), so the same steps give the same bytes.
/// Errors are InputError naming the file.
class RawlogWriter {
 public:
  explicit RawlogWriter(const std::string& path);
  ~RawlogWriter();
  RawlogWriter(const RawlogWriter&) = delete;
  RawlogWriter& operator=(const RawlogWriter&) = delete;

  /// Writes step.action and step.frame; when either is null it is built from the parsed fields
  /// (makeAction / makeFrame).
  void write(const Step& step);
  /// Flushes and closes; called by the destructor too (which swallows errors).
  void close();
  std::size_t stepsWritten() const { return steps_; }
  const std::string& path() const { return path_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
  std::size_t steps_ = 0;
};

/// Writes all steps into `path`.
void writeRawlog(const std::string& path, const std::vector<Step>& steps);

}  // namespace budget_slam::dataset
