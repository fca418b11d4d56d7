#pragma once
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <cstddef>
#include <string>

namespace budget_slam {

/// What an ini file may be (docs/RELIABILITY.md "Configuration"): at most this many bytes...
constexpr std::size_t kMaxIniBytes = std::size_t(1) << 20;
/// ...lines of at most this many bytes...
constexpr std::size_t kMaxIniLineBytes = 16384;
/// ...and $eval{...} expressions of at most this many characters (MRPT compiles them with exprtk).
constexpr std::size_t kMaxIniEvalChars = 256;

/// Reads an ini file whole. `label` names it in messages ("config file 'a.ini'"). Throws
/// ConfigError "<label>: no such file or not readable", "<label>: is a folder, not a file" or
/// "<label>: larger than 1 MiB, not an ini file"; never reads more than kMaxIniBytes + 1 bytes.
std::string readIniFile(const std::string& path, const std::string& label);

/// Checks the text of an ini file before MRPT sees it (MRPT's parser accepts anything: a binary
/// file, prose, a key set twice, and throws std::runtime_error from its ${...} expansion), and
/// returns the text MRPT must parse: the same lines, a UTF-8 byte-order mark dropped and lines
/// that are comments blanked (MRPT would expand ${...} in them, and reads a `// ...` line as a
/// key). Every failure is a ConfigError "<label>: line N: ...":
///  - not text: a NUL or control byte, bytes that are not UTF-8, a line over kMaxIniLineBytes;
///  - not an ini: no [section] at all, a key before the first section, a line that is neither
///    `[section]`, `key = value`, `@define NAME VALUE` nor a comment (`#`, `;`, `//`);
///  - a key set twice in one section (MRPT would silently keep the last): both lines named;
///  - `${NAME}` with no `@define NAME` above it, an unclosed `${`, `$eval{` or `$env{`, an
///    `$eval{}` longer than kMaxIniEvalChars.
/// Sections and keys are compared without case, as MRPT does.
std::string checkedIniText(const std::string& text, const std::string& label);

/// checkedIniText(), then MRPT's own preprocessing (@define, ${}, $eval{}, $env{}) and parsing into
/// `ini`; an exception MRPT still throws becomes a ConfigError "<label>: <its first line>".
void loadIniText(mrpt::config::CConfigFileMemory& ini, const std::string& text,
                 const std::string& label);

/// Copies every key of `from` into `to` (later copies win). Unlike a round trip through
/// getContent()/setContent(), values are never expanded a second time.
void copyIni(const mrpt::config::CConfigFileBase& from, mrpt::config::CConfigFileMemory& to);

/// A value given outside an ini file (--set): one line of UTF-8 text without control characters
/// and without MRPT's ${...}, $eval{...} or $env{...} (expanded in ini files only). Throws
/// ConfigError "<label>: ...".
void checkIniValue(const std::string& value, const std::string& label);

}  // namespace budget_slam
