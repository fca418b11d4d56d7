#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace budget_slam::reducers {

/// Small deterministic k-means over 2-D points (Hochdorfer & Schlegel Sec. III-C clusters the
/// landmarks' mean observation positions with it).
///
///  - Start: k-means++ (Arthur & Vassilvitskii 2007) drawn from a SplitMix64 generator whose
///    arithmetic is written out here, so a seed gives the same clusters with every standard
///    library (std::uniform_*_distribution differ between them).
///  - Assignment: L1 (the paper's choice: cheaper, and the observation means lie on a chain along
///    the trajectory, Sec. III-C) or L2; ties go to the lowest cluster index.
///  - Update: arithmetic mean of the members (as the paper; not the L1-optimal median).
///  - No empty cluster: an empty cluster takes the point farthest from its own centre among the
///    clusters holding two or more points (ties: lowest point index). k <= N makes this always
///    possible, so every cluster of the result has at least one member.
///  - Stops when an assignment repeats or after max_iterations.
class KMeans {
 public:
  enum class Distance { L1, L2 };

  struct Options {
    std::size_t k = 1;  ///< clusters wanted; clamped to [1, N]
    Distance distance = Distance::L1;
    std::size_t max_iterations = 100;  ///< Lloyd iterations at most, >= 1
    std::uint64_t seed = 1;            ///< of the k-means++ start
  };

  struct Result {
    std::vector<std::size_t> label;        ///< cluster of each point, in [0, centres.size())
    std::vector<Eigen::Vector2d> centres;  ///< mean of each cluster's members
    std::size_t iterations = 0;            ///< Lloyd iterations run
    bool converged = false;                ///< the last assignment repeated the previous one
    std::size_t reseeds = 0;               ///< empty clusters refilled
  };

  /// Clusters `points`; k is clamped to [1, points.size()]. No points: an empty result. A
  /// non-finite point is an Error (a diverged estimate must not be clustered).
  static Result cluster(const std::vector<Eigen::Vector2d>& points, const Options& options);

  static double distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Distance d);

  /// Nearest centre of each point under `d`, ties to the lowest centre index.
  static std::vector<std::size_t> assign(const std::vector<Eigen::Vector2d>& points,
                                         const std::vector<Eigen::Vector2d>& centres, Distance d);

  /// The k-means++ start alone (indices of the chosen points), exposed for tests.
  static std::vector<std::size_t> seedIndices(const std::vector<Eigen::Vector2d>& points,
                                              std::size_t k, Distance d, std::uint64_t seed);
};

/// SplitMix64 (Steele, Lea & Flood 2014): fixed integer arithmetic, same stream everywhere.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

}  // namespace budget_slam::reducers
