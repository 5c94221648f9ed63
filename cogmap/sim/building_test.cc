#include "cogmap/sim/building.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

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

// A second wing turned by 30 or 45 degrees either way: the simulated robot
// drives the whole route (through the joint and every room of both wings),
// no leg of the route crosses a wall, and the turned wing's walls are
// square to its own direction, not the first's.
TEST(Building, ASecondWingTurnedAgainstTheFirstIsDrivable) {
  for (double wing : {30.0, -45.0}) {
    BuildingOptions o;
    o.rooms = 6;
    o.corridor_m = 15;
    o.wing_deg = wing;
    const FloorPlan plan = GenerateBuilding(o);
    EXPECT_EQ(plan.rooms.size(), 7u) << wing;         // the first wing's rooms and corridor
    EXPECT_EQ(plan.doorways.size(), 12u) << wing;     // both wings' doors
    EXPECT_EQ(plan.route.size(), 2u * 18u + 2u) << wing;
    for (size_t k = 1; k < plan.route.size(); ++k)
      for (const Segment2& w : plan.walls)
        EXPECT_FALSE(SegmentsCross(plan.route[k - 1].pose.translation(), plan.route[k].pose.translation(), w.a, w.b))
            << wing << " leg " << k;
    int turned = 0, square = 0;
    for (const Segment2& w : plan.walls) {
      const Vec2 d = w.b - w.a;
      const double a = std::remainder(std::atan2(d.y(), d.x()) - DegToRad(wing), kPi / 2.0);
      (std::abs(a) < 1e-6 ? turned : square) += 1;
    }
    EXPECT_GE(turned, 16) << wing;  // the second wing's walls
    EXPECT_GE(square, 16) << wing;  // the first's (and the joint's)
    const SimStats s = Simulate(plan, sensors::BuiltinRobot("laser"), {}, {});
    EXPECT_EQ(s.waypoints_reached, static_cast<int>(plan.route.size())) << wing;
  }
  BuildingOptions steep;
  steep.wing_deg = 75.0;
  EXPECT_THROW(GenerateBuilding(steep), InputError);
}

TEST(Building, TooManyRoomsForCorridorIsAnError) {
  BuildingOptions o;
  o.rooms = 100;
  o.corridor_m = 20;
  EXPECT_THROW(GenerateBuilding(o), InputError);
}

// Sizes no building has, or no number at all, are errors naming the option
// before anything is made (an infinite corridor width made a 2D-Map of
// infinite coordinates, exit 0).
TEST(Building, SizesNoBuildingHasAreErrorsNamingTheOption) {
  auto message = [](const BuildingOptions& o) {
    try {
      GenerateBuilding(o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  BuildingOptions o;
  o.rooms = 10;
  o.corridor_m = 30;
  EXPECT_EQ(message(o), "no error");
  BuildingOptions wide = o;
  wide.corridor_width_m = std::numeric_limits<double>::infinity();
  EXPECT_EQ(message(wide), "gen-building: --corridor-width-m inf: at most 50 m");
  BuildingOptions deep = o;
  deep.room_depth_m = 1e300;
  EXPECT_EQ(message(deep), "gen-building: --room-depth-m 1e+300: at most 100 m");
  BuildingOptions long_one = o;
  long_one.corridor_m = std::nan("");
  EXPECT_EQ(message(long_one), "gen-building: --corridor-m nan: at most 100000 m");
  BuildingOptions many = o;
  many.rooms = 100000000;
  EXPECT_EQ(message(many), "gen-building: --rooms 100000000: at most 100000");
  BuildingOptions thick = o;
  thick.wall_m = -0.1;
  EXPECT_EQ(message(thick), "gen-building: --wall-m must be 0 or more");
  thick.wall_m = 0.6;  // over a quarter of the 2 m corridor
  EXPECT_EQ(message(thick), "gen-building: --wall-m 0.6: at most 0.5 m");
}

// --wall-m: each wall's line becomes a wall's outline, two faces the
// thickness apart and two ends; the doors keep their width, and the robot
// still drives the whole route through them.
TEST(Building, ThickWallsAreTwoFacesAndTwoEndsAndStayDrivable) {
  BuildingOptions o;
  o.rooms = 4;
  o.corridor_m = 16;
  const FloorPlan thin = GenerateBuilding(o);
  o.wall_m = 0.25;
  const FloorPlan plan = GenerateBuilding(o);
  ASSERT_EQ(plan.walls.size(), 4 * thin.walls.size());
  for (size_t k = 0; k < thin.walls.size(); ++k) {
    const Segment2& line = thin.walls[k];
    const Segment2* w = &plan.walls[4 * k];
    // The two faces: parallel to the line, 0.125 m either side of it.
    for (int f = 0; f < 2; ++f) {
      EXPECT_NEAR((w[f].b - w[f].a).norm(), (line.b - line.a).norm(), 1e-9);
      const Vec2 d = (line.b - line.a).normalized(), n(-d.y(), d.x());
      EXPECT_NEAR(std::abs(n.dot(w[f].a - line.a)), 0.125, 1e-9);
      EXPECT_NEAR(std::abs(n.dot(w[f].b - line.a)), 0.125, 1e-9);
    }
    // The ends: 0.25 m across, through the line's ends.
    EXPECT_NEAR((w[2].b - w[2].a).norm(), 0.25, 1e-9);
    EXPECT_NEAR((0.5 * (w[2].a + w[2].b) - line.a).norm(), 0.0, 1e-9);
    EXPECT_NEAR((0.5 * (w[3].a + w[3].b) - line.b).norm(), 0.0, 1e-9);
  }
  for (size_t k = 0; k < plan.doorways.size(); ++k)
    EXPECT_NEAR((plan.doorways[k].line.b - plan.doorways[k].line.a).norm(), 0.9, 1e-9);
  const SimStats s = Simulate(plan, sensors::BuiltinRobot("pioneer16"), {}, {});
  EXPECT_EQ(s.waypoints_reached, static_cast<int>(plan.route.size()));
  EXPECT_TRUE(s.warnings.empty());
}

}  // namespace
}  // namespace cogmap::sim
