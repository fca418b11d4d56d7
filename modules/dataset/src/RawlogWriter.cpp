#include "budget_slam/dataset/RawlogWriter.h"

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/Gzip.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/dataset/StepToMrpt.h"

namespace budget_slam::dataset {

struct RawlogWriter::Impl {
  explicit Impl(const std::string& path) : file(path) {}
  PendingFile file;
  GzipCompressor gzip{1};  // MRPT's CFileGZOutputStream level: the same bytes as before
  std::string out;         // compressed bytes not yet written
  bool finished = false, committed = false;
};

RawlogWriter::RawlogWriter(const std::string& path)
    : impl_(std::make_unique<Impl>(path)), path_(path) {}

RawlogWriter::~RawlogWriter() = default;  // an unfinished file is removed (PendingFile)

void RawlogWriter::write(const Step& step) {
  if (impl_->finished) throw Error("rawlog '" + path_ + "': already closed");
  const auto action = step.action     ? step.action
                      : step.odometry ? makeAction(*step.odometry, step.t)
                                      : mrpt::obs::CActionCollection::Create();
  const auto frame = step.frame  ? step.frame
                     : step.scan ? makeFrame(*step.scan, step.t)
                                 : mrpt::obs::CSensoryFrame::Create();
  mrpt::io::CMemoryStream mem;
  try {
    auto arch = mrpt::serialization::archiveFrom(mem);
    arch << *action << *frame;
  } catch (const std::exception& e) {
    throw InputError("rawlog '" + path_ + "': cannot write step " + std::to_string(steps_) + " (" +
                     exceptionLine(e) + ")");
  }
  impl_->gzip.add(
      std::string_view(static_cast<const char*>(mem.getRawBufferData()), mem.getTotalBytesCount()),
      impl_->out);
  if (impl_->out.size() >= (1u << 16)) {
    impl_->file.write(impl_->out);
    impl_->out.clear();
  }
  ++steps_;
}

PendingFile& RawlogWriter::finish() {
  if (!impl_->finished) {
    impl_->finished = true;
    impl_->gzip.finish(impl_->out);
    impl_->file.write(impl_->out);
    impl_->out.clear();
  }
  return impl_->file;
}

void RawlogWriter::close() {
  if (impl_->committed) return;
  finish().commit();
  impl_->committed = true;
}

void writeRawlog(const std::string& path, const std::vector<Step>& steps) {
  RawlogWriter writer(path);
  for (const auto& s : steps) writer.write(s);
  writer.close();
}

}  // namespace budget_slam::dataset
