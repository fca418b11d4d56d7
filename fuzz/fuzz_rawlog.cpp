// libFuzzer target: RawlogReader over arbitrary bytes (plain or gzip, either rawlog format).
// Allowed outcomes: steps, then the end or one InputError. A finding is anything else: a crash,
// a sanitizer report, another exception (the object checker and MRPT disagreeing on a layout),
// an allocation above -malloc_limit_mb, a hang.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "budget_slam/core/Error.h"
#include "budget_slam/dataset/RawlogReader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    budget_slam::dataset::RawlogReader reader("fuzz.rawlog", bytes);
    while (reader.next()) {
    }
  } catch (const budget_slam::InputError& e) {
    // The one-line message contract: no line break, nothing but printable ASCII from the file.
    for (const char* p = e.what(); *p; ++p)
      if (*p == '\n' || static_cast<unsigned char>(*p) >= 0x80) __builtin_trap();
  }
  return 0;
}
