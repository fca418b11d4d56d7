#include "TextTable.h"

#include <sys/stat.h>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "budget_slam/core/Error.h"

namespace budget_slam::dataset {

TextTable::TextTable(std::string path) : path_(std::move(path)) {
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

namespace {
/// One line without its '\n'; false at the end of the file. Throws on a read error.
bool readLine(gzFile f, std::string& line, const std::string& path, std::size_t line_no) {
  line.clear();
  char buf[4096];
  while (gzgets(f, buf, sizeof buf)) {
    line += buf;
    if (!line.empty() && line.back() == '\n') {
      line.pop_back();
      return true;
    }
  }
  int code = Z_OK;
  const char* msg = gzerror(f, &code);
  if (code != Z_OK && code != Z_STREAM_END)
    throw InputError(path + ": read error after line " + std::to_string(line_no) + " (" + msg +
                     ")");
  return !line.empty();
}
}  // namespace

bool TextTable::next() {
  std::string text;
  while (readLine(in_, text, path_, line_)) {
    ++line_;
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#' || text[first] == '%') continue;
    words_.clear();
    std::istringstream ss(text);
    for (std::string w; ss >> w;) words_.push_back(w);
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
  if (end == w.c_str() || *end != '\0') fail(what + " is not a number: '" + w + "'");
  if (!std::isfinite(v) || errno == ERANGE) fail(what + " is not a finite number: '" + w + "'");
  return v;
}

long long TextTable::integer(std::size_t i, const std::string& what) const {
  const std::string& w = word(i);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(w.c_str(), &end, 10);
  if (end == w.c_str() || *end != '\0' || errno == ERANGE)
    fail(what + " is not an integer: '" + w + "'");
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

void TextTable::fail(const std::string& what) const { throw InputError(where() + ": " + what); }

std::string TextTable::where() const { return where(line_); }

std::string TextTable::where(std::size_t line) const { return path_ + ":" + std::to_string(line); }

}  // namespace budget_slam::dataset
