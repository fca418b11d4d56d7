#include "budget_slam/core/Text.h"

#include <cstdio>
#include <new>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/HeapRelease.h"

namespace budget_slam {
namespace {

/// Length of the UTF-8 sequence starting at s[i], 0 if it is not a valid one.
std::size_t utf8Length(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return 1;
  std::size_t n;
  unsigned lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;  // overlong
    if (c == 0xED) hi = 0x9F;  // UTF-16 surrogates
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;  // overlong
    if (c == 0xF4) hi = 0x8F;  // past U+10FFFF
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  if (b(i + 1) < lo || b(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
  return n;
}

std::string hexByte(unsigned char c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "\\x%02x", c);
  return buf;
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return std::string(s.substr(b, e - b + 1));
}

/// A character a terminal or an editor may take for a control or a line break: the C1 controls
/// (U+0080 to U+009F, NEL among them) and the line and paragraph separators U+2028, U+2029.
bool breaksALine(std::string_view ch) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(ch[k]); };
  if (ch.size() == 2) return b(0) == 0xC2 && b(1) <= 0x9F;
  if (ch.size() == 3) return b(0) == 0xE2 && b(1) == 0x80 && (b(2) == 0xA8 || b(2) == 0xA9);
  return false;
}

}  // namespace

bool isValidUtf8(std::string_view s, std::size_t* bad) {
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8Length(s, i);
    if (n == 0) {
      if (bad) *bad = i;
      return false;
    }
    i += n;
  }
  return true;
}

std::string printable(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8Length(s, i);
    const auto c = static_cast<unsigned char>(s[i]);
    if (n == 0 || (n == 1 && (c < 0x20 || c == 0x7F))) {
      out += hexByte(c);
      ++i;
    } else if (breaksALine(s.substr(i, n))) {
      for (std::size_t k = 0; k < n; ++k) out += hexByte(static_cast<unsigned char>(s[i + k]));
      i += n;
    } else {
      out.append(s.substr(i, n));
      i += n;
    }
  }
  return out;
}

std::string excerpt(std::string_view s, std::size_t max_chars) {
  const std::string p = printable(s);
  if (p.size() <= max_chars) return p;
  std::size_t cut = max_chars;
  // Back up to the start of a UTF-8 character (continuation bytes are 10xxxxxx).
  while (cut > 0 && (static_cast<unsigned char>(p[cut]) & 0xC0) == 0x80) --cut;
  while (cut > 0 && p[cut - 1] == ' ') --cut;
  return p.substr(0, cut) + "...";
}

std::string exceptionLine(std::string_view what) {
  constexpr std::string_view kMrpt = "==== MRPT exception ====";
  if (what.find(kMrpt) != std::string_view::npos) {
    // MRPT 2.x: "==== MRPT exception ====\nMessage:  <text>\nLocation: ...\nCall stack ...".
    const auto m = what.find("Message:");
    if (m != std::string_view::npos) {
      const auto start = m + 8;
      const auto end = what.find('\n', start);
      const std::string line = trim(
          what.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
      if (!line.empty()) return printable(line);
    }
  }
  std::string_view rest = what;
  // The first non-blank line.
  while (!rest.empty()) {
    const auto end = rest.find('\n');
    const std::string line = trim(rest.substr(0, end));
    if (!line.empty() && line.find(kMrpt) == std::string::npos) return printable(line);
    if (end == std::string_view::npos) break;
    rest.remove_prefix(end + 1);
  }
  return "unknown error";
}

std::string exceptionLine(const std::exception& e) { return exceptionLine(e.what()); }

std::string failureLine(const std::exception& e) {
  // Called in catch handlers, often of an allocation that failed: the line itself may not fit in
  // memory either, and a throw from a worker thread's handler would end the process. "out of
  // memory" fits std::string's inline buffer (15 characters), so returning it allocates nothing.
  try {
    if (dynamic_cast<const Error*>(&e)) return exceptionLine(e);
    if (dynamic_cast<const std::bad_alloc*>(&e)) {
      releaseMemoryReserve();  // what follows this line (summary.json) runs in the reserve
      return "out of memory (" + exceptionLine(e) + "; an address-space limit, ulimit -v?)";
    }
    return "internal error: " + exceptionLine(e);
  } catch (const std::bad_alloc&) {
    return "out of memory";
  }
}

std::string withAlso(const std::string& why, const std::string& also) {
  if (also.empty() || also == why) return why;
  return why + "; " + also;
}

std::string trimmed(const std::string& s, const char* blanks) {
  const auto b = s.find_first_not_of(blanks);
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(blanks);
  return s.substr(b, e - b + 1);
}

std::string lowerAscii(std::string s) {
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return s;
}

}  // namespace budget_slam
