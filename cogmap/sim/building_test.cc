#include "cogmap/sim/building.h"

#include <gtest/gtest.h>

#include "cogmap/core/error.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::sim {
namespace {

TEST(Building, HundredRoomsAlongOneKilometre) {
  BuildingOptions o;
  const FloorPlan plan = GenerateBuilding(o);
  EXPECT_EQ(plan.rooms.size(), 101u);  // 100 rooms and the corridor
  EXPECT_EQ(plan.doorways.size(), 100u);
  EXPECT_EQ(plan.route.size(), 300u);
  EXPECT_DOUBLE_EQ(plan.max.x() - plan.min.x(), 1000.0);
  // Every room centre is visited.
  for (size_t i = 1; i < plan.rooms.size(); ++i) {
    const Vec2 c = 0.5 * (plan.rooms[i].min + plan.rooms[i].max);
    bool visited = false;
    for (const auto& wp : plan.route) visited |= (wp.pose.translation() - c).norm() < 1e-9;
    EXPECT_TRUE(visited) << plan.rooms[i].name;
  }
}

TEST(Building, SameSeedSameBuilding) {
  BuildingOptions o;
  o.rooms = 10;
  o.corridor_m = 60;
  const FloorPlan a = GenerateBuilding(o), b = GenerateBuilding(o);
  ASSERT_EQ(a.walls.size(), b.walls.size());
  for (size_t i = 0; i < a.walls.size(); ++i) EXPECT_EQ(a.walls[i].a, b.walls[i].a);
  o.seed = 2;
  EXPECT_NE(GenerateBuilding(o).walls[5].a, a.walls[5].a);
}

TEST(Building, SmallBuildingRouteIsDrivable) {
  BuildingOptions o;
  o.rooms = 4;
  o.corridor_m = 16;
  const FloorPlan plan = GenerateBuilding(o);
  const SimStats s = Simulate(plan, sensors::BuiltinRobot("pioneer16"), {}, {});
  EXPECT_EQ(s.waypoints_reached, static_cast<int>(plan.route.size()));
  EXPECT_TRUE(s.warnings.empty());
}

TEST(Building, SurvivesTwoDMapRoundTrip) {
  const FloorPlan plan = GenerateBuilding({});
  const FloorPlan back = io::ParseAriaMap(io::FormatAriaMap(plan), "big.map").plan;
  ASSERT_EQ(back.walls.size(), plan.walls.size());
  ASSERT_EQ(back.route.size(), plan.route.size());
  EXPECT_EQ(back.route[123].name, plan.route[123].name);
  EXPECT_NEAR((back.route[123].pose.translation() - plan.route[123].pose.translation()).norm(), 0.0, 1e-3);
  ASSERT_EQ(back.rooms.size(), plan.rooms.size());
  EXPECT_EQ(back.rooms[57].name, plan.rooms[57].name);
  EXPECT_EQ(back.doorways.size(), plan.doorways.size());
}

TEST(Building, TooManyRoomsForCorridorIsAnError) {
  BuildingOptions o;
  o.rooms = 100;
  o.corridor_m = 20;
  EXPECT_THROW(GenerateBuilding(o), InputError);
}

}  // namespace
}  // namespace cogmap::sim
