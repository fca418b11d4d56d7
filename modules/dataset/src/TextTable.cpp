#include "TextTable.h"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "budget_slam/core/Cancellation.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/InputLimits.h"
#include "budget_slam/core/Text.h"

namespace budget_slam::dataset {
namespace {

/// Bytes read from the file at a time.
constexpr unsigned kChunk = 64 * 1024;

std::string hexByte(unsigned char c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02x", c);
  return buf;
}

std::string numberText(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

TextTable::TextTable(std::string path) : path_(std::move(path)) {
  csv_ = path_.size() >= 4 && path_.compare(path_.size() - 4, 4, ".csv") == 0;
  struct stat st {};
  if (::stat(path_.c_str(), &st) != 0) {
    const int err = errno;
    if (::stat((path_ + ".gz").c_str(), &st) != 0)
      throw InputError(path_ + ": cannot open (" + std::strerror(err) + ")");
    path_ += ".gz";
  }
  if (S_ISDIR(st.st_mode)) throw InputError(path_ + ": cannot open (is a directory)");
  // zlib reads plain files through the same calls.
  in_ = gzopen(path_.c_str(), "rb");
  if (!in_) throw InputError(path_ + ": cannot open (" + std::strerror(errno) + ")");
}

TextTable::~TextTable() {
  if (in_) gzclose(in_);
}

bool TextTable::fill() {
  // A stop request ends the reading between two chunks: within one read, whatever the file is.
  if (Cancellation::requested())
    throw Interrupted(std::string("interrupted by ") + Cancellation::signalName() +
                      " while reading " + where(line_ + 1));
  buf_.erase(0, pos_);
  pos_ = 0;
  const std::size_t had = buf_.size();
  buf_.resize(had + kChunk);
  const int n = gzread(in_, &buf_[had], kChunk);
  if (n < 0) {
    int code = Z_OK;
    const char* msg = gzerror(in_, &code);
    throw InputError(path_ + ": read error after line " + std::to_string(line_) + " (" +
                     printable(msg) + ")");
  }
  buf_.resize(had + static_cast<std::size_t>(n));
  return n > 0;
}

bool TextTable::readLine(std::string& line) {
  std::size_t scanned = pos_;  // bytes of this line already checked end here
  for (;;) {
    const std::size_t eol = buf_.find('\n', scanned);
    const std::size_t end = eol == std::string::npos ? buf_.size() : eol;
    // Text only: a binary file is refused at its first byte that is not text, which the message
    // names without echoing it.
    for (std::size_t k = scanned; k < end; ++k) {
      const auto c = static_cast<unsigned char>(buf_[k]);
      if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7f)
        throw InputError(where(line_ + 1) + ": " +
                         (c == 0 ? std::string("a NUL byte") : "control byte " + hexByte(c)) +
                         " at column " + std::to_string(k - pos_ + 1) + ", not a text file");
    }
    if (end - pos_ > limits::kMaxLineBytes)
      throw InputError(where(line_ + 1) + ": line longer than " +
                       std::to_string(limits::kMaxLineBytes) + " bytes, not a data file");
    if (eol != std::string::npos) {
      line.assign(buf_, pos_, eol - pos_);
      pos_ = eol + 1;
      return true;
    }
    const std::size_t checked = end - pos_;
    if (!fill()) {  // the end of the file: a last line without '\n', if any
      line.assign(buf_, pos_, std::string::npos);
      pos_ = buf_.size();
      return !line.empty();
    }
    scanned = checked;  // fill() moved this line's bytes to the start of buf_
  }
}

bool TextTable::next() {
  std::string text;
  while (readLine(text)) {
    ++line_;
    std::size_t bad = 0;
    if (!isValidUtf8(text, &bad))
      fail("byte " + hexByte(static_cast<unsigned char>(text[bad])) + " at column " +
           std::to_string(bad + 1) + " is not UTF-8 text");
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#' || text[first] == '%') continue;
    if (++records_ > limits::kMaxRecords)
      fail("more than " + std::to_string(limits::kMaxRecords) + " records in one file");
    words_.clear();
    if (!csv_) {
      std::istringstream ss(text);
      for (std::string w; ss >> w;) words_.push_back(w);
      return true;
    }
    for (std::size_t at = 0;;) {
      const std::size_t comma = text.find(',', at);
      const std::string field = text.substr(at, comma == std::string::npos ? comma : comma - at);
      const auto b = field.find_first_not_of(" \t\r"), e = field.find_last_not_of(" \t\r");
      if (b == std::string::npos) fail("field " + std::to_string(words_.size() + 1) + " is empty");
      words_.push_back(field.substr(b, e - b + 1));
      if (comma == std::string::npos) break;
      at = comma + 1;
    }
    // A header names the columns ("Time,Subject,Range,Bearing"): the first record, not a number.
    if (!header_checked_) {
      header_checked_ = true;
      char* end = nullptr;
      std::strtod(words_[0].c_str(), &end);
      if (end == words_[0].c_str() || *end != '\0') {
        --records_;
        continue;
      }
    }
    return true;
  }
  words_.clear();
  return false;
}

double TextTable::number(std::size_t i, const std::string& what) const {
  const std::string& w = word(i);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(w.c_str(), &end);
  if (end == w.c_str() || *end != '\0') fail(what + " is not a number: '" + excerpt(w) + "'");
  if (!std::isfinite(v) || errno == ERANGE)
    fail(what + " is not a finite number: '" + excerpt(w) + "'");
  return v;
}

double TextTable::bounded(std::size_t i, const std::string& what, double limit) const {
  const double v = number(i, what);
  if (!(std::abs(v) <= limit))
    fail(what + " = " + excerpt(word(i)) + " is out of range (|" + what + "| must be at most " +
         numberText(limit) + ")");
  return v;
}

long long TextTable::integer(std::size_t i, const std::string& what) const {
  const std::string& w = word(i);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(w.c_str(), &end, 10);
  if (end == w.c_str() || *end != '\0' || errno == ERANGE)
    fail(what + " is not an integer: '" + excerpt(w) + "'");
  return v;
}

long long TextTable::landmarkId(std::size_t i, const std::string& what) const {
  const long long v = integer(i, what);
  if (v < 0 || v > limits::kMaxLandmarkId)
    fail(what + " = " + word(i) + " is not a landmark id (0 to " +
         std::to_string(limits::kMaxLandmarkId) + ")");
  return v;
}

void TextTable::expectFields(std::size_t n, const std::string& record) const {
  if (size() != n)
    fail(record + " needs " + std::to_string(n) + " fields, found " + std::to_string(size()));
}

void TextTable::expectAtLeast(std::size_t n, const std::string& record) const {
  if (size() < n)
    fail(record + " needs at least " + std::to_string(n) + " fields, found " +
         std::to_string(size()));
}

void TextTable::fail(const std::string& what) const {
  // One line whatever a word of the file echoed in `what` holds (core/Text.h printable()).
  throw InputError(where() + ": " + printable(what));
}

std::string TextTable::where() const { return where(line_); }

std::string TextTable::where(std::size_t line) const { return path_ + ":" + std::to_string(line); }

}  // namespace budget_slam::dataset
