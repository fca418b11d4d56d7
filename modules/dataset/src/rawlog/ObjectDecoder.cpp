#include "ObjectDecoder.h"

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cctype>
#include <sstream>
#include <stdexcept>

#include "ReadFailure.h"

namespace budget_slam::dataset::rawlog {
namespace {

std::string trim(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  const auto b = s.find_first_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b);
}

}  // namespace

std::string mrptCause(const std::string& what) {
  // MRPT nests exceptions ("Exception while parsing typed object 'X'" ... "Message: <cause>")
  // with call stacks; the last "Message:" line is the innermost cause.
  std::string cause;
  std::istringstream in(what);
  for (std::string line; std::getline(in, line);) {
    const auto m = line.find("Message:");
    if (m != std::string::npos) {
      const std::string msg = trim(line.substr(m + 8));
      if (!msg.empty()) cause = msg;
    }
  }
  if (cause.empty()) cause = trim(what.substr(0, what.find('\n')));
  return printable(cause);
}

mrpt::serialization::CSerializable::Ptr decodeObject(const std::uint8_t* data, std::size_t size) {
  mrpt::io::CMemoryStream mem;
  mem.assignMemoryNotOwn(data, size);
  auto arch = mrpt::serialization::archiveFrom(mem);
  mrpt::serialization::CSerializable::Ptr obj;
  try {
    arch >> obj;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw ReadFailure(ReadFailure::Kind::kCorrupt, "that MRPT refuses: " + mrptCause(e.what()));
  }
  if (mem.getPosition() != size)
    throw std::logic_error("rawlog object check: MRPT read " + std::to_string(mem.getPosition()) +
                           " bytes of an object checked as " + std::to_string(size) + " bytes");
  return obj;
}

}  // namespace budget_slam::dataset::rawlog
