#include "budget_slam/core/Gzip.h"

#include "budget_slam/core/Error.h"

namespace budget_slam {

GzipCompressor::GzipCompressor(int level) {
  // windowBits 15 + 16: a gzip header and trailer around the deflate stream, as gzopen writes.
  if (deflateInit2(&z_, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw Error("gzip compression cannot start (zlib: out of memory)");
}

GzipCompressor::~GzipCompressor() { deflateEnd(&z_); }

void GzipCompressor::run(std::string_view bytes, int flush, std::string& out) {
  z_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z_.avail_in = static_cast<uInt>(bytes.size());
  char buf[64 * 1024];
  for (;;) {
    z_.next_out = reinterpret_cast<Bytef*>(buf);
    z_.avail_out = sizeof buf;
    const int rc = deflate(&z_, flush);
    if (rc == Z_STREAM_ERROR) throw Error("gzip compression failed (zlib: stream error)");
    out.append(buf, sizeof buf - z_.avail_out);
    if (flush == Z_FINISH ? rc == Z_STREAM_END : (z_.avail_in == 0 && z_.avail_out != 0)) break;
  }
}

void GzipCompressor::add(std::string_view bytes, std::string& out) {
  // zlib counts input in 32-bit units: feed a huge buffer in parts.
  constexpr std::size_t kPart = 1u << 30;
  for (std::size_t at = 0; at < bytes.size(); at += kPart)
    run(bytes.substr(at, kPart), Z_NO_FLUSH, out);
}

void GzipCompressor::finish(std::string& out) {
  if (finished_) return;
  finished_ = true;
  run({}, Z_FINISH, out);
}

std::string gzipBytes(std::string_view bytes, int level) {
  GzipCompressor z(level);
  std::string out;
  z.add(bytes, out);
  z.finish(out);
  return out;
}

}  // namespace budget_slam
