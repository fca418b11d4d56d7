#pragma once
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <cstdlib>
#include <functional>
#include <initializer_list>
#include <iomanip>
#include <limits>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "budget_slam/core/IniSection.h"

namespace budget_slam {

/// The ini names of an enum's values, in the order "must be one of ..." lists them.
template <class E>
using EnumNames = std::vector<std::pair<std::string, E>>;

template <class E>
const std::string& nameOf(const EnumNames<E>& names, E value) {
  for (const auto& [n, v] : names)
    if (v == value) return n;
  return names.front().first;  // unreachable for a complete table
}

/// The value named `name`, or nullptr when the table has no such name.
template <class E>
const E* valueOf(const EnumNames<E>& names, const std::string& name) {
  for (const auto& [n, v] : names)
    if (n == name) return &v;
  return nullptr;
}

template <class E>
std::vector<std::string> namesOf(const EnumNames<E>& names) {
  std::vector<std::string> out;
  for (const auto& p : names) out.push_back(p.first);
  return out;
}

/// One key of a section as its user reads it (`budget-slam --list ... --json`): its name, the
/// value it has when the ini leaves it out (as ini text; none when that value is not ours to say,
/// as for MRPT's own keys), and its comment (unit, range).
struct OptionInfo {
  std::string key;
  std::optional<std::string> default_text;
  std::string doc;
};

/// One key of an options struct O: its ini name, how it is read into O (checked; the field's
/// current value is the default, so a struct's member initializers are the defaults), how the
/// field is written back as ini text, and a comment (unit, range) for the dump.
template <class O>
struct OptionKey {
  std::string name;
  std::function<void(O&, const IniSection&)> read;
  std::function<std::string(const O&)> text;
  std::string doc;
};

/// Every key of one options struct, defined once: loading, the dump and the known-keys list of
/// the unknown-key check all follow from it (TabledOptions).
template <class O>
class OptionTable {
 public:
  OptionTable(std::initializer_list<OptionKey<O>> keys) : keys_(keys) {}

  /// Reads every key of `section`, in table order; the first bad value throws its ConfigError.
  void load(O& o, const mrpt::config::CConfigFileBase& ini, const std::string& section) const {
    const IniSection s(ini, section);
    for (const auto& k : keys_) k.read(o, s);
  }
  /// MRPT's dump layout: a banner, then `key = value  // doc`, one key a line.
  void dump(const O& o, std::ostream& out, const std::string& section) const {
    out << "\n----------- [" << section << "] ------------\n";
    for (const auto& k : keys_) {
      out << std::left << std::setw(25) << k.name << "= " << k.text(o);
      if (!k.doc.empty()) out << "  // " << k.doc;
      out << "\n";
    }
  }
  void save(const O& o, mrpt::config::CConfigFileBase& ini, const std::string& section) const {
    for (const auto& k : keys_) ini.write(section, k.name, k.text(o));
  }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& k : keys_) out.push_back(k.name);
    return out;
  }
  /// Every key with its value in `o` (O's defaults when `o` is O{}) and its comment.
  std::vector<OptionInfo> describe(const O& o) const {
    std::vector<OptionInfo> out;
    for (const auto& k : keys_) out.push_back({k.name, k.text(o), k.doc});
    return out;
  }

 private:
  std::vector<OptionKey<O>> keys_;
};

/// MRPT's CLoadableOptions with load, dump, save and keys() taken from D's one table:
/// `static const OptionTable<D>& table();` and `static constexpr const char* kSection`.
template <class D>
struct TabledOptions : public mrpt::config::CLoadableOptions {
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& ini,
                          const std::string& section) override {
    D::table().load(static_cast<D&>(*this), ini, section);
  }
  void saveToConfigFile(mrpt::config::CConfigFileBase& ini,
                        const std::string& section) const override {
    D::table().save(static_cast<const D&>(*this), ini, section);
  }
  void dumpToTextStream(std::ostream& out) const override {
    D::table().dump(static_cast<const D&>(*this), out, D::kSection);
  }
  /// Keys of the section, for the unknown-key check.
  static std::vector<std::string> keys() { return D::table().names(); }
  /// Keys with their defaults (D's member initializers) and comments.
  static std::vector<OptionInfo> describe() { return D::table().describe(D{}); }
};

/// Builders of the common kinds of key; each reads with IniSection's checked readers, so the
/// error messages are IniSection's ("[S] k = v: must be at least 1").
namespace option {

/// The shortest text (6 to 17 significant digits) that reads back as exactly `v`: the dump
/// stays readable and what save writes loads back to the same value.
inline std::string numberText(double v) {
  std::string t;
  for (int digits = 6; digits <= 17; ++digits) {
    std::ostringstream o;
    o << std::setprecision(digits) << v;
    t = o.str();
    if (std::strtod(t.c_str(), nullptr) == v) break;
  }
  return t;
}

/// An integer field (any integral type), in [lo, hi].
template <class O, class T>
OptionKey<O> integer(std::string name, T O::*field, long long lo,
                     long long hi = std::numeric_limits<long long>::max(), std::string doc = "") {
  const std::string key = name;
  return {std::move(name),
          [=](O& o, const IniSection& s) {
            o.*field = static_cast<T>(s.readInt(key, static_cast<long long>(o.*field), lo, hi));
          },
          [=](const O& o) { return std::to_string(o.*field); }, std::move(doc)};
}

/// A finite real field in [lo, hi].
template <class O>
OptionKey<O> real(std::string name, double O::*field, double lo, double hi, std::string doc = "") {
  const std::string key = name;
  return {std::move(name),
          [=](O& o, const IniSection& s) { o.*field = s.readDouble(key, o.*field, lo, hi); },
          [=](const O& o) { return numberText(o.*field); }, std::move(doc)};
}

/// A standard deviation (IniSection::readStd).
template <class O>
OptionKey<O> stddev(std::string name, double O::*field, std::string doc = "") {
  const std::string key = name;
  return {std::move(name), [=](O& o, const IniSection& s) { o.*field = s.readStd(key, o.*field); },
          [=](const O& o) { return numberText(o.*field); }, std::move(doc)};
}

template <class O>
OptionKey<O> flag(std::string name, bool O::*field, std::string doc = "") {
  const std::string key = name;
  return {std::move(name), [=](O& o, const IniSection& s) { o.*field = s.readBool(key, o.*field); },
          [=](const O& o) { return std::string(o.*field ? "true" : "false"); }, std::move(doc)};
}

template <class O>
OptionKey<O> text(std::string name, std::string O::*field, std::string doc = "") {
  const std::string key = name;
  return {std::move(name),
          [=](O& o, const IniSection& s) { o.*field = s.readString(key, o.*field); },
          [=](const O& o) { return o.*field; }, std::move(doc)};
}

/// An enum field named by `names` (case-sensitive; "must be one of" lists them in order).
template <class O, class E>
OptionKey<O> choice(std::string name, E O::*field, const EnumNames<E>& names,
                    std::string doc = "") {
  const std::string key = name;
  return {std::move(name),
          [=, &names](O& o, const IniSection& s) {
            o.*field = *valueOf(names, s.readChoice(key, nameOf(names, o.*field), namesOf(names)));
          },
          [=, &names](const O& o) { return nameOf(names, o.*field); }, std::move(doc)};
}

/// A comma- or space-separated list; an absent key keeps the field's value.
template <class O>
OptionKey<O> list(std::string name, std::vector<std::string> O::*field, std::string doc = "") {
  const std::string key = name;
  return {std::move(name),
          [=](O& o, const IniSection& s) {
            if (s.has(key)) o.*field = s.readList(key);
          },
          [=](const O& o) {
            std::string t;
            for (const auto& item : o.*field) t += (t.empty() ? "" : ",") + item;
            return t;
          },
          std::move(doc)};
}

/// A key of a struct S nested in O as `O::*member` (e.g. SolverSettings inside GraphSlamOptions):
/// the same name, check and doc, read into and written from the nested struct.
template <class O, class S>
OptionKey<O> within(S O::*member, OptionKey<S> key) {
  auto read = std::move(key.read);
  auto text = std::move(key.text);
  return {std::move(key.name), [=](O& o, const IniSection& s) { read(o.*member, s); },
          [=](const O& o) { return text(o.*member); }, std::move(key.doc)};
}

}  // namespace option
}  // namespace budget_slam
