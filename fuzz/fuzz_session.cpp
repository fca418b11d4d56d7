// libFuzzer target: the session state reader (readSessionStateBytes) over arbitrary bytes, then
// what a resuming run does with what it read: every owner section taken and every field read by
// its type, and the unread check. Allowed outcomes: a state or one InputError line. A finding is
// anything else: a crash, a sanitizer report, another exception, an allocation above
// -malloc_limit_mb, a hang.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "budget_slam/core/Error.h"
#include "budget_slam/session/SessionStateFile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  using namespace budget_slam::session;
  try {
    const SessionState s = readSessionStateBytes("fuzz.txt", bytes);
    // As the owners of a resumed run read: every section, every field by its type.
    for (const auto& section : s.sections()) {
      const SessionSection& taken = s.take(section.name());
      for (const auto& f : taken.fields()) {
        switch (f.type()) {
          case FieldType::Integer:
            taken.integer(f.name);
            break;
          case FieldType::Real:
            taken.real(f.name);
            break;
          case FieldType::Text:
            taken.text(f.name);
            break;
          case FieldType::Integers:
            taken.integers(f.name);
            break;
          case FieldType::Reals:
            taken.reals(f.name);
            break;
          case FieldType::Matrix:
            taken.matrix(f.name);
            break;
        }
      }
    }
    s.checkAllRead();
    // The checked getters' errors: sizes and ranges an owner would ask for.
    for (const auto& section : s.sections())
      for (const auto& f : section.fields()) {
        try {
          if (f.type() == FieldType::Integer) section.integer(f.name, 0, 100);
          if (f.type() == FieldType::Integers) section.integers(f.name, 3, 0, 100);
          if (f.type() == FieldType::Reals) section.reals(f.name, 2);
          if (f.type() == FieldType::Matrix) section.matrix(f.name, 2, 2);
        } catch (const budget_slam::InputError& e) {
          for (const char* p = e.what(); *p; ++p)
            if (*p == '\n' || *p == '\r') __builtin_trap();
        }
      }
  } catch (const budget_slam::InputError& e) {
    // The one-line message contract: no line break, nothing but printable text from the file.
    for (const char* p = e.what(); *p; ++p)
      if (*p == '\n' || *p == '\r') __builtin_trap();
  }
  return 0;
}
