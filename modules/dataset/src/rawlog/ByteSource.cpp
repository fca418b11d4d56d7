#include "ByteSource.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <vector>

#include "ReadFailure.h"

namespace budget_slam::dataset::rawlog {
namespace {

using Kind = ReadFailure::Kind;

class FileSource : public ByteSource {
 public:
  explicit FileSource(const std::string& path) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw ReadFailure(Kind::kIo, std::strerror(errno));
    struct stat st {};
    if (::fstat(fd_, &st) == 0) {
      regular_ = S_ISREG(st.st_mode);
      if (regular_) size_ = static_cast<std::uint64_t>(st.st_size);
    }
  }
  ~FileSource() override {
    if (fd_ >= 0) ::close(fd_);
  }
  FileSource(const FileSource&) = delete;
  FileSource& operator=(const FileSource&) = delete;

  std::size_t read(std::uint8_t* buf, std::size_t n) override {
    if (!regular_) waitForData();
    for (;;) {
      const ssize_t got = ::read(fd_, buf, n);
      if (got >= 0) {
        consumed_ += static_cast<std::uint64_t>(got);
        return static_cast<std::size_t>(got);
      }
      if (errno != EINTR) throw ReadFailure(Kind::kIo, std::strerror(errno));
    }
  }
  std::uint64_t storedConsumed() const override { return consumed_; }
  std::uint64_t storedSize() const override { return size_; }
  std::optional<std::uint64_t> remaining() const override {
    if (!regular_) return std::nullopt;
    return size_ - std::min(size_, consumed_);
  }
  void setStopCheck(std::function<bool()> stop) override { stop_ = std::move(stop); }

 private:
  /// A pipe may stay silent for ever: wait in slices so that a stop request is seen.
  void waitForData() {
    for (;;) {
      if (stop_ && stop_()) throw ReadStopped{};
      pollfd p{fd_, POLLIN, 0};
      const int r = ::poll(&p, 1, 100);
      if (r > 0) return;
      if (r < 0 && errno != EINTR) return;  // read() reports it
    }
  }

  int fd_ = -1;
  bool regular_ = true;
  std::uint64_t consumed_ = 0, size_ = 0;
  std::function<bool()> stop_;
};

class MemorySource : public ByteSource {
 public:
  explicit MemorySource(std::string_view bytes) : bytes_(bytes) {}
  std::size_t read(std::uint8_t* buf, std::size_t n) override {
    const std::size_t k = std::min(n, bytes_.size() - pos_);
    if (k) std::memcpy(buf, bytes_.data() + pos_, k);
    pos_ += k;
    return k;
  }
  std::uint64_t storedConsumed() const override { return pos_; }
  std::uint64_t storedSize() const override { return bytes_.size(); }
  std::optional<std::uint64_t> remaining() const override { return bytes_.size() - pos_; }

 private:
  std::string_view bytes_;
  std::size_t pos_ = 0;
};

/// Hands back the bytes already taken from `raw` (to look at the magic number), then the rest.
class PrefixedSource : public ByteSource {
 public:
  PrefixedSource(std::vector<std::uint8_t> prefix, std::unique_ptr<ByteSource> raw)
      : prefix_(std::move(prefix)), raw_(std::move(raw)) {}
  std::size_t read(std::uint8_t* buf, std::size_t n) override {
    if (pos_ < prefix_.size()) {
      const std::size_t k = std::min(n, prefix_.size() - pos_);
      std::memcpy(buf, prefix_.data() + pos_, k);
      pos_ += k;
      return k;
    }
    return raw_->read(buf, n);
  }
  std::uint64_t storedConsumed() const override {
    return raw_->storedConsumed() - (prefix_.size() - pos_);
  }
  std::uint64_t storedSize() const override { return raw_->storedSize(); }
  std::optional<std::uint64_t> remaining() const override {
    const auto rest = raw_->remaining();
    if (!rest) return std::nullopt;
    return *rest + (prefix_.size() - pos_);
  }
  void setStopCheck(std::function<bool()> stop) override { raw_->setStopCheck(std::move(stop)); }

 private:
  std::vector<std::uint8_t> prefix_;
  std::size_t pos_ = 0;
  std::unique_ptr<ByteSource> raw_;
};

/// zlib's inflate over a raw source with its error state surfaced: MRPT's gzread-based stream
/// turns a failed CRC check or a cut file into a silent end of file.
class GzipSource : public ByteSource {
 public:
  explicit GzipSource(std::unique_ptr<ByteSource> raw) : raw_(std::move(raw)), in_(kChunk) {
    zs_.zalloc = Z_NULL;
    zs_.zfree = Z_NULL;
    zs_.opaque = Z_NULL;
    // 16 + MAX_WBITS: a gzip header and trailer (CRC-32 and length), nothing else.
    if (inflateInit2(&zs_, 16 + MAX_WBITS) != Z_OK)
      throw ReadFailure(Kind::kCompression, "zlib cannot start");
  }
  ~GzipSource() override { inflateEnd(&zs_); }
  GzipSource(const GzipSource&) = delete;
  GzipSource& operator=(const GzipSource&) = delete;

  std::size_t read(std::uint8_t* buf, std::size_t n) override {
    if (failure_) throw *failure_;
    if (finished_ || n == 0) return 0;
    try {
      return inflateSome(buf, n);
    } catch (const ReadFailure& e) {
      // Hand out what inflated before the failure (a CRC check fails only after the member's
      // last byte): the reader then names the step the damage stops, not a step read ahead.
      if (zs_.next_out && zs_.next_out != buf) {
        failure_ = e;
        return static_cast<std::size_t>(zs_.next_out - buf);
      }
      throw;
    }
  }

 private:
  std::size_t inflateSome(std::uint8_t* buf, std::size_t n) {
    zs_.next_out = buf;  // (also tells read() how much was produced when inflate fails)
    zs_.avail_out = static_cast<uInt>(std::min<std::size_t>(n, std::size_t{1} << 30));
    const uInt want = zs_.avail_out;
    for (;;) {
      if (zs_.avail_in == 0) {
        const std::size_t got = raw_->read(in_.data(), in_.size());
        if (got == 0) {
          if (between_members_) {
            finished_ = true;
            return want - zs_.avail_out;
          }
          // Reported like a plain file cut short; the reader names the object it cut.
          throw ReadFailure(Kind::kEndOfData, "the file ends before the end of its gzip data");
        }
        zs_.next_in = in_.data();
        zs_.avail_in = static_cast<uInt>(got);
      }
      if (between_members_) {
        // Another member follows (gzip concatenates them); inflate checks its header.
        between_members_ = false;
        fresh_member_ = true;
        if (inflateReset(&zs_) != Z_OK)
          throw ReadFailure(Kind::kCompression, "zlib cannot restart");
      }
      const int r = inflate(&zs_, Z_NO_FLUSH);
      const uInt produced = want - zs_.avail_out;
      if (produced > 0) fresh_member_ = false;
      switch (r) {
        case Z_OK:
        case Z_BUF_ERROR:  // no progress: it needs more input (read above) or more room
          if (produced > 0 || zs_.avail_out == 0) return produced;
          continue;
        case Z_STREAM_END:
          between_members_ = true;
          ++members_;
          if (produced > 0) return produced;
          continue;
        case Z_NEED_DICT:
          throw ReadFailure(Kind::kCompression, "damaged gzip data, it asks for a dictionary");
        case Z_MEM_ERROR:
          throw ReadFailure(Kind::kCompression, "zlib ran out of memory");
        case Z_DATA_ERROR: {
          const std::string why = zs_.msg ? zs_.msg : "data error";
          if (fresh_member_ && members_ > 0)
            throw ReadFailure(Kind::kCompression,
                              "bytes after the end of the gzip data that are not gzip data, "
                              "zlib: " +
                                  why);
          throw ReadFailure(Kind::kCompression, "damaged gzip data, zlib: " + why);
        }
        default:
          throw ReadFailure(Kind::kCompression, "zlib error " + std::to_string(r));
      }
    }
  }

 public:
  std::uint64_t storedConsumed() const override { return raw_->storedConsumed() - zs_.avail_in; }
  std::uint64_t storedSize() const override { return raw_->storedSize(); }
  std::optional<std::uint64_t> remaining() const override { return std::nullopt; }
  void setStopCheck(std::function<bool()> stop) override { raw_->setStopCheck(std::move(stop)); }

 private:
  static constexpr std::size_t kChunk = 1 << 16;
  std::unique_ptr<ByteSource> raw_;
  std::vector<std::uint8_t> in_;
  z_stream zs_{};
  bool between_members_ = false;  ///< a member ended: another one or the end comes next
  bool fresh_member_ = true;      ///< the current member has produced nothing yet
  int members_ = 0;
  bool finished_ = false;
  std::optional<ReadFailure> failure_;  ///< met after some bytes of the last read; thrown next
};

/// Plain data as is, gzip data inflated: the first two bytes tell (gzip's magic 1f 8b), as
/// zlib's gzopen tells them for MRPT's CFileGZInputStream.
std::unique_ptr<ByteSource> plainOrGzip(std::unique_ptr<ByteSource> raw) {
  std::vector<std::uint8_t> head(2);
  std::size_t have = 0;
  while (have < head.size()) {
    const std::size_t got = raw->read(head.data() + have, head.size() - have);
    if (got == 0) break;
    have += got;
  }
  head.resize(have);
  const bool gzip = have == 2 && head[0] == 0x1f && head[1] == 0x8b;
  auto whole = std::make_unique<PrefixedSource>(std::move(head), std::move(raw));
  if (gzip) return std::make_unique<GzipSource>(std::move(whole));
  return whole;
}

}  // namespace

std::unique_ptr<ByteSource> openFileSource(const std::string& path) {
  return plainOrGzip(std::make_unique<FileSource>(path));
}

std::unique_ptr<ByteSource> openMemorySource(std::string_view bytes) {
  return plainOrGzip(std::make_unique<MemorySource>(bytes));
}

}  // namespace budget_slam::dataset::rawlog
