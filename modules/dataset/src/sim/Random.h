#pragma once
#include <cstdint>
#include <random>

namespace budget_slam::dataset::sim {

/// Seeded random numbers with the same output on every platform: std::mt19937_64's sequence is
/// fixed by the standard, and the uniform and normal transforms below are ours (the standard
/// library's distributions are implementation-defined).
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Standard normal (Box-Muller; the second value of each pair is kept for the next call).
  double normal();
  double normal(double stddev) { return stddev == 0 ? 0.0 : stddev * normal(); }

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0;
};

}  // namespace budget_slam::dataset::sim
