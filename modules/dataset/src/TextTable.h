#pragma once
#include <zlib.h>

#include <string>
#include <vector>

namespace budget_slam::dataset {

/// Reads a whitespace-separated text data file record by record, skipping blank lines and lines
/// starting with '#' or '%'. Plain or gzip-compressed: when `path` does not exist but `path.gz`
/// does, that is read (the project keeps its copies of public data gzipped). Every error is an
/// InputError of one line naming the file and line:
///   "<path>:<line>: <what is wrong>"  (or "<path>: cannot open (<reason>)").
/// Internal to the converters and the ground-truth loader.
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
  /// Field i as an integer.
  long long integer(std::size_t i, const std::string& what) const;
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
  std::string path_;
  gzFile in_ = nullptr;
  std::size_t line_ = 0;
  std::vector<std::string> words_;
};

}  // namespace budget_slam::dataset
