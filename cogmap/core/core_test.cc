#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
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
#include "cogmap/core/process.h"

namespace cogmap {
namespace {

// 64 MiB written page by page: resident now, and in the peak since.
TEST(Process, ThePeakResidentSetHoldsWhatThisProgramTouched) {
  const long rss0 = ResidentKib();
  ASSERT_GT(rss0, 0);
  EXPECT_GE(PeakResidentKib(), rss0);
  std::vector<char> block(64L << 20);
  for (size_t i = 0; i < block.size(); i += 4096) block[i] = static_cast<char>(i >> 12);
  const long during = ResidentKib();
  EXPECT_GE(during, rss0 + 60L * 1024) << "the block's pages are resident";
  EXPECT_GE(PeakResidentKib(), during);
  volatile char sink = block[block.size() / 2];
  (void)sink;
}

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
                                 // Work that takes time: a thread that took
                                 // index 3 and was preempted before calling
                                 // it (two cores, eight threads) still stops
                                 // the others well before the end.
                                 std::this_thread::sleep_for(std::chrono::microseconds(20));
                               }),
                 std::runtime_error);
    // The other threads stop taking indices: far fewer than all the rest ran.
    EXPECT_LT(after.load(), 9000);
  }
}

// The threads of the process (Linux: one entry each in /proc/self/task).
size_t ThreadsOfThisProcess() {
  size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator("/proc/self/task")) n += e.is_directory() ? 1 : 0;
  return n;
}

TEST(ForEachShared, HelpersAreKeptNotStartedForEachCall) {
  ForEachShared(4, 3, [](size_t) {});  // the pool's helpers for 3 threads started
  const size_t before = ThreadsOfThisProcess();
  std::set<std::thread::id> ids;
  std::mutex m;
  for (int call = 0; call < 200; ++call)
    ForEachShared(4, 3, [&](size_t) {
      std::this_thread::sleep_for(std::chrono::microseconds(50));
      std::lock_guard<std::mutex> lock(m);
      ids.insert(std::this_thread::get_id());
    });
  EXPECT_EQ(ThreadsOfThisProcess(), before);
  // Every call's threads were among those alive before (the pool may hold
  // more helpers than this call wants: earlier tests asked for 8 threads).
  EXPECT_GE(ids.size(), 1u);
  EXPECT_LE(ids.size(), before);
}

TEST(ForEachShared, ACallInsideASharedCallFinishes) {
  std::vector<std::atomic<int>> calls(16 * 16);
  ForEachShared(16, 2, [&](size_t i) {
    ForEachShared(16, 2, [&](size_t j) { ++calls[i * 16 + j]; });
  });
  for (const auto& c : calls) EXPECT_EQ(c.load(), 1);
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
