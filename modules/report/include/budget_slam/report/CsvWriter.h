#pragma once
#include <memory>
#include <string>
#include <vector>

#include "budget_slam/core/FileWrite.h"

namespace budget_slam::report {

/// A CSV file with a plain header (no '#'), built a row at a time. Two ways to write it:
///  - Stream (steps.csv, evictions.csv): each row goes to disk whole when it ends (LineFile), so
///    that a run that stops early (bad data, Ctrl-C, a full disk) leaves every row written so far
///    readable and no row cut in the middle;
///  - WholeFile (landmarks.csv, comparison.csv): nothing is on disk until close(), which writes
///    the file atomically (writeFileAtomically).
/// Every write is checked: failures throw Error "cannot write '<path>' (<reason>)".
class CsvWriter {
 public:
  enum class Mode { Stream, WholeFile };
  CsvWriter(const std::string& path, const std::vector<std::string>& columns,
            Mode mode = Mode::Stream);

  /// One cell each; numbers in SI units. A NaN double (a value that does not apply) is an empty
  /// field, the tidy-CSV way to say "missing"; infinities are written as inf and -inf.
  CsvWriter& cell(double v);
  CsvWriter& cell(long long v);
  CsvWriter& cell(unsigned long long v);
  CsvWriter& cell(int v) { return cell(static_cast<long long>(v)); }
  CsvWriter& cell(std::size_t v) { return cell(static_cast<unsigned long long>(v)); }
  CsvWriter& cell(const std::string& v);
  /// Ends the row: Stream writes it out. Throws std::logic_error when the row does not have the
  /// header's width (a programming error), Error when it cannot be written.
  void endRow();
  /// Stream: flushes to disk (fsync); WholeFile: writes the file. Throws Error naming the file.
  void close();

  const std::string& path() const { return path_; }

 private:
  void separator();
  std::string path_;
  Mode mode_;
  std::unique_ptr<LineFile> file_;  ///< Stream
  std::string text_;                ///< WholeFile: the rows so far
  std::string row_;                 ///< the row being built
  std::size_t columns_ = 0, in_row_ = 0;
};

/// Shortest round-trip formatting of a double ("%.17g" would print 0.1 as 0.10000000000000001).
std::string formatDouble(double v);

}  // namespace budget_slam::report
