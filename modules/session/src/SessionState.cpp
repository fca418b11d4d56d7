#include "budget_slam/session/SessionState.h"

#include <algorithm>
#include <stdexcept>

#include "budget_slam/core/Error.h"

namespace budget_slam::session {

const std::vector<std::string>& SessionState::reservedSections() {
  static const std::vector<std::string> names = {"session", "resume_options", "landmarks", "robot"};
  return names;
}

namespace {
bool isReserved(const std::string& name) {
  const auto& r = SessionState::reservedSections();
  return std::find(r.begin(), r.end(), name) != r.end();
}
}  // namespace

SessionSection& SessionState::section(const std::string& name) {
  if (isReserved(name))
    throw std::invalid_argument("session state: section name '" + name + "' is reserved");
  for (auto& s : sections_)
    if (s.name() == name) return s;
  sections_.emplace_back(name, source);
  taken_.push_back(false);
  return sections_.back();
}

void SessionState::addSection(SessionSection s) {
  for (const auto& t : sections_)
    if (t.name() == s.name())
      throw InputError(stateLabel(s.source()) + ": line " + std::to_string(s.line()) +
                       ": section '" + s.name() + "' appears twice");
  sections_.push_back(std::move(s));
  taken_.push_back(false);
}

const SessionSection* SessionState::takeIfPresent(const std::string& name) const {
  for (std::size_t i = 0; i < sections_.size(); ++i)
    if (sections_[i].name() == name) {
      taken_[i] = true;
      return &sections_[i];
    }
  return nullptr;
}

const SessionSection& SessionState::take(const std::string& name) const {
  if (const auto* s = takeIfPresent(name)) return *s;
  throw InputError(stateLabel(source) + ": missing section '" + name + "'");
}

void SessionState::checkAllRead() const {
  for (std::size_t i = 0; i < sections_.size(); ++i) {
    const auto& s = sections_[i];
    if (!taken_[i]) s.failSection("unknown section (no part of this run reads it)");
    const auto unread = s.unread();
    if (!unread.empty())
      s.fail(unread.front(), "unknown field (its section's owner does not read it)");
  }
}

std::vector<std::string> resumeMismatches(const std::map<std::string, std::string>& saved,
                                          const std::map<std::string, std::string>& now) {
  // "Section.key" shown as "[Section] key", as the ini and every other message name it.
  const auto shown = [](const std::string& k) {
    const auto dot = k.find('.');
    return dot == std::string::npos ? k : "[" + k.substr(0, dot) + "] " + k.substr(dot + 1);
  };
  const auto value = [](const std::map<std::string, std::string>& m, const std::string& k) {
    const auto it = m.find(k);
    return it == m.end() ? std::string("(unset)") : it->second;
  };
  std::vector<std::string> out;
  std::map<std::string, bool> keys;
  for (const auto& [k, v] : saved) keys[k] = true;
  for (const auto& [k, v] : now) keys[k] = true;
  for (const auto& [k, unused] : keys) {
    const std::string a = value(saved, k), b = value(now, k);
    if (a != b) out.push_back(shown(k) + " = " + b + ", the saved session had " + a);
  }
  return out;
}

}  // namespace budget_slam::session
