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
  if (::stat(path_.c_str(), &st) != 0)
    throw InputError(path_ + ": cannot open (" + std::strerror(errno) + ")");
  if (S_ISDIR(st.st_mode)) throw InputError(path_ + ": cannot open (is a directory)");
  in_.open(path_);
  if (!in_) throw InputError(path_ + ": cannot open (" + std::strerror(errno) + ")");
}

bool TextTable::next() {
  std::string text;
  while (std::getline(in_, text)) {
    ++line_;
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#' || text[first] == '%') continue;
    words_.clear();
    std::istringstream ss(text);
    for (std::string w; ss >> w;) words_.push_back(w);
    return true;
  }
  if (in_.bad()) throw InputError(path_ + ": read error after line " + std::to_string(line_));
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
