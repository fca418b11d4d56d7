#include "budget_slam/dataset/RawlogWriter.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/StepToMrpt.h"

namespace budget_slam::dataset {

struct RawlogWriter::Impl {
  mrpt::io::CFileGZOutputStream file;
};

RawlogWriter::RawlogWriter(const std::string& path) : impl_(std::make_unique<Impl>()), path_(path) {
  // zlib's gzopen writes a header without modification time, so the bytes depend on the data only.
  if (!impl_->file.open(path)) throw InputError("rawlog '" + path + "': cannot be created");
}

RawlogWriter::~RawlogWriter() {
  try {
    close();
  } catch (...) {
  }
}

void RawlogWriter::write(const Step& step) {
  if (!impl_->file.is_open()) throw InputError("rawlog '" + path_ + "': already closed");
  const auto action = step.action     ? step.action
                      : step.odometry ? makeAction(*step.odometry, step.t)
                                      : mrpt::obs::CActionCollection::Create();
  const auto frame = step.frame  ? step.frame
                     : step.scan ? makeFrame(*step.scan, step.t)
                                 : mrpt::obs::CSensoryFrame::Create();
  try {
    auto arch = mrpt::serialization::archiveFrom(impl_->file);
    arch << *action << *frame;
  } catch (const std::exception& e) {
    throw InputError("rawlog '" + path_ + "': cannot write step " + std::to_string(steps_) + " (" +
                     std::string(e.what()).substr(0, std::string(e.what()).find('\n')) + ")");
  }
  ++steps_;
}

void RawlogWriter::close() {
  if (impl_->file.is_open()) impl_->file.close();
}

void writeRawlog(const std::string& path, const std::vector<Step>& steps) {
  RawlogWriter writer(path);
  for (const auto& s : steps) writer.write(s);
  writer.close();
}

}  // namespace budget_slam::dataset
