#pragma once
#include <mrpt/serialization/CSerializable.h>

#include <cstdint>
#include <string>

namespace budget_slam::dataset::rawlog {

/// Deserializes one object that ObjectChecker passed, with MRPT's own code, from memory.
/// Throws ReadFailure(kCorrupt) with MRPT's innermost message when MRPT refuses a value (a
/// duplicated landmark ID); throws std::logic_error when MRPT does not read exactly `size` bytes,
/// which would mean the checker and MRPT disagree on the layout (a bug, never bad input).
mrpt::serialization::CSerializable::Ptr decodeObject(const std::uint8_t* data, std::size_t size);

/// One line from an MRPT exception text (nested "Message:" lines and call stacks): the
/// innermost cause, printable.
std::string mrptCause(const std::string& what);

}  // namespace budget_slam::dataset::rawlog
