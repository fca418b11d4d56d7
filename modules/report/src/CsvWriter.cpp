#include "budget_slam/report/CsvWriter.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "budget_slam/core/Error.h"

namespace budget_slam::report {

std::string formatDouble(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& columns)
    : path_(path), out_(path), columns_(columns.size()) {
  if (!out_) throw Error("cannot write '" + path + "'");
  for (std::size_t i = 0; i < columns.size(); ++i) out_ << (i ? "," : "") << columns[i];
  out_ << '\n';
  out_.flush();
}

void CsvWriter::separator() {
  if (in_row_++) out_ << ',';
}

CsvWriter& CsvWriter::cell(double v) {
  separator();
  // NaN means "does not apply" (e.g. no ground truth): an empty field, which pandas and
  // numpy.genfromtxt read as missing.
  if (!std::isnan(v)) out_ << formatDouble(v);
  return *this;
}

CsvWriter& CsvWriter::cell(long long v) {
  separator();
  out_ << v;
  return *this;
}

CsvWriter& CsvWriter::cell(unsigned long long v) {
  separator();
  out_ << v;
  return *this;
}

CsvWriter& CsvWriter::cell(const std::string& v) {
  separator();
  if (v.find_first_of(",\"\n") == std::string::npos) {
    out_ << v;
  } else {
    out_ << '"';
    for (char c : v) out_ << (c == '"' ? "\"\"" : std::string(1, c));
    out_ << '"';
  }
  return *this;
}

void CsvWriter::endRow() {
  if (in_row_ != columns_)
    throw std::logic_error(path_ + ": row with " + std::to_string(in_row_) + " cells, header has " +
                           std::to_string(columns_));
  out_ << '\n';
  out_.flush();
  in_row_ = 0;
}

}  // namespace budget_slam::report
