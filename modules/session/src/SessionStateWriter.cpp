// The session state file's writer (docs/OUTPUTS.md "Session state").
#include <zlib.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "SessionBlocks.h"
#include "budget_slam/core/Error.h"
#include "budget_slam/core/FileWrite.h"
#include "budget_slam/session/SessionStateFile.h"

namespace budget_slam::session {
namespace {

/// Values a line of an `ints` or `reals` field (a matrix has one row a line).
constexpr std::size_t kValuesPerLine = 10;

void appendNumber(std::string& out, double v) {
  char buf[32];
  // Shortest text that reads back as exactly v (std::from_chars on read).
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

void appendNumber(std::string& out, std::int64_t v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

template <class T>
void appendArray(std::string& out, const std::vector<T>& v) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    appendNumber(out, v[i]);
    out += (i + 1) % kValuesPerLine == 0 || i + 1 == v.size() ? '\n' : ' ';
  }
}

/// Error "session state 'L': section 'S', field 'X': <what> (not written)" for a value the reader
/// would refuse.
void checkFinite(const SessionSection& s, const Field& f) {
  const auto bad = [&](const std::string& where, double v) {
    s.fail(f.name, where + " is not finite (" + std::string(std::isnan(v) ? "nan" : "inf") + ")");
  };
  switch (f.type()) {
    case FieldType::Real: {
      const double v = std::get<double>(f.value);
      if (!std::isfinite(v)) bad("the value", v);
      break;
    }
    case FieldType::Reals: {
      const auto& v = std::get<std::vector<double>>(f.value);
      for (std::size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i])) bad("value " + std::to_string(i + 1), v[i]);
      break;
    }
    case FieldType::Matrix: {
      const auto& m = std::get<Eigen::MatrixXd>(f.value);
      for (Eigen::Index r = 0; r < m.rows(); ++r)
        for (Eigen::Index c = 0; c < m.cols(); ++c)
          if (!std::isfinite(m(r, c)))
            bad("row " + std::to_string(r + 1) + ", column " + std::to_string(c + 1), m(r, c));
      break;
    }
    default:
      break;
  }
}

void appendSection(std::string& out, const SessionSection& s) {
  out += "[" + s.name() + "]\n";
  for (const auto& f : s.fields()) {
    out += fieldTypeName(f.type());
    out += ' ';
    out += f.name;
    switch (f.type()) {
      case FieldType::Integer:
        out += ' ';
        appendNumber(out, std::get<std::int64_t>(f.value));
        out += '\n';
        break;
      case FieldType::Real:
        out += ' ';
        appendNumber(out, std::get<double>(f.value));
        out += '\n';
        break;
      case FieldType::Text: {
        const auto& t = std::get<std::string>(f.value);
        if (!t.empty()) out += ' ' + t;
        out += '\n';
        break;
      }
      case FieldType::Integers: {
        const auto& v = std::get<std::vector<std::int64_t>>(f.value);
        out += ' ' + std::to_string(v.size()) + '\n';
        appendArray(out, v);
        break;
      }
      case FieldType::Reals: {
        const auto& v = std::get<std::vector<double>>(f.value);
        out += ' ' + std::to_string(v.size()) + '\n';
        appendArray(out, v);
        break;
      }
      case FieldType::Matrix: {
        const auto& m = std::get<Eigen::MatrixXd>(f.value);
        out += ' ' + std::to_string(m.rows()) + ' ' + std::to_string(m.cols()) + '\n';
        if (m.cols() == 0) break;  // rows of no values have no lines
        for (Eigen::Index r = 0; r < m.rows(); ++r)
          for (Eigen::Index c = 0; c < m.cols(); ++c) {
            appendNumber(out, m(r, c));
            out += c + 1 == m.cols() ? '\n' : ' ';
          }
        break;
      }
    }
  }
}

/// True when the file at `path` begins with this format's first line.
bool isSessionStateFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string magic = std::string(kFormatName) + ' ';
  std::string head(magic.size(), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  return in.gcount() == static_cast<std::streamsize>(magic.size()) && head == magic;
}

}  // namespace

std::string formatSessionState(const SessionState& state, const std::string& label) {
  std::vector<SessionSection> sections = coreSections(state, label);
  for (const auto& s : state.sections()) {
    SessionSection copy(s.name(), label);
    for (const auto& f : s.fields()) copy.add({f.name, f.value, 0});
    sections.push_back(std::move(copy));
  }
  try {
    for (const auto& s : sections)
      for (const auto& f : s.fields()) checkFinite(s, f);
    // The reader's own checks, so that a run never writes a state it could not resume from.
    SessionState check;
    check.source = label;
    readCoreBlocks(sections, &check);
  } catch (const InputError& e) {
    throw Error(std::string(e.what()) + " (not written)");
  }

  std::string out;
  std::size_t values = 0;
  for (const auto& s : sections)
    for (const auto& f : s.fields())
      if (f.type() == FieldType::Matrix) values += std::get<Eigen::MatrixXd>(f.value).size();
  out.reserve(1024 + 26 * values);
  out += std::string(kFormatName) + ' ' + std::to_string(kFormatVersion) + '\n';
  out +=
      "# budget-slam session state (docs/OUTPUTS.md, \"Session state\"); the end line holds the "
      "CRC-32 of every byte above it\n";
  for (const auto& s : sections) appendSection(out, s);
  const auto crc = crc32_z(0L, reinterpret_cast<const Bytef*>(out.data()), out.size());
  char end[32];
  std::snprintf(end, sizeof end, "end crc32 %08lx\n", static_cast<unsigned long>(crc));
  out += end;
  return out;
}

void writeSessionState(const std::string& path, const SessionState& state) {
  const std::string text = formatSessionState(state, path);
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) {
    if (std::filesystem::is_directory(path, ec))
      throw Error(stateLabel(path) + ": is a folder; not written over");
    if (!isSessionStateFile(path))
      throw Error(stateLabel(path) +
                  ": the file exists and is not a session state; not written over");
  }
  writeFileAtomically(path, text);
}

}  // namespace budget_slam::session
