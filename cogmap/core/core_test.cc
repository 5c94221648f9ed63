#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/core/bresenham.h"
#include "cogmap/core/error.h"
#include "cogmap/core/geometry.h"
#include "cogmap/core/parallel.h"

namespace cogmap {
namespace {

TEST(ForEachShared, CallsEachIndexOnceOnOneOrMoreThreads) {
  for (int threads : {1, 2, 8}) {
    std::vector<std::atomic<int>> calls(1000);
    std::vector<std::thread::id> who(calls.size());
    ForEachShared(calls.size(), threads, [&](size_t i) {
      ++calls[i];
      who[i] = std::this_thread::get_id();
    });
    for (const auto& c : calls) EXPECT_EQ(c.load(), 1);
    if (threads == 1) {
      for (const auto& id : who) EXPECT_EQ(id, std::this_thread::get_id());
    }
  }
  ForEachShared(0, 2, [](size_t) { FAIL() << "no index to call"; });
  // No more threads than indices: three indices on at most three threads.
  std::mutex m;
  std::set<std::thread::id> ids;
  std::vector<std::atomic<int>> three(3);
  ForEachShared(three.size(), 8, [&](size_t i) {
    ++three[i];
    std::lock_guard<std::mutex> lock(m);
    ids.insert(std::this_thread::get_id());
  });
  for (const auto& c : three) EXPECT_EQ(c.load(), 1);
  EXPECT_LE(ids.size(), 3u);
}

TEST(ForEachShared, RaisesTheFirstErrorOnceAllHaveStopped) {
  for (int threads : {1, 2, 8}) {
    std::atomic<int> after{0};
    EXPECT_THROW(ForEachShared(10000, threads,
                               [&](size_t i) {
                                 if (i == 3) throw std::runtime_error("index 3");
                                 if (i > 3) ++after;
                               }),
                 std::runtime_error);
    // The other threads stop taking indices: far fewer than all the rest ran.
    EXPECT_LT(after.load(), 9000);
  }
}

TEST(Angles, NormalizeWrapsIntoHalfOpenRange) {
  EXPECT_NEAR(NormalizeAngle(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(NormalizeAngle(-kPi), kPi, 1e-12);
  EXPECT_NEAR(NormalizeAngle(DegToRad(370)), DegToRad(10), 1e-12);
  EXPECT_NEAR(AngleDiff(DegToRad(-179), DegToRad(179)), DegToRad(2), 1e-12);
}

TEST(Pose2, ComposeAndInverseRoundTrip) {
  const Pose2 a{1.0, 2.0, 0.5}, b{-0.3, 0.7, -1.2};
  const Pose2 ab = a * b;
  const Pose2 back = a.inverse() * ab;
  EXPECT_NEAR(back.x, b.x, 1e-12);
  EXPECT_NEAR(back.y, b.y, 1e-12);
  EXPECT_NEAR(back.theta, b.theta, 1e-12);
}

TEST(Pose2, RotatesCounterClockwise) {
  const Pose2 r{0, 0, kPi / 2};
  const Vec2 p = r * Vec2(1, 0);
  EXPECT_NEAR(p.x(), 0.0, 1e-12);
  EXPECT_NEAR(p.y(), 1.0, 1e-12);
}

TEST(Bresenham, VisitsBothEndsInOrder) {
  std::vector<std::pair<int, int>> cells;
  WalkBresenham(0, 0, 3, 1, [&](int x, int y) { cells.emplace_back(x, y); return true; });
  ASSERT_EQ(cells.size(), 4u);
  EXPECT_EQ(cells.front(), std::make_pair(0, 0));
  EXPECT_EQ(cells.back(), std::make_pair(3, 1));
}

TEST(Bresenham, StopsEarly) {
  int n = 0;
  EXPECT_FALSE(WalkBresenham(0, 0, 10, 0, [&](int, int) { return ++n < 3; }));
  EXPECT_EQ(n, 3);
}

TEST(Bresenham, FirstStepIsTheWalksSecondCell) {
  for (int dy = -7; dy <= 7; ++dy)
    for (int dx = -7; dx <= 7; ++dx) {
      if (!dx && !dy) continue;
      std::vector<std::pair<int, int>> cells;
      WalkBresenham(0, 0, dx, dy, [&](int x, int y) { cells.emplace_back(x, y); return cells.size() < 2; });
      int sx = 9, sy = 9;
      BresenhamFirstStep(dx, dy, &sx, &sy);
      ASSERT_EQ(cells.size(), 2u);
      EXPECT_EQ(std::make_pair(sx, sy), cells[1]) << "toward (" << dx << ", " << dy << ")";
    }
}

TEST(Geometry, PointSegmentDistanceClampsToEnds) {
  EXPECT_NEAR(PointSegmentDistance({2, 1}, {0, 0}, {1, 0}), std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(PointSegmentDistance({0.5, 1}, {0, 0}, {1, 0}), 1.0, 1e-12);
}

TEST(Geometry, ConvexHullOfASquareWithInnerAndEdgePoints) {
  // The inner point, the midpoint of an edge and a repeated corner go.
  const auto h = ConvexHull({{1, 1}, {0, 0}, {2, 0}, {1, 0}, {2, 2}, {0, 2}, {0, 0}});
  ASSERT_EQ(h.size(), 4u);
  const std::vector<Vec2> expected{{0, 0}, {2, 0}, {2, 2}, {0, 2}};  // counter-clockwise from the lowest x
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(h[i], expected[i]) << i;
  EXPECT_EQ(ConvexHull({{1, 1}, {1, 1}}).size(), 1u);
  EXPECT_DOUBLE_EQ(SignedArea(h), 4.0);  // counter-clockwise: positive
  EXPECT_DOUBLE_EQ(SignedArea({{0, 0}, {0, 2}, {2, 2}, {2, 0}}), -4.0);
}

TEST(InputError, NamesFileAndLine) {
  EXPECT_STREQ(InputError("a.log", 12, "bad").what(), "a.log:12: bad");
  EXPECT_STREQ(InputError("a.log", 0, "empty").what(), "a.log: empty");
}

}  // namespace
}  // namespace cogmap
