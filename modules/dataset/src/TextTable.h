#pragma once
#include <zlib.h>

#include <string>
#include <vector>

namespace budget_slam::dataset {

/// Reads a whitespace-separated text data file record by record, skipping blank lines and lines
/// starting with '#' or '%'. Plain or gzip-compressed: when `path` does not exist but `path.gz`
/// does, that is read (the project keeps its copies of public data gzipped). A `.csv` file is
/// comma-separated (each field trimmed of spaces, none empty), and its first record is a header,
/// skipped, when its first field is not a number. Every error is an
/// InputError of one line naming the file and line:
///   "<path>:<line>: <what is wrong>"  (or "<path>: cannot open (<reason>)").
/// The input is hostile until checked (docs/RELIABILITY.md "Converters"): a line is at most
/// limits::kMaxLineBytes long and holds text (no NUL or control byte, valid UTF-8), a file at most
/// limits::kMaxRecords records, each checked before it is kept; a stop request (Ctrl-C) ends the
/// reading with Interrupted naming the line. Internal to the converters and the ground-truth
/// loader.
class TextTable {
 public:
  explicit TextTable(std::string path);
  ~TextTable();
  TextTable(const TextTable&) = delete;
  TextTable& operator=(const TextTable&) = delete;

  /// Advances to the next record; false at the end of the file.
  bool next();

  std::size_t line() const { return line_; }
  std::size_t size() const { return words_.size(); }
  const std::string& word(std::size_t i) const { return words_.at(i); }
  const std::string& path() const { return path_; }

  /// Field i (0-based) as a finite double; `what` names it in the error.
  double number(std::size_t i, const std::string& what) const;
  /// Field i as a finite double with |value| <= `limit` ("<what> = <word> is out of range: ...").
  double bounded(std::size_t i, const std::string& what, double limit) const;
  /// Field i as an integer.
  long long integer(std::size_t i, const std::string& what) const;
  /// Field i as a landmark id: an integer from 0 to limits::kMaxLandmarkId.
  long long landmarkId(std::size_t i, const std::string& what) const;
  /// Fails unless the record has exactly n fields (tag included).
  void expectFields(std::size_t n, const std::string& record) const;
  /// Fails unless the record has at least n fields.
  void expectAtLeast(std::size_t n, const std::string& record) const;

  /// Throws InputError("<path>:<line>: <what>").
  [[noreturn]] void fail(const std::string& what) const;
  /// "<path>:<line>" of the current record.
  std::string where() const;
  /// "<path>:<line>" of another line of this file.
  std::string where(std::size_t line) const;

 private:
  /// One line without its '\n' into `line`; false at the end of the file.
  bool readLine(std::string& line);
  /// Refills buf_ from the file; false at its end. Throws on a read error.
  bool fill();

  std::string path_;
  gzFile in_ = nullptr;
  std::string buf_;       ///< bytes read and not yet taken
  std::size_t pos_ = 0;   ///< first byte of buf_ not yet taken
  std::size_t line_ = 0;  ///< lines read
  std::size_t records_ = 0;
  std::vector<std::string> words_;
  bool csv_ = false;             ///< comma-separated, with an optional header
  bool header_checked_ = false;  ///< csv: the first record was looked at
};

}  // namespace budget_slam::dataset
