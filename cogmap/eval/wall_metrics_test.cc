#include "cogmap/eval/wall_metrics.h"

#include <gtest/gtest.h>

namespace cogmap::eval {
namespace {

TEST(WallMetrics, Defaults) {
  const WallMetricsOptions o;
  EXPECT_EQ(o.sample_step_m, 0.05);
  EXPECT_EQ(o.recall_within_m, 0.2);
}

TEST(SampleSegment, EveryFiveCentimetres) {
  const auto p = SampleSegment({Vec2(0, 0), Vec2(1, 0)}, 0.05);
  ASSERT_EQ(p.size(), 21u);
  EXPECT_NEAR(p[1].x(), 0.05, 1e-12);
  EXPECT_EQ(p.back(), Vec2(1, 0));
}

TEST(WallPrecision, ParallelOffsetWall) {
  // A map wall 0.1 m off a true wall along its whole length.
  const auto st = WallPrecision({{Vec2(0, 0.1), Vec2(2, 0.1)}}, {{Vec2(0, 0), Vec2(2, 0)}});
  EXPECT_EQ(st.samples, 41);
  EXPECT_NEAR(st.mean_m, 0.1, 1e-12);
  EXPECT_NEAR(st.p95_m, 0.1, 1e-12);
}

TEST(WallPrecision, TiltedWallHasExactMeanAndP95) {
  // From (0,0) to (0.8, 0.6) (length 1) over the true wall y = 0: distances
  // 0.6 * i / 20, i = 0..20: mean 0.3, p95 (nearest rank 20 of 21) 0.57.
  const auto st = WallPrecision({{Vec2(0, 0), Vec2(0.8, 0.6)}}, {{Vec2(-5, 0), Vec2(5, 0)}});
  EXPECT_EQ(st.samples, 21);
  EXPECT_NEAR(st.mean_m, 0.3, 1e-12);
  EXPECT_NEAR(st.p95_m, 0.57, 1e-12);
  EXPECT_NEAR(st.max_m, 0.6, 1e-12);
}

TEST(WallPrecision, NoMapWalls) { EXPECT_EQ(WallPrecision({}, {{Vec2(0, 0), Vec2(1, 0)}}).samples, 0); }

TEST(LineOfSight, BlockedAndClear) {
  const std::vector<Segment2> walls = {{Vec2(1, -1), Vec2(1, 1)}};
  EXPECT_FALSE(ClearLineOfSight(Vec2(0, 0), Vec2(2, 0), walls, 1e-3));
  EXPECT_TRUE(ClearLineOfSight(Vec2(0, 0), Vec2(0.5, 3), walls, 1e-3));
  // Looking at a point on the wall itself is clear.
  EXPECT_TRUE(ClearLineOfSight(Vec2(0, 0), Vec2(1, 0.5), walls, 1e-3));
}

// A 4 m wall, one pose 1 m above its start, range sqrt(2): the samples at
// x = 0, 0.05 .. 1.0 are seeable. Each stands for 5 cm (the end one 2.5 cm):
// 1.025 m. The map wall covers x <= 0.5, and samples up to x = 0.7 lie within
// 0.2 m of it: 0.725 m found.
TEST(WallRecall, RangeLimitsTheSeeablePart) {
  const std::vector<Segment2> truth = {{Vec2(0, 0), Vec2(4, 0)}};
  const std::vector<Vec2> path = {Vec2(0, 1)};
  WallMetricsOptions o;
  o.sensor_range_m = std::sqrt(2.0) + 1e-9;  // sees x in [0, 1]
  const auto st = WallRecall({{Vec2(0, 0), Vec2(0.5, 0)}}, truth, path, o);
  EXPECT_EQ(st.samples, 81);
  EXPECT_EQ(st.seeable_samples, 21);
  EXPECT_NEAR(st.seeable_length_m, 1.025, 1e-9);
  EXPECT_NEAR(st.found_length_m, 0.725, 1e-9);
  EXPECT_NEAR(st.recall(), 0.725 / 1.025, 1e-9);
}

TEST(WallRecall, HiddenWallIsNotCounted) {
  // Two parallel walls, the path below both: the upper one is hidden.
  const std::vector<Segment2> truth = {{Vec2(-5, 1), Vec2(5, 1)}, {Vec2(-1, 2), Vec2(1, 2)}};
  const std::vector<Vec2> path = {Vec2(0, 0)};
  WallMetricsOptions o;
  o.sensor_range_m = 100.0;
  const auto st = WallRecall({{Vec2(-5, 1), Vec2(5, 1)}}, truth, path, o);
  EXPECT_NEAR(st.seeable_length_m, 10.0, 1e-9);
  EXPECT_NEAR(st.recall(), 1.0, 1e-12);
}

TEST(WallRecall, NothingSeeable) {
  const auto st = WallRecall({}, {{Vec2(0, 0), Vec2(1, 0)}}, {}, {});
  EXPECT_EQ(st.seeable_length_m, 0.0);
  EXPECT_EQ(st.recall(), 0.0);
}

TEST(ThinPath, KeepsEnds) {
  const auto p = ThinPath({Vec2(0, 0), Vec2(0.01, 0), Vec2(0.2, 0), Vec2(0.21, 0)}, 0.1);
  EXPECT_EQ(p.size(), 3u);
  EXPECT_EQ(p.back(), Vec2(0.21, 0));
}

}  // namespace
}  // namespace cogmap::eval
