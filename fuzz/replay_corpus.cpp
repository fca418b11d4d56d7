// Replays a committed corpus (fuzz/corpus/<BUDGET_SLAM_FUZZ_CORPUS>/) through its fuzz target's
// entry point, so that every build, and the sanitizer build, keeps the inputs fuzzing found worth
// keeping; a regression aborts as it would under libFuzzer. BUDGET_SLAM_FUZZ_MIN_INPUTS: how many
// inputs the corpus holds at least (a corpus that went missing fails).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

TEST(FuzzCorpus, EveryInputEndsInAResultOrOneError) {
  const std::filesystem::path dir =
      std::string(BUDGET_SLAM_SOURCE_DIR) + "/fuzz/corpus/" + BUDGET_SLAM_FUZZ_CORPUS;
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    std::ifstream in(e.path(), std::ios::binary);
    const std::string bytes(std::istreambuf_iterator<char>(in), {});
    SCOPED_TRACE(e.path().filename().string());
    EXPECT_EQ(
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
        0);
    ++n;
  }
  EXPECT_GE(n, static_cast<std::size_t>(BUDGET_SLAM_FUZZ_MIN_INPUTS));
}
