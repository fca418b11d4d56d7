// libFuzzer target: the session state reader (readSessionStateBytes) over arbitrary bytes, then
// what a resuming run does with what it read: every owner section taken and every field read by
// its type, and the unread check. Allowed outcomes: a state or one InputError line. A finding is
// anything else: a crash, a sanitizer report, another exception, an allocation above
// -malloc_limit_mb, a hang.
//
// Built with BUDGET_SLAM_FUZZ_KEEP_CRC (target fuzz_session_crc), the structure-aware mode: a
// custom mutator changes the bytes before the end line (libFuzzer's own mutations, and numbers
// swapped for edge values or for other numbers of the file: ids shifted, counts that lie, cross
// references that point elsewhere) and then writes the end line's CRC-32 afresh, so that every
// input reaches past the checksum into the blocks' checks; and the reducers with memory restore
// their sections from each state read and are asked to choose and forget over its map, as the
// first drops of a resumed run do (docs/RELIABILITY.md "Session states").
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "budget_slam/core/Error.h"
#include "budget_slam/session/SessionStateFile.h"

#ifdef BUDGET_SLAM_FUZZ_KEEP_CRC
#include <zlib.h>

#include <cctype>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "budget_slam/core/IniText.h"
#include "budget_slam/gaussian/GaussianStateBackend.h"
#include "budget_slam/reducers/BuiltinReducers.h"
#include "budget_slam/session/SessionStateOwner.h"

#ifndef BUDGET_SLAM_FUZZ_CORPUS  // libFuzzer's entry: the corpus replay test has no mutator
namespace {

constexpr std::string_view kEnd = "end crc32 ";
/// The end line's length: "end crc32 " and 8 hex digits and '\n'.
constexpr std::size_t kEndLine = 19;

/// Numbers that break assumptions: zero, signs, the int64 edges, huge, tiny and special reals.
const char* const kEdges[] = {"0",
                              "1",
                              "-1",
                              "2",
                              "3",
                              "9223372036854775807",
                              "-9223372036854775808",
                              "9223372036854775806",
                              "4294967295",
                              "2000",
                              "100000",
                              "1e308",
                              "-1e308",
                              "1e-320",
                              "nan",
                              "inf",
                              "0.5",
                              "-0"};

/// [begin, end) of each token of `s` that reads as a number.
std::vector<std::pair<std::size_t, std::size_t>> numbers(const std::string& s) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\n')) ++i;
    const std::size_t b = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\n') ++i;
    if (i > b && (std::isdigit(static_cast<unsigned char>(s[b])) || s[b] == '-'))
      out.push_back({b, i});
  }
  return out;
}

/// One structural change of the body: a number replaced by an edge value, by its neighbour
/// (+-1: ids shifted by one), or by another number of the file (a cross reference that points
/// elsewhere); or a line of numbers reversed (an order that is assumed).
void mutateNumbers(std::string& body, std::mt19937& rng) {
  const auto nums = numbers(body);
  if (nums.empty()) return;
  const auto [b, e] = nums[rng() % nums.size()];
  const std::string token = body.substr(b, e - b);
  std::string with;
  switch (rng() % 4) {
    case 0:
      with = kEdges[rng() % (sizeof kEdges / sizeof kEdges[0])];
      break;
    case 1: {
      char* end = nullptr;
      const long long v = std::strtoll(token.c_str(), &end, 10);
      // Wrapping at the int64 edges (as unsigned: defined) gives the other edge, also worth trying.
      const auto u = static_cast<unsigned long long>(v);
      with = std::to_string(static_cast<long long>(rng() % 2 ? u + 1 : u - 1));
      break;
    }
    case 2: {
      const auto [ob, oe] = nums[rng() % nums.size()];
      with = body.substr(ob, oe - ob);
      break;
    }
    default: {
      // The line holding the number, its values reversed.
      const std::size_t lb = body.rfind('\n', b) == std::string::npos ? 0 : body.rfind('\n', b) + 1;
      const std::size_t le =
          body.find('\n', b) == std::string::npos ? body.size() : body.find('\n', b);
      std::vector<std::string> values;
      std::size_t i = lb;
      while (i < le) {
        const std::size_t sp = std::min(body.find(' ', i), le);
        values.push_back(body.substr(i, sp - i));
        i = sp + 1;
      }
      std::string line;
      for (auto it = values.rbegin(); it != values.rend(); ++it)
        line += (line.empty() ? "" : " ") + *it;
      body.replace(lb, le - lb, line);
      return;
    }
  }
  body.replace(b, e - b, with);
}

}  // namespace

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

/// The body (everything before the end line) mutated, then the end line written for it.
extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size,
                                               std::size_t max_size, unsigned int seed) {
  if (max_size <= kEndLine + 1) return LLVMFuzzerMutate(data, size, max_size);
  std::string body(reinterpret_cast<const char*>(data), size);
  const std::size_t at = body.rfind(kEnd);
  if (at != std::string::npos && (at == 0 || body[at - 1] == '\n')) body.resize(at);
  std::mt19937 rng(seed);
  const std::size_t room = max_size - kEndLine - 1;  // the body's most, before its end line
  if (body.size() > room) body.resize(room);
  if (rng() % 2) {
    mutateNumbers(body, rng);
    if (body.size() > room) body.resize(room);
  } else {
    std::vector<std::uint8_t> buf(room);
    std::memcpy(buf.data(), body.data(), body.size());
    body.assign(reinterpret_cast<const char*>(buf.data()),
                LLVMFuzzerMutate(buf.data(), body.size(), room));
  }
  if (!body.empty() && body.back() != '\n') body += '\n';
  char end[32];
  std::snprintf(end, sizeof end, "end crc32 %08lx\n",
                crc32_z(0L, reinterpret_cast<const Bytef*>(body.data()), body.size()));
  body += end;
  if (body.size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
  std::memcpy(data, body.data(), body.size());
  return body.size();
}
#endif

namespace {

using namespace budget_slam;

/// The options of the seeds' runs (fuzz/corpus/session_crc/README): the sections their reducers
/// wrote read back with the same options, as --resume requires.
const mrpt::config::CConfigFileMemory& seedOptions() {
  static const mrpt::config::CConfigFileMemory ini = [] {
    mrpt::config::CConfigFileMemory i;
    loadIniText(i, "[LandmarkBudget]\nmax_landmarks = 10\n", "fuzz");
    return i;
  }();
  return ini;
}

/// Each reducer with memory restores its section (when the state has one) and is asked what it
/// would drop among the whole map, then told each landmark left, the first one at a time, as a
/// resumed run's first drops would.
void restoreAndChoose(const session::SessionState& s) {
  const std::size_t n = s.map.landmarks.size();
  if (n == 0) return;
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(3 + 2 * n, 3 + 2 * n);
  P.bottomRightCorner(2 * n, 2 * n) = s.map.covariance;
  if (s.robot) {
    P.topLeftCorner(3, 3) = s.robot->pose.cov;
    P.topRightCorner(3, 2 * n) = s.robot->cross_covariance;
    P.bottomLeftCorner(2 * n, 3) = s.robot->cross_covariance.transpose();
  }
  const auto step = static_cast<StepIndex>(s.header.next_step);
  for (const char* name : {"localization-information", "place-coverage", "random", "mi"}) {
    if (!s.takeIfPresent("reducer." + std::string(name))) continue;
    auto reducer = reducers::builtinReducers().create(name, seedOptions(), 1);
    session::sessionOwner(reducer.get())->restoreSession(s);
    gaussian::GaussianStateBackend backend(s.map.landmarks, P, step);
    ObservationKeeper* keeper = observationKeeper(reducer.get());
    while (backend.landmarkCount() > 0) {
      const auto views = backend.landmarks();
      std::vector<std::size_t> all(views.size());
      for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
      const ReducerChoice c = reducer->choose({backend, views, all, step});
      bool known = false;
      for (const auto& v : views) known = known || v.id == c.id;
      if (!known) __builtin_trap();  // a choice outside the candidates
      backend.removeLandmark(c.id);
      if (keeper) keeper->forget(c.id);
    }
  }
}

}  // namespace
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  using namespace budget_slam::session;
  try {
    const SessionState s = readSessionStateBytes("fuzz.txt", bytes);
#ifdef BUDGET_SLAM_FUZZ_KEEP_CRC
    restoreAndChoose(s);
#endif
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
