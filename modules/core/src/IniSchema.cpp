#include "budget_slam/core/IniSchema.h"

#include <algorithm>
#include <cctype>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"

namespace budget_slam {
namespace {

bool containsNoCase(const std::vector<std::string>& v, const std::string& w) {
  const std::string lw = lowerAscii(w);
  return std::any_of(v.begin(), v.end(), [&](const std::string& x) { return lowerAscii(x) == lw; });
}

}  // namespace

std::size_t editDistance(const std::string& a0, const std::string& b0) {
  const std::string a = lowerAscii(a0), b = lowerAscii(b0);
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t bestD = std::string::npos;
  for (const auto& c : candidates) {
    const std::size_t d = editDistance(word, c);
    if (d < bestD) bestD = d, best = c;
  }
  // Beyond about a third of the word, a suggestion misleads more than it helps.
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  return bestD <= limit ? best : "";
}

void IniSchema::addSection(const std::string& section, const std::vector<std::string>& keys) {
  auto& v = sections_[section];
  for (const auto& k : keys)
    if (!containsNoCase(v, k)) v.push_back(k);
}

void IniSchema::addForeignSection(const std::string& section) {
  if (!section.empty() && section.back() == '*')
    foreign_prefixes_.push_back(lowerAscii(section.substr(0, section.size() - 1)));
  else
    foreign_.push_back(section);
}

bool IniSchema::hasSection(const std::string& section) const {
  return std::any_of(sections_.begin(), sections_.end(),
                     [&](const auto& kv) { return lowerAscii(kv.first) == lowerAscii(section); });
}

bool IniSchema::isForeign(const std::string& section) const {
  const std::string l = lowerAscii(section);
  return containsNoCase(foreign_, section) ||
         std::any_of(foreign_prefixes_.begin(), foreign_prefixes_.end(), [&](const std::string& p) {
           return l.size() > p.size() && l.rfind(p, 0) == 0;
         });
}

std::string IniSchema::unknownSection(const std::string& section) const {
  std::vector<std::string> known = foreign_;
  for (const auto& [s, keys] : sections_) known.push_back(s);
  const std::string near = closestMatch(section, known);
  return "unknown section [" + section + "]" +
         (near.empty() ? std::string(" (neither budget-slam nor another MRPT application reads it)")
                       : " (did you mean [" + near + "]?)");
}

void IniSchema::validate(const mrpt::config::CConfigFileBase& ini) const {
  // Every unknown section and key at once (a foreign ini is not fixed one key a try), the first
  // with its suggestion; the list bounded, so that a hostile file's thousand keys stay one line.
  constexpr std::size_t kListed = 12;
  struct Unknown {
    std::string section, key, message;
    ConfigErrorKind kind;
  };
  std::vector<Unknown> unknown;
  std::size_t count = 0;
  const auto add = [&](Unknown u) {
    if (count++ < kListed) unknown.push_back(std::move(u));
  };
  std::vector<std::string> sections;
  ini.getAllSections(sections);
  for (const auto& section : sections) {
    const auto it = std::find_if(sections_.begin(), sections_.end(), [&](const auto& kv) {
      return lowerAscii(kv.first) == lowerAscii(section);
    });
    if (it == sections_.end()) {
      if (isForeign(section)) continue;  // another application's section
      add({section, "", unknownSection(section), ConfigErrorKind::UnknownSection});
      continue;
    }
    std::vector<std::string> keys;
    ini.getAllKeys(section, keys);
    for (const auto& key : keys) {
      if (containsNoCase(it->second, key)) continue;
      const std::string near = closestMatch(key, it->second);
      add({section, key,
           "unknown key [" + section + "] " + key +
               (near.empty() ? std::string(" (no similar key in this section)")
                             : " (did you mean " + near + "?)"),
           ConfigErrorKind::UnknownKey});
    }
  }
  if (unknown.empty()) return;
  std::string message = unknown.front().message;
  if (count > 1) {
    message += "; " + std::to_string(count - 1) + " more unknown:";
    for (std::size_t i = 1; i < unknown.size(); ++i)
      message += (i > 1 ? ", [" : " [") + printable(unknown[i].section) + "]" +
                 (unknown[i].key.empty() ? std::string(" (the section)")
                                         : " " + printable(unknown[i].key));
    if (count > unknown.size())
      message += ", ... (" + std::to_string(count - unknown.size()) + " not listed)";
  }
  throw KeyError(unknown.front().section, unknown.front().key, message, unknown.front().kind);
}

}  // namespace budget_slam
