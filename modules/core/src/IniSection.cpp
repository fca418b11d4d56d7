#include "budget_slam/core/IniSection.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"

namespace budget_slam {
namespace {

std::string trim(const std::string& s) { return trimmed(s, " \t\r\n"); }

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string formatNumber(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

}  // namespace

IniSection::IniSection(const mrpt::config::CConfigFileBase& ini, std::string section)
    : ini_(ini), section_(std::move(section)) {}

bool IniSection::has(const std::string& key) const {
  // MRPT returns the default for an absent key; an impossible default tells us it is absent.
  static const std::string kAbsent =
      "\x01"
      "absent"
      "\x01";
  return ini_.read_string(section_, key, kAbsent, false) != kAbsent;
}

std::string IniSection::raw(const std::string& key) const {
  std::string v = ini_.read_string(section_, key, "", false);
  // MRPT ini files put comments after values: "std_sensor_yaw_deg = 0.1 // degrees".
  const auto c = v.find("//");
  if (c != std::string::npos) v = v.substr(0, c);
  return trim(v);
}

void IniSection::fail(const std::string& key, const std::string& value,
                      const std::string& why) const {
  throw KeyError::ofValue(section_, key, value, why);
}

std::string IniSection::readString(const std::string& key, const std::string& def) const {
  return has(key) ? raw(key) : def;
}

double IniSection::readDouble(const std::string& key, double def, double lo, double hi) const {
  if (!has(key)) return def;
  const std::string v = raw(key);
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || end != v.c_str() + v.size() || std::isnan(x))
    fail(key, "'" + v + "'", "not a number");
  if (!std::isfinite(x) || (errno == ERANGE && std::abs(x) > 1))
    fail(key, v, "must be a finite number");
  if (x < lo) fail(key, v, "must be at least " + formatNumber(lo));
  if (x > hi) fail(key, v, "must be at most " + formatNumber(hi));
  return x;
}

double IniSection::readStd(const std::string& key, double def) const {
  const double x = readDouble(key, def);
  if (!has(key)) return x;
  if (x <= 0) fail(key, raw(key), "must be > 0 (a standard deviation)");
  if (x < kMinStd) fail(key, raw(key), "must be at least " + formatNumber(kMinStd));
  if (x > kMaxStd) fail(key, raw(key), "must be at most " + formatNumber(kMaxStd));
  return x;
}

long long IniSection::readInt(const std::string& key, long long def, long long lo,
                              long long hi) const {
  if (!has(key)) return def;
  const std::string v = raw(key);
  char* end = nullptr;
  errno = 0;
  const long long x = std::strtoll(v.c_str(), &end, 10);
  if (v.empty() || end != v.c_str() + v.size() || errno == ERANGE)
    fail(key, "'" + v + "'", "not an integer");
  if (x < lo) fail(key, v, "must be at least " + std::to_string(lo));
  if (x > hi) fail(key, v, "must be at most " + std::to_string(hi));
  return x;
}

bool IniSection::readBool(const std::string& key, bool def) const {
  if (!has(key)) return def;
  const std::string v = lower(raw(key));
  if (v == "true" || v == "1" || v == "yes" || v == "on") return true;
  if (v == "false" || v == "0" || v == "no" || v == "off") return false;
  fail(key, "'" + raw(key) + "'", "not a boolean (true or false)");
}

std::string IniSection::readChoice(const std::string& key, const std::string& def,
                                   const std::vector<std::string>& allowed) const {
  if (!has(key)) return def;
  const std::string v = raw(key);
  if (std::find(allowed.begin(), allowed.end(), v) != allowed.end()) return v;
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  fail(key, "'" + v + "'", "must be one of " + list);
}

std::vector<std::string> IniSection::readList(const std::string& key) const {
  std::vector<std::string> out;
  if (!has(key)) return out;
  std::string v = raw(key);
  std::replace(v.begin(), v.end(), ',', ' ');
  std::istringstream in(v);
  for (std::string item; in >> item;) out.push_back(item);
  return out;
}

}  // namespace budget_slam
