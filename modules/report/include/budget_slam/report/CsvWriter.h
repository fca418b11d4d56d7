#pragma once
#include <fstream>
#include <string>
#include <vector>

namespace budget_slam::report {

/// A CSV file written row by row and flushed after each row, so that a run that stops early
/// (bad data, Ctrl-C) leaves every row written so far readable. Plain header, no '#'.
class CsvWriter {
 public:
  CsvWriter(const std::string& path, const std::vector<std::string>& columns);

  /// One cell each; numbers in SI units. A NaN double (a value that does not apply) is an empty
  /// field, the tidy-CSV way to say "missing"; infinities are written as inf and -inf.
  CsvWriter& cell(double v);
  CsvWriter& cell(long long v);
  CsvWriter& cell(unsigned long long v);
  CsvWriter& cell(int v) { return cell(static_cast<long long>(v)); }
  CsvWriter& cell(std::size_t v) { return cell(static_cast<unsigned long long>(v)); }
  CsvWriter& cell(const std::string& v);
  void endRow();

  const std::string& path() const { return path_; }

 private:
  void separator();
  std::string path_;
  std::ofstream out_;
  std::size_t columns_ = 0, in_row_ = 0;
};

/// Shortest round-trip formatting of a double ("%.17g" would print 0.1 as 0.10000000000000001).
std::string formatDouble(double v);

}  // namespace budget_slam::report
