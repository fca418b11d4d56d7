#pragma once
#include <string>
#include <string_view>

#include "budget_slam/session/SessionState.h"

namespace budget_slam::session {

/// The first line of every session state file is "<kFormatName> <version>".
constexpr const char* kFormatName = "budget-slam-session-state";
constexpr int kFormatVersion = 1;
/// The file's name in a run's output folder, beside landmarks.csv.
constexpr const char* kStateFileName = "session_state.txt";

/// The text of the file (docs/OUTPUTS.md "Session state"): doubles in their shortest form that
/// reads back as the same double, the core blocks, then the owners' sections in the order they
/// were added, and an end line with the CRC-32 of everything before it.
/// Throws Error "session state 'LABEL': section 'S', field 'X': <why> (not written)" when the
/// state breaks a rule the reader would refuse (a non-finite value, a non-symmetric or
/// non-positive-definite covariance, sizes that do not agree): a run never writes a state it
/// could not resume from. `label` names the file in those messages.
std::string formatSessionState(const SessionState& state, const std::string& label = "");

/// Writes the state to `path` atomically (a temporary file renamed over it: a reader sees the old
/// file or the new one, never a part). Never replaces a file that is not a session state: an
/// existing `path` whose first line is not this format's is left alone and Error
/// "session state 'P': the file exists and is not a session state; not written over" is thrown.
/// A failed write is Error "cannot write 'P' (<reason>)", `path` left as it was.
void writeSessionState(const std::string& path, const SessionState& state);

/// Reads and checks a session state file. Every failure is one InputError line naming the file
/// and, where known, the line, section and field:
///   "session state 'F': no such file"
///   "session state 'F': not a budget-slam session state (it begins 'PK\x03\x04...')"
///   "session state 'F': format version 2; this budget-slam reads version 1"
///   "session state 'F': truncated inside line 12 (section 'landmarks', field 'covariance')"
///   "session state 'F': line 9: section 'landmarks', field 'mean': value 3 is not finite (nan)"
///   "session state 'F': checksum mismatch (the end line says 0x1234abcd, the contents give
///    0x89ab0123): the file was changed or damaged"
///   "session state 'F': line 14: section 'landmarks', field 'covariance': not positive definite"
/// What the file declares is checked against `limits` and against the bytes left in the file
/// before anything is allocated for it. Owners then take their sections (SessionState::take).
SessionState readSessionState(const std::string& path, const SessionLimits& limits = {});

/// The same over bytes in memory; `label` stands for the file name in messages.
SessionState readSessionStateBytes(const std::string& label, std::string_view bytes,
                                   const SessionLimits& limits = {});

}  // namespace budget_slam::session
