#pragma once
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ByteSource.h"

namespace budget_slam::dataset::rawlog {

/// The uncompressed bytes of a rawlog cut into top-level objects. The bytes of the object being
/// checked stay in one contiguous buffer (so that MRPT can then deserialize exactly them from
/// memory); the buffer grows only as real bytes arrive, and never beyond `max_object_bytes`, so
/// that no size declared in the file decides what is allocated.
class ObjectStream {
 public:
  ObjectStream(std::unique_ptr<ByteSource> source, std::size_t max_object_bytes);

  /// Polled before every read from the source (throws ReadStopped when it returns true).
  void setStopCheck(std::function<bool()> stop) {
    stop_ = stop;
    source_->setStopCheck(std::move(stop));
  }

  /// Starts a new top-level object at the cursor; false at a clean end of the data.
  bool beginObject();
  /// The bytes of the current object so far (from beginObject() to the cursor).
  const std::uint8_t* objectData() const { return buf_.data() + begin_; }
  std::size_t objectSize() const { return pos_ - begin_; }

  /// Takes the next `n` bytes of the object: returns a pointer valid until the next take.
  /// Throws ReadFailure: kEndOfData when the data ends first, kCorrupt when the object would
  /// outgrow max_object_bytes.
  const std::uint8_t* take(std::size_t n);
  template <typename T>
  T get() {
    T v;
    std::memcpy(&v, take(sizeof(T)), sizeof(T));
    return v;
  }

  /// Bytes the current object may still take: the per-object limit, and the end of the data
  /// when known (plain files).
  std::uint64_t room() const;
  /// True when the end of the data is known to come within room() (so a size beyond it means
  /// the file ends first, not that the object is too large).
  bool roomIsEndOfData() const;
  std::size_t maxObjectBytes() const { return max_object_; }

  const ByteSource& source() const { return *source_; }

 private:
  void fill(std::size_t need);  // until `need` bytes lie after the cursor

  std::unique_ptr<ByteSource> source_;
  std::size_t max_object_;
  std::function<bool()> stop_;
  std::vector<std::uint8_t> buf_;
  std::size_t begin_ = 0, pos_ = 0, end_ = 0;  // object start, cursor, end of valid bytes
};

}  // namespace budget_slam::dataset::rawlog
