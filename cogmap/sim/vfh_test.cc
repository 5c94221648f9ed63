#include "cogmap/sim/vfh.h"

#include <gtest/gtest.h>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/sim/nav_grid.h"

namespace cogmap::sim {
namespace {

TEST(Vfh, FreeGoalSectorIsTakenAsIs) {
  std::vector<double> h(72, 0.0);
  const VfhResult r = VfhChoose(h, 0.3, {});
  EXPECT_TRUE(r.free);
  EXPECT_DOUBLE_EQ(r.heading_rad, 0.3);
}

TEST(Vfh, BlockedGoalSteersToNearestValley) {
  VfhOptions o;
  std::vector<double> h(72, 5.0);
  // Sectors 36..39 (0..20 degrees) blocked; 40.. free on the left; right side blocked.
  for (int k = 40; k < 72; ++k) h[k] = 0.0;
  const VfhResult r = VfhChoose(h, DegToRad(2.0), o);
  ASSERT_TRUE(r.free);
  // Wide valley: 16 sectors from sector 40 -> centre of sectors 40..55 = 20 + 40 degrees.
  EXPECT_NEAR(r.heading_rad, DegToRad(20 + 5 * 7.5 + 2.5), 1e-9);
}

TEST(Vfh, AllBlockedReportsNoFreeSector) {
  std::vector<double> h(72, 5.0);
  EXPECT_FALSE(VfhChoose(h, 0.0, {}).free);
}

TEST(Vfh, WallAheadBlocksStraightOnButNotTheDoorGap) {
  // A wall across x = 1 with a 1 m gap centred on y = 0; the robot (0.26 m)
  // fits through, so the straight-ahead sector stays free; without the gap it
  // is blocked.
  const std::vector<Segment2> with_gap = {{{1, -5}, {1, -0.5}}, {{1, 0.5}, {1, 5}}};
  const std::vector<Segment2> solid = {{{1, -5}, {1, 5}}};
  for (int gap = 0; gap < 2; ++gap) {
    const World world(gap ? with_gap : solid);
    const NavGrid nav(world, LimitsAround(world, {{0, 0}}, 0.1, 3.0), 0.26, 0.05);
    const VfhResult r = VfhSteer(nav, {0.05, 0.05}, 0.0, 0.26);
    const int ahead = 36;  // sector [0, 5) degrees
    if (gap) {
      EXPECT_LE(r.histogram[ahead], VfhOptions{}.threshold);
      EXPECT_NEAR(r.heading_rad, 0.0, 1e-12);
    } else {
      EXPECT_GT(r.histogram[ahead], VfhOptions{}.threshold);
    }
  }
}

TEST(Vfh, DefaultsLockedToSpec) {
  const VfhOptions o;
  EXPECT_NEAR(o.sector_rad, DegToRad(5.0), 1e-12);  // SPEC 6
}

TEST(NavGrid, WorldTooLargeForTheGridIsAnInputErrorNotAnAllocation) {
  // 1e12 m across (a world file's 1e15 mm): refused before any cast to int.
  const World world({{{0, 0}, {1e12, 0}}, {{0, 0}, {0, 10}}});
  EXPECT_THROW(LimitsAround(world, {}, 0.1, 1.0), InputError);
  const World wide({{{0, 0}, {1000, 0}}, {{0, 0}, {0, 1000}}});  // 1 km square: 1e8 cells
  EXPECT_THROW(LimitsAround(wide, {}, 0.1, 1.0), InputError);
  const World room({{{0, 0}, {10, 0}}, {{0, 0}, {0, 10}}});
  EXPECT_EQ(LimitsAround(room, {}, 0.1, 1.0).width(), 120);
}

}  // namespace
}  // namespace cogmap::sim
