#pragma once
#include <stdexcept>
#include <string>

namespace budget_slam::dataset::rawlog {

/// Why a rawlog could not be read further. Raised by the byte sources, the object checker and
/// the decoder; RawlogReader turns it into one InputError line naming the file and the step.
class ReadFailure : public std::runtime_error {
 public:
  enum class Kind {
    kEndOfData,    ///< the data ends inside an object (a truncated file)
    kCorrupt,      ///< bytes MRPT's format does not allow: framing, size, version, class, value
    kUnsupported,  ///< a well-formed MRPT object of a class budget-slam does not read
    kCompression,  ///< gzip/zlib: bad compressed data, CRC or length check failed, ends early
    kIo,           ///< the operating system failed a read
  };
  ReadFailure(Kind kind, const std::string& detail) : std::runtime_error(detail), kind(kind) {}
  Kind kind;
};

/// The reader's stop check asked to stop (Ctrl-C, SIGTERM). Not an error: the caller ends the run.
struct ReadStopped {};

/// `bytes` with every byte outside printable ASCII written as \xNN, so that text taken from a
/// corrupt file (a class name) is valid UTF-8 and one line in any message.
std::string printable(const std::string& bytes);

}  // namespace budget_slam::dataset::rawlog
