#include "budget_slam/core/IniText.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <vector>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"

namespace fs = std::filesystem;

namespace budget_slam {
namespace {

std::string trim(const std::string& s) { return trimmed(s, " \t"); }

bool startsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

/// Characters of section and key names: MRPT's own files use letters, digits and _ . - + :
/// (e.g. [HMT-SLAM], +localizationAngDistance).
bool isNameChar(unsigned char c) {
  return std::isalnum(c) || c == '_' || c == '.' || c == '-' || c == '+' || c == ':';
}

bool isName(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return isNameChar(static_cast<unsigned char>(c));
  });
}

bool isComment(const std::string& trimmed) {
  return trimmed[0] == '#' || trimmed[0] == ';' || startsWith(trimmed, "//");
}

std::string hex(unsigned char c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02x", c);
  return buf;
}

/// One line after MRPT's "\" + newline continuations are joined: where it starts, and which
/// physical lines it spans.
struct LogicalLine {
  std::size_t first = 0, last = 0;  ///< physical line indices (0-based)
  std::string text;
};

class Checker {
 public:
  Checker(const std::string& label) : label_(label) {}

  std::string run(std::string text) {
    if (text.size() > kMaxIniBytes) fail("larger than 1 MiB, not an ini file");
    if (startsWith(text, "\xEF\xBB\xBF")) text.erase(0, 3);  // UTF-8 byte-order mark
    splitPhysical(text);
    for (std::size_t i = 0; i < physical_.size(); ++i) checkBytes(i);
    std::vector<LogicalLine> logical;
    for (std::size_t i = 0; i < physical_.size(); ++i) {
      LogicalLine l;
      l.first = i;
      for (;; ++i) {
        const std::string& p = physical_[i];
        const bool continued = !p.empty() && p.back() == '\\' && i + 1 < physical_.size();
        l.text += continued ? p.substr(0, p.size() - 1) : p;
        if (!continued) break;
      }
      l.last = i;
      logical.push_back(std::move(l));
    }
    for (const auto& l : logical) checkLine(l);
    if (!seen_section_) fail("holds no [section], not an ini file");

    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < physical_.size(); ++i) {
      if (!blank_.count(i)) out += physical_[i];
      if (i + 1 < physical_.size()) out += '\n';
    }
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& why) const { throw ConfigError(label_ + ": " + why); }
  [[noreturn]] void failAt(std::size_t line, const std::string& why) const {
    fail("line " + std::to_string(line + 1) + ": " + why);
  }

  void splitPhysical(const std::string& text) {
    std::size_t start = 0;
    for (;;) {
      const auto end = text.find('\n', start);
      std::string line = text.substr(start, end == std::string::npos ? end : end - start);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      physical_.push_back(std::move(line));
      if (end == std::string::npos) break;
      start = end + 1;
    }
  }

  void checkBytes(std::size_t i) const {
    const std::string& p = physical_[i];
    if (p.size() > kMaxIniLineBytes)
      failAt(i, "longer than " + std::to_string(kMaxIniLineBytes) + " bytes, not an ini file");
    for (const char ch : p) {
      const auto c = static_cast<unsigned char>(ch);
      if (c == 0) failAt(i, "a NUL byte, not a text file");
      if ((c < 0x20 && c != '\t') || c == 0x7F)
        failAt(i, "control byte " + hex(c) + ", not a text file");
    }
    std::size_t bad = 0;
    if (!isValidUtf8(p, &bad))
      failAt(i, "byte " + hex(static_cast<unsigned char>(p[bad])) + " at column " +
                    std::to_string(bad + 1) + " is not UTF-8 text, not an ini file");
  }

  /// ${NAME}, $eval{...} and $env{...} in `s` (a value, a section line, a @define value).
  void checkExpansions(const LogicalLine& l, const std::string& s) const {
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s[i] != '$') continue;
      const std::string rest = s.substr(i);
      std::size_t open = 0;
      std::string kind;
      if (startsWith(rest, "${")) open = 2, kind = "${";
      if (startsWith(rest, "$eval{")) open = 6, kind = "$eval{";
      if (startsWith(rest, "$env{")) open = 5, kind = "$env{";
      if (open == 0) continue;
      const auto close = s.find('}', i + open);
      if (close == std::string::npos) failAt(l.first, "unclosed " + kind + " (no } after it)");
      const std::string inner = s.substr(i + open, close - i - open);
      if (kind == "${" && !defined_.count(inner))
        failAt(l.first, "unknown variable ${" + excerpt(inner) + "} (no @define " + excerpt(inner) +
                            " above it)");
      if (kind == "$eval{" && inner.size() > kMaxIniEvalChars)
        failAt(l.first,
               "$eval{...} longer than " + std::to_string(kMaxIniEvalChars) + " characters");
      i = close;
    }
  }

  void checkLine(const LogicalLine& l) {
    const std::string t = trim(l.text);
    if (t.empty()) return;
    if (isComment(t)) {
      for (std::size_t i = l.first; i <= l.last; ++i) blank_.insert(i);
      return;
    }
    if (startsWith(t, "@define")) {
      const std::string rest = t.substr(7);
      if (rest.empty() || (rest[0] != ' ' && rest[0] != '\t'))
        failAt(l.first, "expected @define NAME VALUE");
      const std::string body = trim(rest);
      const auto sp = body.find_first_of(" \t");
      const std::string name = body.substr(0, sp);
      if (!isName(name)) failAt(l.first, "'" + excerpt(name) + "' is not a variable name");
      if (sp != std::string::npos) checkExpansions(l, body.substr(sp));
      defined_.insert(name);
      return;
    }
    if (t.find("@define") != std::string::npos) failAt(l.first, "@define must start its line");
    if (t[0] == '[') {
      const auto close = t.find(']');
      if (close == std::string::npos) failAt(l.first, "'" + excerpt(t) + "': no ] closes it");
      const std::string name = trim(t.substr(1, close - 1));
      if (!isName(name)) failAt(l.first, "'" + excerpt(t) + "' is not a section name");
      const std::string after = trim(t.substr(close + 1));
      if (!after.empty() && !isComment(after))
        failAt(l.first, "text after the section name: '" + excerpt(after) + "'");
      section_ = name;
      seen_section_ = true;
      return;
    }
    const auto eq = t.find('=');
    if (eq == std::string::npos)
      failAt(l.first, "neither [section], key = value nor a comment: '" + excerpt(t) + "'");
    const std::string key = trim(t.substr(0, eq));
    if (key.empty()) failAt(l.first, "'" + excerpt(t) + "' has no key before =");
    if (!isName(key)) failAt(l.first, "'" + excerpt(key) + "' is not a key name");
    if (!seen_section_) failAt(l.first, "key '" + key + "' before any [section]");
    checkExpansions(l, t.substr(eq + 1));
    const auto [it, fresh] = keys_.emplace(lowerAscii(section_) + "\n" + lowerAscii(key), l.first);
    if (!fresh)
      failAt(l.first, "duplicated key [" + section_ + "] " + key + " (first set at line " +
                          std::to_string(it->second + 1) + ")");
  }

  std::string label_;
  std::vector<std::string> physical_;
  std::set<std::size_t> blank_;              ///< physical lines of comments
  std::set<std::string> defined_;            ///< @define names so far
  std::map<std::string, std::size_t> keys_;  ///< "section\nkey" (lower case) -> line
  std::string section_;
  bool seen_section_ = false;
};

}  // namespace

std::string readIniFile(const std::string& path, const std::string& label) {
  std::error_code ec;
  const auto st = fs::status(path, ec);
  if (!ec && fs::is_directory(st)) throw ConfigError(label + ": is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (ec || !fs::exists(st) || !in) throw ConfigError(label + ": no such file or not readable");
  std::string text(kMaxIniBytes + 1, '\0');
  in.read(&text[0], static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw ConfigError(label + ": no such file or not readable");
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxIniBytes) throw ConfigError(label + ": larger than 1 MiB, not an ini file");
  return text;
}

std::string checkedIniText(const std::string& text, const std::string& label) {
  return Checker(label).run(text);
}

void loadIniText(mrpt::config::CConfigFileMemory& ini, const std::string& text,
                 const std::string& label) {
  const std::string checked = checkedIniText(text, label);
  try {
    ini.setContent(checked);
  } catch (const std::exception& e) {
    throw ConfigError(label + ": " + exceptionLine(e));
  }
}

void copyIni(const mrpt::config::CConfigFileBase& from, mrpt::config::CConfigFileMemory& to) {
  std::vector<std::string> sections;
  from.getAllSections(sections);
  for (const auto& s : sections) {
    std::vector<std::string> keys;
    from.getAllKeys(s, keys);
    for (const auto& k : keys) to.write(s, k, from.read_string(s, k, "", false));
  }
}

void checkIniValue(const std::string& value, const std::string& label) {
  std::size_t bad = 0;
  if (!isValidUtf8(value, &bad))
    throw ConfigError(label + ": byte " + hex(static_cast<unsigned char>(value[bad])) +
                      " is not UTF-8 text");
  for (const char ch : value) {
    const auto c = static_cast<unsigned char>(ch);
    if ((c < 0x20 && c != '\t') || c == 0x7F)
      throw ConfigError(label + ": control byte " + hex(c) + " in the value");
  }
  for (const char* v : {"${", "$eval{", "$env{"})
    if (value.find(v) != std::string::npos)
      throw ConfigError(label + ": " + v +
                        "...} is expanded in ini files only, not in a value given here");
}

}  // namespace budget_slam
