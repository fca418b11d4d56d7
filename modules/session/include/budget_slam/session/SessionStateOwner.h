#pragma once
#include <string>

#include "budget_slam/session/SessionState.h"

namespace budget_slam::session {

/// An optional capability of whatever holds memory that must outlive a run (a backend, the budget
/// manager, a reducer): it writes that memory into a session state and takes it back when a run
/// resumes (`budget-slam run --resume`, docs/OUTPUTS.md "Session state"). Asked once with
/// dynamic_cast (sessionOwner()); a part that remembers nothing between steps does not implement
/// it.
class SessionStateOwner {
 public:
  virtual ~SessionStateOwner() = default;
  /// Writes the owner's memory: its own section (state.section(name)), and for a backend the
  /// core blocks (the map, the robot).
  virtual void saveSession(SessionState& state) const = 0;
  /// Takes the memory back from a state read from a file (state.take(name) for its section).
  /// Throws InputError naming the file, section and field when a value is out of range.
  virtual void restoreSession(const SessionState& state) = 0;
};

/// `part` as a session state owner, or nullptr when it keeps no memory between runs.
template <class T>
const SessionStateOwner* sessionOwner(const T* part) {
  return dynamic_cast<const SessionStateOwner*>(part);
}
template <class T>
SessionStateOwner* sessionOwner(T* part) {
  return dynamic_cast<SessionStateOwner*>(part);
}

}  // namespace budget_slam::session
