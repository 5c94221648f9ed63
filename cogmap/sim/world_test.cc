#include "cogmap/sim/world.h"

#include <random>

#include <gtest/gtest.h>

#include "cogmap/core/angles.h"

namespace cogmap::sim {
namespace {

std::vector<Segment2> Box(double w, double h) {
  return {{{0, 0}, {w, 0}}, {{w, 0}, {w, h}}, {{w, h}, {0, h}}, {{0, h}, {0, 0}}};
}

TEST(World, RayHitsFacingWallAtExactDistance) {
  const World world(Box(10, 4));
  const RayHit hit = world.CastRay({2.5, 1.0}, 0.0, 20.0);
  ASSERT_TRUE(hit.hit());
  EXPECT_DOUBLE_EQ(hit.distance_m, 7.5);
  EXPECT_EQ(hit.wall, 1);
  EXPECT_NEAR(hit.normal.x(), -1.0, 1e-12);
}

TEST(World, DiagonalRayDistanceIsExact) {
  const World world(Box(10, 4));
  // From (1, 1) at 45 degrees the ceiling y = 4 is met after 3 * sqrt(2).
  const RayHit hit = world.CastRay({1.0, 1.0}, kPi / 4, 20.0);
  ASSERT_TRUE(hit.hit());
  EXPECT_NEAR(hit.distance_m, 3.0 * std::sqrt(2.0), 1e-12);
  EXPECT_EQ(hit.wall, 2);
}

TEST(World, NothingBeyondMaxRange) {
  const World world(Box(10, 4));
  EXPECT_FALSE(world.CastRay({1.0, 1.0}, 0.0, 8.99).hit());
  EXPECT_TRUE(world.CastRay({1.0, 1.0}, 0.0, 9.0).hit());
}

TEST(World, RayFromOutsideEntersGrid) {
  const World world(Box(10, 4));
  const RayHit hit = world.CastRay({-5.0, 2.0}, 0.0, 100.0);
  ASSERT_TRUE(hit.hit());
  EXPECT_DOUBLE_EQ(hit.distance_m, 5.0);
  EXPECT_FALSE(world.CastRay({-5.0, 2.0}, kPi, 100.0).hit());
}

TEST(World, MatchesBruteForceOnRandomWalls) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 30.0), a(-kPi, kPi);
  std::vector<Segment2> walls;
  for (int i = 0; i < 300; ++i) {
    const Vec2 p(u(rng), u(rng));
    walls.push_back({p, p + Vec2(u(rng) / 10 - 1.5, u(rng) / 10 - 1.5)});
  }
  const World world(walls);
  for (int k = 0; k < 2000; ++k) {
    const Vec2 o(u(rng), u(rng));
    const double h = a(rng);
    const Vec2 d(std::cos(h), std::sin(h));
    double best = 1e9;
    for (const auto& w : walls) {
      const double t = RaySegmentDistance(o, d, w.a, w.b);
      if (t >= 0 && t < best) best = t;
    }
    const RayHit hit = world.CastRay(o, h, 12.0);
    if (best <= 12.0) {
      ASSERT_TRUE(hit.hit()) << k;
      EXPECT_NEAR(hit.distance_m, best, 1e-9) << k;
    } else {
      EXPECT_FALSE(hit.hit()) << k;
    }
  }
}

TEST(World, ClearanceIsDistanceToNearestWall) {
  const World world(Box(10, 4));
  EXPECT_DOUBLE_EQ(world.Clearance({2.0, 1.5}, 5.0), 1.5);
  EXPECT_DOUBLE_EQ(world.Clearance({5.0, 2.0}, 1.0), 1.0);  // bounded by the limit
}

TEST(World, LineOfSightBlockedByWall) {
  const World world({{{5, -1}, {5, 1}}});
  EXPECT_FALSE(world.LineOfSight({0, 0}, {10, 0}));
  EXPECT_TRUE(world.LineOfSight({0, 2}, {10, 2}));
}

}  // namespace
}  // namespace cogmap::sim
