#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace budget_slam::dataset::rawlog {

/// The uncompressed bytes of a rawlog, stored plain or gzip-compressed. The two are told apart by
/// gzip's magic bytes (1f 8b), as zlib's gzopen does for MRPT's CFileGZInputStream; unlike
/// gzread, every zlib error (bad data, CRC or length check, data ending early, bytes after the
/// compressed stream) is reported, never taken for the end of the file.
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  /// Up to `n` bytes into `buf`; 0 only at the end of the data. Throws ReadFailure.
  virtual std::size_t read(std::uint8_t* buf, std::size_t n) = 0;
  /// Stored (possibly compressed) bytes consumed so far, and their total [bytes].
  virtual std::uint64_t storedConsumed() const = 0;
  virtual std::uint64_t storedSize() const = 0;
  /// Uncompressed bytes still to come when that is known (plain data), else std::nullopt.
  virtual std::optional<std::uint64_t> remaining() const = 0;
  /// A source that can block (a pipe) waits in slices of 100 ms and asks `stop` between them,
  /// throwing ReadStopped when it says so; files and memory never block.
  virtual void setStopCheck(std::function<bool()> stop) {}
};

/// Opens the file at `path`; throws ReadFailure(kIo) when it cannot be opened.
std::unique_ptr<ByteSource> openFileSource(const std::string& path);
/// Reads `bytes`, which the caller keeps alive while the source is used.
std::unique_ptr<ByteSource> openMemorySource(std::string_view bytes);

}  // namespace budget_slam::dataset::rawlog
