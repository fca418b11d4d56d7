#include "ObjectStream.h"

#include <algorithm>

#include "ReadFailure.h"

namespace budget_slam::dataset::rawlog {
namespace {
// Bytes asked of the source at a time: large enough that a plain file costs few system calls,
// small enough that the stop check runs often (well under a millisecond of inflating apart).
constexpr std::size_t kChunk = 64 * 1024;
}  // namespace

ObjectStream::ObjectStream(std::unique_ptr<ByteSource> source, std::size_t max_object_bytes)
    : source_(std::move(source)), max_object_(max_object_bytes) {}

bool ObjectStream::beginObject() {
  // Drop the bytes of the previous objects once they fill a chunk (keeping what was read ahead),
  // so that the copying stays a small fraction of the bytes read.
  if (pos_ >= kChunk) {
    std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
    end_ -= pos_;
    pos_ = 0;
    // Give memory back after an unusually large object.
    if (buf_.capacity() > 4 * kChunk && end_ <= 2 * kChunk) {
      buf_.resize(2 * kChunk);
      buf_.shrink_to_fit();
    }
  }
  begin_ = pos_;
  if (end_ > pos_) return true;
  fill(0);  // one read: nothing more means the data ended between objects
  return end_ > pos_;
}

const std::uint8_t* ObjectStream::take(std::size_t n) {
  if (end_ - pos_ < n) fill(n);
  const std::uint8_t* p = buf_.data() + pos_;
  pos_ += n;
  return p;
}

void ObjectStream::fill(std::size_t need) {
  if (need > max_object_ - std::min(max_object_, pos_ - begin_))
    throw ReadFailure(
        ReadFailure::Kind::kCorrupt,
        "object larger than the " + std::to_string(max_object_ >> 20) + " MiB an object may take");
  // Read ahead by whole chunks, but never keep more than one object plus one chunk.
  const std::size_t target = std::max(need, kChunk);
  if (buf_.size() < pos_ + target) buf_.resize(pos_ + target);
  while (end_ - pos_ < std::max<std::size_t>(need, 1)) {
    if (stop_ && stop_()) throw ReadStopped{};
    const std::size_t got = source_->read(buf_.data() + end_, std::min(kChunk, buf_.size() - end_));
    if (got == 0) break;
    end_ += got;
    if (need == 0) break;
  }
  if (end_ - pos_ < need)
    throw ReadFailure(ReadFailure::Kind::kEndOfData, "the data ends inside an object");
}

std::uint64_t ObjectStream::room() const {
  std::uint64_t r = max_object_ - std::min(max_object_, pos_ - begin_);
  if (const auto rest = source_->remaining()) r = std::min<std::uint64_t>(r, (end_ - pos_) + *rest);
  return r;
}

bool ObjectStream::roomIsEndOfData() const {
  const auto rest = source_->remaining();
  return rest && (end_ - pos_) + *rest < max_object_ - std::min(max_object_, pos_ - begin_);
}

}  // namespace budget_slam::dataset::rawlog
