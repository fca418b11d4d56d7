#pragma once
#include <zlib.h>
#include <string>
#include <string_view>

namespace budget_slam {

/// gzip compression in memory with zlib (deflate, gzip wrapper, no time stamp or name in the
/// header: the same bytes always give the same file, and nothing is written anywhere meanwhile).
/// Errors (out of memory in zlib) throw Error.
class GzipCompressor {
 public:
  /// `level`: 0 (none) to 9 (best); 1 is what MRPT's CFileGZOutputStream uses.
  explicit GzipCompressor(int level = 1);
  ~GzipCompressor();
  GzipCompressor(const GzipCompressor&) = delete;
  GzipCompressor& operator=(const GzipCompressor&) = delete;

  /// Compresses `bytes`; what zlib has ready is appended to `out`.
  void add(std::string_view bytes, std::string& out);
  /// Ends the stream: the rest (and the gzip trailer) is appended to `out`.
  void finish(std::string& out);

 private:
  void run(std::string_view bytes, int flush, std::string& out);
  z_stream z_{};
  bool finished_ = false;
};

/// `bytes` as one gzip file.
std::string gzipBytes(std::string_view bytes, int level = 1);

}  // namespace budget_slam
