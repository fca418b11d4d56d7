#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace budget_slam::session {

/// The types a field of a session state file may have (their names in the file:
/// docs/OUTPUTS.md "Session state").
enum class FieldType { Integer, Real, Text, Integers, Reals, Matrix };

/// "int", "real", "text", "ints", "reals", "matrix".
const char* fieldTypeName(FieldType t);

/// A value of one of the six field types, in FieldType order.
using FieldValue = std::variant<std::int64_t, double, std::string, std::vector<std::int64_t>,
                                std::vector<double>, Eigen::MatrixXd>;

/// One named field of a section.
struct Field {
  std::string name;
  FieldValue value;
  std::size_t line = 0;  ///< line of its declaration in the file it was read from; 0: built here
  FieldType type() const { return static_cast<FieldType>(value.index()); }
};

/// True when `name` may name a section or a field: 1 to 64 characters out of letters, digits,
/// '_', '-' and '.' ("place_records", "LandmarkBudget.max_landmarks").
bool isValidName(const std::string& name);

/// One named section of a session state: typed fields that one owner (the budget manager, a
/// reducer, the state file's own blocks) writes and reads back. The getters throw InputError with
/// one line naming the file, the section and the field ("session state 'F': line 7: section
/// 'budget', field 'refused_ids': is 'ints', expected 'reals'"), and mark the field read, so that
/// SessionState::checkAllRead() can refuse the fields no owner asked for.
class SessionSection {
 public:
  /// `name` must pass isValidName (std::invalid_argument otherwise); `source` is the file the
  /// section was read from ("" when built in memory), named in the errors.
  explicit SessionSection(std::string name, std::string source = "", std::size_t line = 0);

  const std::string& name() const { return name_; }
  const std::string& source() const { return source_; }
  std::size_t line() const { return line_; }

  /// Writing. A field name must pass isValidName and appear once (std::invalid_argument).
  /// Values go out as given; writeSessionState refuses non-finite ones, naming the field.
  void putInteger(const std::string& field, std::int64_t v);
  void putReal(const std::string& field, double v);
  /// One line of printable text (no control characters: std::invalid_argument).
  void putText(const std::string& field, std::string v);
  void putIntegers(const std::string& field, std::vector<std::int64_t> v);
  void putReals(const std::string& field, std::vector<double> v);
  void putMatrix(const std::string& field, Eigen::MatrixXd v);
  /// The reader's entry: a field of any type, at line `line`; InputError for a second field of
  /// the same name.
  void add(Field f);

  /// Reading. A missing field or one of another type is an InputError naming it.
  bool has(const std::string& field) const;
  std::int64_t integer(const std::string& field) const;
  /// An integer in [lo, hi].
  std::int64_t integer(const std::string& field, std::int64_t lo,
                       std::int64_t hi = std::numeric_limits<std::int64_t>::max()) const;
  double real(const std::string& field) const;
  const std::string& text(const std::string& field) const;
  const std::vector<std::int64_t>& integers(const std::string& field) const;
  /// Exactly `n` integers, each in [lo, hi].
  const std::vector<std::int64_t>& integers(const std::string& field, std::size_t n,
                                            std::int64_t lo, std::int64_t hi) const;
  const std::vector<double>& reals(const std::string& field) const;
  /// Exactly `n` reals.
  const std::vector<double>& reals(const std::string& field, std::size_t n) const;
  const Eigen::MatrixXd& matrix(const std::string& field) const;
  /// Exactly `rows` x `cols`.
  const Eigen::MatrixXd& matrix(const std::string& field, Eigen::Index rows,
                                Eigen::Index cols) const;

  /// Every field, in the order written or read.
  const std::vector<Field>& fields() const { return fields_; }
  /// Names of the fields no getter has read yet.
  std::vector<std::string> unread() const;

  /// Throws InputError "session state 'F': line L: section 'S', field 'X': <what>" (the parts
  /// that are known; "session state:" when the section was built in memory).
  [[noreturn]] void fail(const std::string& field, const std::string& what) const;
  /// The same without a field: "session state 'F': section 'S': <what>".
  [[noreturn]] void failSection(const std::string& what) const;

 private:
  const Field& get(const std::string& field, FieldType type) const;
  const Field* find(const std::string& field) const;
  void put(const std::string& field, FieldValue v);

  std::string name_, source_;
  std::size_t line_ = 0;
  std::vector<Field> fields_;
  mutable std::vector<bool> read_;  ///< one a field: a getter asked for it
};

/// "session state 'F'" (or "session state" when `source` is empty): how every message of the
/// session module begins.
std::string stateLabel(const std::string& source);

}  // namespace budget_slam::session
