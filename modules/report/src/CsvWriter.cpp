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

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& columns, Mode mode)
    : path_(path), mode_(mode), columns_(columns.size()) {
  std::string header;
  for (std::size_t i = 0; i < columns.size(); ++i) header += (i ? "," : "") + columns[i];
  header += '\n';
  if (mode_ == Mode::Stream) {
    file_ = std::make_unique<LineFile>(path);
    file_->append(header);
  } else {
    text_ = header;
  }
}

void CsvWriter::separator() {
  if (in_row_++) row_ += ',';
}

CsvWriter& CsvWriter::cell(double v) {
  separator();
  // NaN means "does not apply" (e.g. no ground truth): an empty field, which pandas and
  // numpy.genfromtxt read as missing.
  if (!std::isnan(v)) row_ += formatDouble(v);
  return *this;
}

CsvWriter& CsvWriter::cell(long long v) {
  separator();
  row_ += std::to_string(v);
  return *this;
}

CsvWriter& CsvWriter::cell(unsigned long long v) {
  separator();
  row_ += std::to_string(v);
  return *this;
}

CsvWriter& CsvWriter::cell(const std::string& v) {
  separator();
  if (v.find_first_of(",\"\n\r") == std::string::npos) {
    row_ += v;
  } else {
    row_ += '"';
    for (char c : v) row_ += c == '"' ? std::string("\"\"") : std::string(1, c);
    row_ += '"';
  }
  return *this;
}

void CsvWriter::endRow() {
  if (in_row_ != columns_)
    throw std::logic_error(path_ + ": row with " + std::to_string(in_row_) + " cells, header has " +
                           std::to_string(columns_));
  row_ += '\n';
  in_row_ = 0;
  std::string row;
  row.swap(row_);
  if (mode_ == Mode::Stream)
    file_->append(row);
  else
    text_ += row;
}

void CsvWriter::close() {
  if (mode_ == Mode::Stream)
    file_->sync();
  else
    writeFileAtomically(path_, text_);
}

}  // namespace budget_slam::report
