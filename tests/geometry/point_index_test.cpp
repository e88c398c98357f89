#include "skelgrasp/geometry/point_index.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "skelgrasp/common/error.h"

namespace skelgrasp::geometry {
namespace {

std::vector<Eigen::Vector3d> randomPoints(std::size_t count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> coordinate(-0.1, 0.1);
  std::vector<Eigen::Vector3d> points(count);
  for (auto& p : points) p = {coordinate(rng), coordinate(rng), coordinate(rng)};
  return points;
}

// Brute force: (distance, index) order, the order the index promises.
std::vector<std::pair<double, int>> byDistance(const std::vector<Eigen::Vector3d>& points,
                                               const Eigen::Vector3d& query) {
  std::vector<std::pair<double, int>> all;
  for (std::size_t i = 0; i < points.size(); ++i)
    all.emplace_back((points[i] - query).squaredNorm(), static_cast<int>(i));
  std::sort(all.begin(), all.end());
  return all;
}

TEST(PointIndex, NearestKAndWithinAgreeWithBruteForce) {
  const auto points = randomPoints(2000, 7);
  const PointIndex index(points);
  ASSERT_EQ(index.size(), points.size());
  for (const auto& query : randomPoints(50, 11)) {
    const auto expected = byDistance(points, query);
    const auto found = index.nearestK(query, 8);
    ASSERT_EQ(found.size(), 8u);
    for (std::size_t k = 0; k < found.size(); ++k) {
      EXPECT_EQ(found[k].first, expected[k].second);
      EXPECT_EQ(found[k].second, std::sqrt(expected[k].first));
    }
    const auto [nearest, distance] = index.nearest(query);
    EXPECT_EQ(nearest, expected[0].second);
    EXPECT_EQ(distance, std::sqrt(expected[0].first));
    const double radius = 0.02;
    std::vector<int> inside;
    for (const auto& [squared, i] : expected)
      if (squared < radius * radius) inside.push_back(i);
    EXPECT_EQ(index.within(query, radius), inside);
    EXPECT_EQ(index.countWithin(query, radius), inside.size());
  }
}

TEST(PointIndex, TiesGoToTheLowerIndex) {
  // A grid: many points at the same distance from the origin and duplicated points.
  std::vector<Eigen::Vector3d> points;
  for (int x = -2; x <= 2; ++x)
    for (int y = -2; y <= 2; ++y)
      for (int z = -2; z <= 2; ++z) points.emplace_back(0.01 * x, 0.01 * y, 0.01 * z);
  const auto copy = points;
  points.insert(points.end(), copy.begin(), copy.end());
  const PointIndex index(points);
  const Eigen::Vector3d query(0.005, 0.005, 0.005);  // 8 grid points equally near, twice each
  const auto expected = byDistance(points, query);
  const auto found = index.nearestK(query, 16);
  ASSERT_EQ(found.size(), 16u);
  for (std::size_t k = 0; k < found.size(); ++k) EXPECT_EQ(found[k].first, expected[k].second);
  EXPECT_EQ(index.nearest(copy[0]).first, 0);  // not its duplicate at index 125
  std::vector<int> inside;
  for (const auto& [squared, i] : expected)
    if (squared < 0.01 * 0.01) inside.push_back(i);
  EXPECT_EQ(index.within(query, 0.01), inside);
}

TEST(PointIndex, SkipsNonFinitePointsAndAnswersEmptyQueries) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const PointIndex index({{nan, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 0.0}});
  EXPECT_EQ(index.size(), 2u);
  EXPECT_EQ(index.nearest({0.9, 0, 0}).first, 1);
  EXPECT_EQ(index.nearest({nan, 0, 0}).first, -1);
  EXPECT_TRUE(index.within({0, 0, 0}, 0).empty());
  EXPECT_EQ(index.nearestK({0, 0, 0}, 5).size(), 2u);
  const PointIndex empty(std::vector<Eigen::Vector3d>{});
  EXPECT_EQ(empty.nearest({0, 0, 0}).first, -1);
  EXPECT_TRUE(std::isinf(empty.nearest({0, 0, 0}).second));
  EXPECT_THROW(nearestPoints({}, {Eigen::Vector3d::Zero()}), InvalidArgument);
}

TEST(PointIndex, NearestPointsMapsEveryQuery) {
  const auto targets = randomPoints(500, 3), queries = randomPoints(100, 5);
  std::vector<double> distances;
  const auto nearest = nearestPoints(targets, queries, &distances);
  ASSERT_EQ(nearest.size(), queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const auto expected = byDistance(targets, queries[i]);
    EXPECT_EQ(nearest[i], expected[0].second);
    EXPECT_EQ(distances[i], std::sqrt(expected[0].first));
  }
}

}  // namespace
}  // namespace skelgrasp::geometry
