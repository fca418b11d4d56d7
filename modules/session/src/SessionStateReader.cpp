// The session state file's reader (docs/OUTPUTS.md "Session state"): one line at a time, every
// line bounded, every declared size checked against the limits and the bytes left before it is
// allocated, the CRC-32 of the end line compared before the blocks are checked.
#include <zlib.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "SessionBlocks.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"
#include "budget_slam/session/SessionStateFile.h"

namespace budget_slam::session {
namespace {

/// The first line is short: a file that is not a session state is recognized within this many
/// bytes, whatever it holds.
constexpr std::size_t kMaxFirstLine = 64;

std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && line[i] == ' ') ++i;
    const std::size_t b = i;
    while (i < line.size() && line[i] != ' ') ++i;
    if (i > b) out.push_back(line.substr(b, i - b));
  }
  return out;
}

/// One pass over the file's lines.
class Parser {
 public:
  Parser(std::string label, std::streambuf& in, std::uint64_t size, const SessionLimits& limits)
      : label_(std::move(label)), in_(in), size_(size), limits_(limits) {}

  SessionState run() {
    readFirstLine();
    std::vector<SessionSection> sections;
    while (true) {
      if (!readLine(limits_.max_line_bytes)) truncated();
      if (line_.empty()) fail("an empty line");
      if (line_[0] == '#') continue;
      if (line_[0] == '[') {
        startSection(sections);
        continue;
      }
      if (line_.compare(0, 4, "end ") == 0) break;
      if (sections.empty()) fail("a field before the first section");
      readField(sections.back());
    }
    checkEnd();

    SessionState state;
    state.source = label_;
    readCoreBlocks(sections, &state);
    for (auto& s : sections)
      if (!isCoreSection(s.name())) state.addSection(std::move(s));
    return state;
  }

 private:
  // ---- lines ----

  /// Reads the next line into line_ (without its '\n'); false at the end of the file. A line
  /// without its '\n' at the end of the file is a truncation, a line over `max` bytes an error.
  bool readLine(std::size_t max) {
    crc_ = crc32_z(crc_, reinterpret_cast<const Bytef*>(line_.data()), line_.size());
    if (line_no_ > 0) crc_ = crc32_z(crc_, reinterpret_cast<const Bytef*>("\n"), 1);
    line_.clear();
    int c = in_.sbumpc();
    if (c == std::char_traits<char>::eof()) return false;
    ++line_no_;
    while (c != std::char_traits<char>::eof() && c != '\n') {
      if (line_.size() >= max) {
        if (line_no_ == 1) return true;  // readFirstLine says what it is
        fail("longer than " + std::to_string(max) + " bytes");
      }
      line_ += static_cast<char>(c);
      c = in_.sbumpc();
    }
    consumed_ += line_.size() + (c == '\n' ? 1 : 0);
    if (c != '\n') {
      if (line_no_ == 1) return true;
      throw InputError(stateLabel(label_) + ": truncated inside line " + std::to_string(line_no_) +
                       (line_.compare(0, 4, "end ") == 0 ? " (the end line)" : where()));
    }
    return true;
  }

  std::uint64_t remaining() const { return size_ > consumed_ ? size_ - consumed_ : 0; }

  // ---- errors ----

  /// " (section 'S', field 'X')" for what is being read, "" before the first section.
  std::string where() const {
    if (section_.empty()) return "";
    if (field_.empty()) return " (section '" + section_ + "')";
    return " (section '" + section_ + "', field '" + field_ + "')";
  }

  [[noreturn]] void truncated() const {
    throw InputError(stateLabel(label_) + ": truncated after line " + std::to_string(line_no_) +
                     where() + "; the end line is missing");
  }

  /// "session state 'F': line N: section 'S', field 'X': <what>".
  [[noreturn]] void fail(const std::string& what) const {
    std::string msg = stateLabel(label_) + ": line " + std::to_string(line_no_) + ": ";
    if (!section_.empty()) {
      msg += "section '" + section_ + "'";
      if (!field_.empty()) msg += ", field '" + field_ + "'";
      msg += ": ";
    }
    throw InputError(msg + what);
  }

  // ---- structure ----

  void readFirstLine() {
    const std::string magic = std::string(kFormatName) + ' ';
    if (!readLine(kMaxFirstLine))
      throw InputError(stateLabel(label_) +
                       ": not a budget-slam session state (the file is empty)");
    const std::size_t n = std::min(line_.size(), magic.size());
    if (line_.compare(0, n, magic, 0, n) != 0)
      throw InputError(stateLabel(label_) + ": not a budget-slam session state (it begins '" +
                       excerpt(line_, 40) + "')");
    if (line_.size() >= kMaxFirstLine)
      throw InputError(stateLabel(label_) + ": line 1 is longer than " +
                       std::to_string(kMaxFirstLine) + " bytes");
    if (consumed_ == line_.size())  // no '\n'
      throw InputError(stateLabel(label_) + ": truncated inside line 1");
    if (line_.size() < magic.size())
      throw InputError(stateLabel(label_) + ": not a budget-slam session state (it begins '" +
                       excerpt(line_, 40) + "')");
    const std::string_view v = std::string_view(line_).substr(magic.size());
    int version = 0;
    const auto r = std::from_chars(v.data(), v.data() + v.size(), version);
    if (r.ec != std::errc() || r.ptr != v.data() + v.size())
      fail("'" + excerpt(v) + "' is not a format version");
    if (version != kFormatVersion)
      throw InputError(stateLabel(label_) + ": format version " + std::to_string(version) +
                       "; this budget-slam reads version " + std::to_string(kFormatVersion));
  }

  void startSection(std::vector<SessionSection>& sections) {
    field_.clear();
    section_.clear();
    if (line_.back() != ']') fail("'" + excerpt(line_) + "' is not a section line");
    const std::string name = line_.substr(1, line_.size() - 2);
    if (!isValidName(name)) fail("'" + excerpt(name) + "' is not a section name");
    if (sections.size() >= limits_.max_sections)
      fail("more than " + std::to_string(limits_.max_sections) + " sections");
    for (const auto& s : sections)
      if (s.name() == name) fail("section '" + name + "' appears twice");
    section_ = name;
    section_values_ = 0;
    sections.emplace_back(name, label_, line_no_);
  }

  /// Values the section may hold in all: the landmark block's size follows from max_landmarks
  /// (ids, 2x2 covariance blocks and the per-landmark records), the robot's from it too.
  std::size_t allowance() const {
    const std::size_t m = limits_.max_landmarks;
    if (section_ == "landmarks") return 4 * m * m + 8 * m;
    if (section_ == "robot") return 12 + 6 * m;
    return limits_.max_section_values;
  }

  /// Counts `n` more values against the section's and the file's bounds and, for values on the
  /// lines below (`on_lines_below`), the bytes left (every value takes at least one character and
  /// a separator), before they are allocated.
  void claim(std::uint64_t n, bool on_lines_below = true) {
    if (n > allowance() - section_values_) {
      const std::string most = std::to_string(allowance());
      fail(std::to_string(n) + " values, more than " +
           (section_ == "landmarks" || section_ == "robot"
                ? "a map of " + std::to_string(limits_.max_landmarks) + " landmarks needs (" +
                      most + " in all)"
                : "the " + most + " this section may hold"));
    }
    if (n > limits_.max_values - total_values_)
      fail(std::to_string(n) + " values, more than the " + std::to_string(limits_.max_values) +
           " a session state may hold");
    if (on_lines_below && n > remaining() / 2)
      fail(std::to_string(n) +
           " values, more than the rest of the file can hold "
           "(truncated or corrupt)");
    section_values_ += n;
    total_values_ += n;
  }

  std::uint64_t count(std::string_view t) {
    std::uint64_t v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
      fail("'" + excerpt(t) + "' is not a count");
    return v;
  }

  std::int64_t integer(std::string_view t) {
    std::int64_t v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
      fail("'" + excerpt(t) + "' is not an integer");
    return v;
  }

  double real(std::string_view t, const std::string& which) {
    double v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec == std::errc::result_out_of_range)
      fail(which + " (" + excerpt(t) + ") is out of range");
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
      fail("'" + excerpt(t) + "' is not a number");
    if (!std::isfinite(v))
      fail(which + " is not finite (" + std::string(std::isnan(v) ? "nan" : "inf") + ")");
    return v;
  }

  void readField(SessionSection& section) {
    field_.clear();
    const auto tok = tokens(line_);
    if (tok.size() < 2) fail("'" + excerpt(line_) + "' is not a field line");
    const std::string_view type = tok[0];
    const std::string name(tok[1]);
    if (!isValidName(name)) fail("'" + excerpt(name) + "' is not a field name");
    if (section.fields().size() >= limits_.max_fields)
      fail("more than " + std::to_string(limits_.max_fields) + " fields");
    field_ = name;
    const std::size_t decl = line_no_;
    const auto arity = [&](std::size_t n) {
      if (tok.size() != n)
        fail("'" + excerpt(line_) + "' is not a '" + std::string(type) + "' line");
    };
    FieldValue value;
    if (type == "int") {
      arity(3);
      claim(1, false);
      value = integer(tok[2]);
    } else if (type == "real") {
      arity(3);
      claim(1, false);
      value = real(tok[2], "the value");
    } else if (type == "text") {
      // "text NAME" or "text NAME VALUE": the value is the rest of the line after one space.
      const std::string head = "text " + name;
      if (line_.compare(0, head.size(), head) != 0 ||
          (line_.size() > head.size() && line_[head.size()] != ' '))
        fail("'" + excerpt(line_) + "' is not a 'text' line");
      std::string t = line_.size() > head.size() ? line_.substr(head.size() + 1) : "";
      for (const char c : t)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F)
          fail("text with a control character");
      if (!isValidUtf8(t)) fail("text that is not UTF-8");
      claim(1, false);
      value = std::move(t);
    } else if (type == "ints") {
      arity(3);
      const std::uint64_t n = count(tok[2]);
      claim(n);
      value = readArray<std::int64_t>(n);
    } else if (type == "reals") {
      arity(3);
      const std::uint64_t n = count(tok[2]);
      claim(n);
      value = readArray<double>(n);
    } else if (type == "matrix") {
      arity(4);
      const std::uint64_t rows = count(tok[2]), cols = count(tok[3]);
      // Each factor is bounded before the product is formed.
      if (rows > remaining() || cols > remaining() || (cols > 0 && rows > remaining() / cols))
        fail(std::to_string(rows) + " x " + std::to_string(cols) +
             " values, more than the rest of the file can hold (truncated or corrupt)");
      claim(rows * cols);
      value = readMatrix(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    } else {
      field_.clear();
      fail("'" + excerpt(type) + "' is not a field type (int, real, text, ints, reals, matrix)");
    }
    section.add({name, std::move(value), decl});
    field_.clear();
  }

  template <class T>
  std::vector<T> readArray(std::uint64_t n) {
    std::vector<T> v;
    v.reserve(n);
    while (v.size() < n) {
      if (!readLine(limits_.max_line_bytes)) truncated();
      const auto tok = tokens(line_);
      if (tok.empty()) fail("a line without values");
      if (v.size() + tok.size() > n)
        fail("more values than the " + std::to_string(n) + " declared");
      for (const auto t : tok) {
        if constexpr (std::is_same_v<T, double>)
          v.push_back(real(t, "value " + std::to_string(v.size() + 1)));
        else
          v.push_back(integer(t));
      }
    }
    return v;
  }

  Eigen::MatrixXd readMatrix(Eigen::Index rows, Eigen::Index cols) {
    Eigen::MatrixXd m(rows, cols);
    if (cols == 0) return m;  // rows of no values have no lines
    for (Eigen::Index r = 0; r < rows; ++r) {
      if (!readLine(limits_.max_line_bytes)) truncated();
      const auto tok = tokens(line_);
      if (static_cast<Eigen::Index>(tok.size()) != cols)
        fail("row " + std::to_string(r + 1) + " has " + std::to_string(tok.size()) +
             " values, expected " + std::to_string(cols));
      for (Eigen::Index c = 0; c < cols; ++c)
        m(r, c) = real(tok[static_cast<std::size_t>(c)],
                       "row " + std::to_string(r + 1) + ", column " + std::to_string(c + 1));
    }
    return m;
  }

  void checkEnd() {
    section_.clear();
    field_.clear();
    const auto tok = tokens(line_);
    const auto expected = crc_;  // every byte before the end line
    if (tok.size() != 3 || tok[1] != "crc32" || tok[2].size() != 8)
      fail("'" + excerpt(line_) + "' is not the end line ('end crc32 <8 hex digits>')");
    unsigned long said = 0;
    const auto r = std::from_chars(tok[2].data(), tok[2].data() + 8, said, 16);
    if (r.ec != std::errc() || r.ptr != tok[2].data() + 8)
      fail("'" + excerpt(line_) + "' is not the end line ('end crc32 <8 hex digits>')");
    if (in_.sgetc() != std::char_traits<char>::eof())
      throw InputError(stateLabel(label_) + ": data after the end line (line " +
                       std::to_string(line_no_) + ")");
    if (said != expected) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "the end line says %08lx, the contents give %08lx", said,
                    static_cast<unsigned long>(expected));
      throw InputError(stateLabel(label_) + ": checksum mismatch (" + buf +
                       "): the file was changed or damaged");
    }
  }

  const std::string label_;
  std::streambuf& in_;
  const std::uint64_t size_;
  const SessionLimits limits_;
  std::string line_;
  std::size_t line_no_ = 0;
  std::uint64_t consumed_ = 0;
  uLong crc_ = 0;
  std::string section_, field_;
  std::uint64_t section_values_ = 0, total_values_ = 0;
};

}  // namespace

SessionState readSessionState(const std::string& path, const SessionLimits& limits) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(stateLabel(path) + ": no such file");
  if (std::filesystem::is_directory(path, ec))
    throw InputError(stateLabel(path) + ": is a folder, not a file");
  const auto size = std::filesystem::file_size(path, ec);
  std::filebuf in;
  if (ec || !in.open(path, std::ios::in | std::ios::binary))
    throw InputError(stateLabel(path) + ": cannot open (" +
                     (ec ? ec.message() : std::string("not readable")) + ")");
  return Parser(path, in, size, limits).run();
}

SessionState readSessionStateBytes(const std::string& label, std::string_view bytes,
                                   const SessionLimits& limits) {
  std::stringbuf in(std::string(bytes), std::ios::in);
  return Parser(label, in, bytes.size(), limits).run();
}

}  // namespace budget_slam::session
