#include "budget_slam/session/SessionSection.h"

#include <stdexcept>

#include "budget_slam/core/Error.h"
#include "budget_slam/core/Text.h"

namespace budget_slam::session {

const char* fieldTypeName(FieldType t) {
  switch (t) {
    case FieldType::Integer:
      return "int";
    case FieldType::Real:
      return "real";
    case FieldType::Text:
      return "text";
    case FieldType::Integers:
      return "ints";
    case FieldType::Reals:
      return "reals";
    case FieldType::Matrix:
      return "matrix";
  }
  return "?";
}

bool isValidName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

std::string stateLabel(const std::string& source) {
  return source.empty() ? "session state" : "session state '" + printable(source) + "'";
}

SessionSection::SessionSection(std::string name, std::string source, std::size_t line)
    : name_(std::move(name)), source_(std::move(source)), line_(line) {
  if (!isValidName(name_))
    throw std::invalid_argument("session state: bad section name '" + printable(name_) + "'");
}

void SessionSection::put(const std::string& field, FieldValue v) {
  if (!isValidName(field))
    throw std::invalid_argument("session state: section '" + name_ + "': bad field name '" +
                                printable(field) + "'");
  if (find(field))
    throw std::invalid_argument("session state: section '" + name_ + "': field '" + field +
                                "' written twice");
  fields_.push_back({field, std::move(v), 0});
  read_.push_back(false);
}

void SessionSection::putInteger(const std::string& field, std::int64_t v) { put(field, v); }
void SessionSection::putReal(const std::string& field, double v) { put(field, v); }
void SessionSection::putText(const std::string& field, std::string v) {
  for (const char c : v)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F)
      throw std::invalid_argument("session state: section '" + name_ + "', field '" + field +
                                  "': text with a control character");
  if (!isValidUtf8(v))
    throw std::invalid_argument("session state: section '" + name_ + "', field '" + field +
                                "': text that is not UTF-8");
  put(field, std::move(v));
}
void SessionSection::putIntegers(const std::string& field, std::vector<std::int64_t> v) {
  put(field, std::move(v));
}
void SessionSection::putReals(const std::string& field, std::vector<double> v) {
  put(field, std::move(v));
}
void SessionSection::putMatrix(const std::string& field, Eigen::MatrixXd v) {
  put(field, std::move(v));
}

void SessionSection::add(Field f) {
  if (find(f.name))
    throw InputError(stateLabel(source_) + ": line " + std::to_string(f.line) + ": section '" +
                     name_ + "': field '" + f.name + "' appears twice");
  fields_.push_back(std::move(f));
  read_.push_back(false);
}

const Field* SessionSection::find(const std::string& field) const {
  for (const auto& f : fields_)
    if (f.name == field) return &f;
  return nullptr;
}

bool SessionSection::has(const std::string& field) const { return find(field) != nullptr; }

void SessionSection::fail(const std::string& field, const std::string& what) const {
  std::string msg = stateLabel(source_) + ": ";
  const Field* f = find(field);
  if (f && f->line) msg += "line " + std::to_string(f->line) + ": ";
  throw InputError(msg + "section '" + name_ + "', field '" + field + "': " + what);
}

void SessionSection::failSection(const std::string& what) const {
  std::string msg = stateLabel(source_) + ": ";
  if (line_) msg += "line " + std::to_string(line_) + ": ";
  throw InputError(msg + "section '" + name_ + "': " + what);
}

const Field& SessionSection::get(const std::string& field, FieldType type) const {
  for (std::size_t i = 0; i < fields_.size(); ++i) {
    if (fields_[i].name != field) continue;
    read_[i] = true;
    if (fields_[i].type() != type)
      fail(field, std::string("is '") + fieldTypeName(fields_[i].type()) + "', expected '" +
                      fieldTypeName(type) + "'");
    return fields_[i];
  }
  failSection("missing field '" + field + "'");
}

std::int64_t SessionSection::integer(const std::string& field) const {
  return std::get<std::int64_t>(get(field, FieldType::Integer).value);
}

std::int64_t SessionSection::integer(const std::string& field, std::int64_t lo,
                                     std::int64_t hi) const {
  const std::int64_t v = integer(field);
  if (v < lo || v > hi)
    fail(field, std::to_string(v) + " is out of range [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "]");
  return v;
}

double SessionSection::real(const std::string& field) const {
  return std::get<double>(get(field, FieldType::Real).value);
}

const std::string& SessionSection::text(const std::string& field) const {
  return std::get<std::string>(get(field, FieldType::Text).value);
}

const std::vector<std::int64_t>& SessionSection::integers(const std::string& field) const {
  return std::get<std::vector<std::int64_t>>(get(field, FieldType::Integers).value);
}

const std::vector<std::int64_t>& SessionSection::integers(const std::string& field, std::size_t n,
                                                          std::int64_t lo, std::int64_t hi) const {
  const auto& v = integers(field);
  if (v.size() != n)
    fail(field, std::to_string(v.size()) + " values, expected " + std::to_string(n));
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i] < lo || v[i] > hi)
      fail(field, "value " + std::to_string(i + 1) + " (" + std::to_string(v[i]) +
                      ") is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

const std::vector<double>& SessionSection::reals(const std::string& field) const {
  return std::get<std::vector<double>>(get(field, FieldType::Reals).value);
}

const std::vector<double>& SessionSection::reals(const std::string& field, std::size_t n) const {
  const auto& v = reals(field);
  if (v.size() != n)
    fail(field, std::to_string(v.size()) + " values, expected " + std::to_string(n));
  return v;
}

const Eigen::MatrixXd& SessionSection::matrix(const std::string& field) const {
  return std::get<Eigen::MatrixXd>(get(field, FieldType::Matrix).value);
}

const Eigen::MatrixXd& SessionSection::matrix(const std::string& field, Eigen::Index rows,
                                              Eigen::Index cols) const {
  const auto& m = matrix(field);
  if (m.rows() != rows || m.cols() != cols)
    fail(field, std::to_string(m.rows()) + " x " + std::to_string(m.cols()) + ", expected " +
                    std::to_string(rows) + " x " + std::to_string(cols));
  return m;
}

std::vector<std::string> SessionSection::unread() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < fields_.size(); ++i)
    if (!read_[i]) out.push_back(fields_[i].name);
  return out;
}

}  // namespace budget_slam::session
