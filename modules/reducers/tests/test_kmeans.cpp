#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <set>

#include "budget_slam/core/Error.h"

#include "budget_slam/reducers/CoverageOptions.h"
#include "budget_slam/reducers/KMeans.h"

using budget_slam::reducers::CoverageOptions;
using budget_slam::reducers::KMeans;
using budget_slam::reducers::SplitMix64;
using Distance = KMeans::Distance;

namespace {

std::vector<Eigen::Vector2d> randomPoints(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-10, 10);  // only the data, not the algorithm
  std::vector<Eigen::Vector2d> p;
  for (std::size_t i = 0; i < n; ++i) p.emplace_back(u(rng), u(rng));
  return p;
}

std::vector<std::size_t> sizes(const KMeans::Result& r) {
  std::vector<std::size_t> s(r.centres.size(), 0);
  for (auto l : r.label) ++s.at(l);
  return s;
}

}  // namespace

TEST(SplitMix64, ReferenceStream) {
  // Vigna's splitmix64.c from state 0: fixed integer arithmetic, the same on every platform.
  SplitMix64 g(0);
  EXPECT_EQ(g.next(), 0xE220A8397B1DCDAFULL);
  EXPECT_EQ(g.next(), 0x6E789E6AA1B965F4ULL);
  SplitMix64 h(0);
  h.next();
  const double u = h.uniform();
  EXPECT_EQ(u, static_cast<double>(0x6E789E6AA1B965F4ULL >> 11) * 0x1.0p-53);
}

TEST(KMeans, L1AssignmentDiffersFromL2) {
  // From the origin: centre a = (2, 0) is at L1 2 and L2 2; b = (1.2, 1.2) at L1 2.4, L2 1.70.
  const std::vector<Eigen::Vector2d> pts = {{0, 0}, {3, 0}, {1.2, 2.0}};
  const std::vector<Eigen::Vector2d> centres = {{2, 0}, {1.2, 1.2}};
  EXPECT_EQ(KMeans::assign(pts, centres, Distance::L1), (std::vector<std::size_t>{0, 0, 1}));
  EXPECT_EQ(KMeans::assign(pts, centres, Distance::L2), (std::vector<std::size_t>{1, 0, 1}));
  EXPECT_DOUBLE_EQ(KMeans::distance({0, 0}, {1.2, 1.2}, Distance::L1), 2.4);
  // Equidistant: the lower centre index.
  EXPECT_EQ(KMeans::assign({{0, 0}}, {{1, 0}, {0, 1}}, Distance::L1)[0], 0u);
}

TEST(KMeans, SeparatedBlobsAreFoundWithEitherMetric) {
  std::vector<Eigen::Vector2d> pts;
  for (int b = 0; b < 3; ++b)
    for (int i = 0; i < 5; ++i) pts.emplace_back(100.0 * b + 0.1 * i, 50.0 * b - 0.2 * i);
  for (const auto d : {Distance::L1, Distance::L2}) {
    KMeans::Options o;
    o.k = 3;
    o.distance = d;
    o.seed = 4;
    const auto r = KMeans::cluster(pts, o);
    EXPECT_TRUE(r.converged);
    for (int b = 0; b < 3; ++b)
      for (int i = 1; i < 5; ++i) EXPECT_EQ(r.label[5 * b + i], r.label[5 * b]);
    EXPECT_EQ(std::set<std::size_t>(r.label.begin(), r.label.end()).size(), 3u);
    // Centres are arithmetic means of the members.
    const auto c0 = r.centres[r.label[0]];
    EXPECT_NEAR(c0.x(), 0.2, 1e-12);
    EXPECT_NEAR(c0.y(), -0.4, 1e-12);
  }
}

TEST(KMeans, DeterministicForASeedAndSeedMatters) {
  const auto pts = randomPoints(200, 1);
  KMeans::Options o;
  o.k = 12;
  o.seed = 77;
  const auto a = KMeans::cluster(pts, o), b = KMeans::cluster(pts, o);
  EXPECT_EQ(a.label, b.label);
  ASSERT_EQ(a.centres.size(), b.centres.size());
  for (std::size_t c = 0; c < a.centres.size(); ++c) EXPECT_EQ(a.centres[c], b.centres[c]);
  EXPECT_NE(KMeans::seedIndices(pts, 12, Distance::L1, 77),
            KMeans::seedIndices(pts, 12, Distance::L1, 78));
  // The start is a set of distinct points.
  const auto s = KMeans::seedIndices(pts, 12, Distance::L1, 77);
  EXPECT_EQ(std::set<std::size_t>(s.begin(), s.end()).size(), 12u);
}

TEST(KMeans, NoEmptyClustersEvenWithDuplicatePoints) {
  // 12 points on 2 distinct positions, k = 5: three clusters must be refilled.
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < 12; ++i) pts.emplace_back(i % 2 ? 5.0 : 0.0, 1.0);
  KMeans::Options o;
  o.k = 5;
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    o.seed = seed;
    const auto r = KMeans::cluster(pts, o);
    ASSERT_EQ(r.centres.size(), 5u);
    for (auto s : sizes(r)) EXPECT_GE(s, 1u) << "seed " << seed;
    EXPECT_GT(r.reseeds, 0u);
  }
  // Random data with k close to N.
  for (unsigned seed = 0; seed < 20; ++seed) {
    const auto p = randomPoints(30, seed);
    o.k = 25;
    o.seed = seed;
    o.distance = seed % 2 ? Distance::L1 : Distance::L2;
    for (auto s : sizes(KMeans::cluster(p, o))) EXPECT_GE(s, 1u);
  }
}

TEST(KMeans, KClampsToThePointCount) {
  KMeans::Options o;
  o.k = 10;
  const auto r = KMeans::cluster({{0, 0}, {1, 1}, {2, 2}}, o);
  EXPECT_EQ(r.centres.size(), 3u);
  EXPECT_EQ(std::set<std::size_t>(r.label.begin(), r.label.end()).size(), 3u);
  o.k = 0;
  EXPECT_EQ(KMeans::cluster({{0, 0}, {1, 1}}, o).centres.size(), 1u);
  EXPECT_TRUE(KMeans::cluster({}, o).label.empty());

  // k = max(1, round(0.25 N)), DESIGN.md "coverage".
  CoverageOptions c;
  EXPECT_EQ(c.kmeans(0).k, 1u);
  EXPECT_EQ(c.kmeans(1).k, 1u);
  EXPECT_EQ(c.kmeans(2).k, 1u);   // 0.5 rounds up, still 1
  EXPECT_EQ(c.kmeans(6).k, 2u);   // 1.5 -> 2
  EXPECT_EQ(c.kmeans(10).k, 3u);  // 2.5 -> 3
  EXPECT_EQ(c.kmeans(9).k, 2u);   // 2.25 -> 2
  EXPECT_EQ(c.kmeans(400).k, 100u);
}

TEST(KMeans, StopsAfterMaxIterations) {
  const auto pts = randomPoints(300, 9);
  KMeans::Options o;
  o.k = 30;
  o.max_iterations = 1;
  const auto r = KMeans::cluster(pts, o);
  EXPECT_EQ(r.iterations, 1u);
  EXPECT_FALSE(r.converged);
  o.max_iterations = 1000;
  EXPECT_TRUE(KMeans::cluster(pts, o).converged);
}

TEST(KMeans, NonFinitePointsAreAnErrorNotUndefinedBehaviour) {
  // A diverged estimate: NaN positions used to leave refillEmpty without a farthest point and
  // write one past the end of the labels.
  KMeans::Options o;
  o.k = 2;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  try {
    KMeans::cluster({{0, 0}, {nan, nan}, {1, 1}}, o);
    FAIL() << "no error";
  } catch (const budget_slam::Error& e) {
    EXPECT_EQ(std::string(e.what()), "k-means: point 1 is not finite (nan, nan)");
  }
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(KMeans::cluster({{inf, 0}, {0, 0}}, o), budget_slam::Error);
  // Every point non-finite, k = N: the case that crashed.
  o.k = 3;
  EXPECT_THROW(KMeans::cluster({{nan, nan}, {nan, nan}, {nan, nan}}, o), budget_slam::Error);
}
