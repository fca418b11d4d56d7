#pragma once
#include <cstddef>
#include <exception>
#include <string>
#include <string_view>

namespace budget_slam {

/// True when `s` is well-formed UTF-8 (no overlong forms, surrogates or code points past
/// U+10FFFF). Otherwise `*bad` (if given) receives the offset of the first bad byte.
bool isValidUtf8(std::string_view s, std::size_t* bad = nullptr);

/// `s` as one printable line of valid UTF-8: control characters (newlines included, and the C1
/// controls and line separators of Unicode: U+0080 to U+009F, U+2028, U+2029) and bytes that are
/// not UTF-8 become `\xNN`, so that a message echoing file content (a corrupt class name, a
/// binary ini line) stays one line and can go into summary.json.
std::string printable(std::string_view s);

/// The first `max_chars` bytes of printable(s), cut at a character boundary, with "..." when cut.
std::string excerpt(std::string_view s, std::size_t max_chars = 40);

/// One line for an exception: MRPT's multi-line "==== MRPT exception ====" dumps give their first
/// "Message:" line, anything else its first line; always printable().
std::string exceptionLine(const std::exception& e);
std::string exceptionLine(std::string_view what);

/// The one line a program ends with for an exception that escaped its work: an Error's own text
/// (it names the file, step or key), "out of memory (...)" for std::bad_alloc (an address-space
/// limit, ulimit -v; just "out of memory" when even the line cannot be made), "internal error:
/// <exceptionLine>" for anything else (a bug). Throws nothing.
std::string failureLine(const std::exception& e);

/// `why`, and `also` after it ("why; also") when `also` says something more: the one line that
/// reports a failure and the summary.json that could not be written about it.
std::string withAlso(const std::string& why, const std::string& also);

/// `s` without the leading and trailing characters of `blanks`.
std::string trimmed(const std::string& s, const char* blanks = " \t\r\n");

/// `s` with ASCII letters in lower case (ini section and key names compare without case, as
/// MRPT's CConfigFile does).
std::string lowerAscii(std::string s);

}  // namespace budget_slam
