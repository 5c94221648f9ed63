#include "cogmap/sim/simulator.h"

#include <gtest/gtest.h>

#include "cogmap/core/error.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sim/world.h"

namespace cogmap::sim {
namespace {

const std::string kWorlds = std::string(COGMAP_SHARED_DIR) + "/worlds/";

FloorPlan Box(double w, double h) {
  FloorPlan p;
  p.walls = {{{0, 0}, {w, 0}}, {{w, 0}, {w, h}}, {{w, h}, {0, h}}, {{0, h}, {0, 0}}};
  p.home = Pose2{1, 1, 0};
  return p;
}

struct SimRun {
  SimStats stats;
  std::vector<sensors::LogRecord> records;
};

SimRun Drive(const FloorPlan& plan, SimulatorOptions o = {}, const std::string& robot = "pioneer16") {
  SimRun run;
  run.stats = Simulate(plan, sensors::BuiltinRobot(robot), o,
                       [&](const sensors::LogRecord& r) { run.records.push_back(r); });
  return run;
}

// Every true pose keeps the footprint off the walls.
void ExpectNeverInsideWall(const FloorPlan& plan, const SimRun& run, double radius = 0.26) {
  const World world(plan.walls);
  for (const auto& r : run.records)
    ASSERT_GE(world.Clearance(r.truth->translation(), radius), radius - 1e-9) << "t=" << r.time_s;
}

void ExpectRouteCompleted(const std::string& name, const SimulatorOptions& o = {}) {
  const FloorPlan plan = io::ReadAriaMap(kWorlds + name).plan;
  const SimRun run = Drive(plan, o);
  EXPECT_EQ(run.stats.waypoints_reached, static_cast<int>(plan.route.size()));
  for (const auto& w : run.stats.warnings) ADD_FAILURE() << w;
  EXPECT_FALSE(run.stats.time_limit_reached);
  EXPECT_GE(run.stats.min_clearance_m, 0.26);
  ExpectNeverInsideWall(plan, run);
}

TEST(Simulator, CompletesNineRoomsRoute) { ExpectRouteCompleted("nine_rooms.map"); }
TEST(Simulator, CompletesHallwayLoopRoute) { ExpectRouteCompleted("hallway_loop.map"); }
TEST(Simulator, CompletesClutteredLabRoute) { ExpectRouteCompleted("cluttered_lab.map"); }

TEST(Simulator, CompletesRoutesWithVfhOnOwnSonar) {
  SimulatorOptions o;
  o.vfh_from_readings = true;
  ExpectRouteCompleted("nine_rooms.map", o);
  ExpectRouteCompleted("cluttered_lab.map", o);
}

TEST(Simulator, ExploreCoversMostOfNineRooms) {
  const FloorPlan plan = io::ReadAriaMap(kWorlds + "nine_rooms.map").plan;
  SimulatorOptions o;
  o.mode = SimMode::kExplore;
  const SimRun run = Drive(plan, o);
  EXPECT_FALSE(run.stats.time_limit_reached);
  EXPECT_GE(run.stats.coverage, 0.9);
  std::printf("explore nine_rooms: coverage %.3f, %.0f s, %.1f m\n", run.stats.coverage,
              run.stats.simulated_s, run.stats.distance_m);
  ExpectNeverInsideWall(plan, run);
}

// A real building with furniture (chairs round tables, 0.05 m pixels):
// explore used to wedge the sonar robot among the chairs of the first room,
// VFH closing every sector, and stop after 300 s idle at coverage 0.12.
TEST(Simulator, ExploreGetsOutFromAmongChairs) {
  const std::string dir = std::string(COGMAP_SHARED_DIR) + "/data/room-segmentation/";
  const FloorPlan plan = io::ReadWorld(dir + "Freiburg52_scan_furnitures.png").plan;
  SimulatorOptions o;
  o.mode = SimMode::kExplore;
  o.seed = 11;
  const SimRun run = Drive(plan, o);
  EXPECT_GE(run.stats.coverage, 0.9);
  std::printf("explore Freiburg52 with furniture: coverage %.3f, %.0f s, %.1f m\n", run.stats.coverage,
              run.stats.simulated_s, run.stats.distance_m);
  ExpectNeverInsideWall(plan, run);
}

TEST(Simulator, SameSeedGivesSameRecords) {
  const FloorPlan plan = io::ReadAriaMap(kWorlds + "cluttered_lab.map").plan;
  SimulatorOptions o;
  o.max_time_s = 20;
  o.seed = 11;
  const SimRun a = Drive(plan, o), b = Drive(plan, o);
  ASSERT_EQ(a.records.size(), b.records.size());
  for (size_t i = 0; i < a.records.size(); ++i) {
    ASSERT_EQ(a.records[i].odom.x, b.records[i].odom.x);
    ASSERT_EQ(a.records[i].odom.theta, b.records[i].odom.theta);
    ASSERT_EQ(a.records[i].ranges.size(), b.records[i].ranges.size());
    for (size_t k = 0; k < a.records[i].ranges.size(); ++k)
      ASSERT_EQ(a.records[i].ranges[k].range_m, b.records[i].ranges[k].range_m);
  }
  o.seed = 12;
  const SimRun c = Drive(plan, o);
  EXPECT_NE(a.records.back().odom.x, c.records.back().odom.x);
}

TEST(Simulator, FiresTwoSonarBanksEvery40Ms) {
  FloorPlan plan = Box(6, 4);
  plan.route = {{"wp01", {4, 1, 0}}};
  const SimRun run = Drive(plan);
  ASSERT_GT(run.records.size(), 10u);
  EXPECT_NEAR(run.records[1].time_s - run.records[0].time_s, 0.04, 1e-12);
  ASSERT_EQ(run.records[0].ranges.size(), 2u);
  EXPECT_EQ(run.records[0].ranges[0].sensor, 0);
  EXPECT_EQ(run.records[0].ranges[1].sensor, 8);
  EXPECT_EQ(run.records[1].ranges[0].sensor, 1);
  EXPECT_TRUE(run.records[0].truth.has_value());
}

TEST(Simulator, DriftTurnsOdometryAwayFromTruth) {
  FloorPlan plan = Box(12, 3);
  plan.route = {{"wp01", {11, 1, 0}}};
  SimulatorOptions o;
  o.odometry = OdometryNoiseOptions{0, 0, 0, DegToRad(1.0), 0};
  const SimRun run = Drive(plan, o);
  EXPECT_EQ(run.stats.waypoints_reached, 1);
  for (const auto& w : run.stats.warnings) ADD_FAILURE() << w;
  const auto& last = run.records.back();
  // About 10 m driven at 1 degree per metre.
  EXPECT_NEAR(AngleDiff(last.odom.theta, last.truth->theta), DegToRad(run.stats.distance_m), DegToRad(0.2));
}

TEST(Simulator, WorldWithoutWallsIsAnError) {
  FloorPlan plan;
  plan.home = Pose2{};
  EXPECT_THROW(Drive(plan), InputError);
}

TEST(Simulator, StartInsideWallIsAnError) {
  FloorPlan plan = Box(6, 4);
  plan.home = Pose2{0.1, 2, 0};
  EXPECT_THROW(Drive(plan), InputError);
}

TEST(Simulator, HugeWorldIsAnErrorNotACrash) {
  FloorPlan plan = Box(6, 4);
  plan.walls.push_back({{1e6, 1e6}, {1e6 + 1, 1e6}});
  EXPECT_THROW(Drive(plan), InputError);
}

TEST(Simulator, WaypointInsideWallIsSkippedWithWarning) {
  FloorPlan plan = Box(6, 4);
  plan.walls.push_back({{3, 0}, {3, 2.5}});
  plan.route = {{"wp01", {3.0, 1.0, 0}}, {"wp02", {5, 1, 0}}};
  const SimRun run = Drive(plan);
  ASSERT_EQ(run.stats.warnings.size(), 1u);
  EXPECT_NE(run.stats.warnings[0].find("wp01"), std::string::npos);
  EXPECT_NE(run.stats.warnings[0].find("inside a wall"), std::string::npos);
  EXPECT_EQ(run.stats.waypoints_reached, 1);  // wp02, around the wall
}

TEST(Simulator, UnreachableWaypointIsSkippedWithWarning) {
  FloorPlan plan = Box(8, 4);
  plan.walls.push_back({{5, 0}, {5, 4}});  // closes off x > 5
  plan.route = {{"wp01", {7, 2, 0}}, {"wp02", {3, 2, 0}}};
  const SimRun run = Drive(plan);
  ASSERT_EQ(run.stats.warnings.size(), 1u);
  EXPECT_NE(run.stats.warnings[0].find("wp01"), std::string::npos);
  EXPECT_NE(run.stats.warnings[0].find("unreachable"), std::string::npos);
  EXPECT_EQ(run.stats.waypoints_reached, 1);
}

TEST(Simulator, RunEndsAtTimeLimit) {
  FloorPlan plan = Box(40, 4);
  plan.route = {{"wp01", {39, 2, 0}}};
  SimulatorOptions o;
  o.max_time_s = 5;
  const SimRun run = Drive(plan, o);
  EXPECT_TRUE(run.stats.time_limit_reached);
  EXPECT_NEAR(run.stats.simulated_s, 5.0, 0.05);
}

TEST(Simulator, LaserRobotRecordsAllBeamsTogether) {
  FloorPlan plan = Box(6, 4);
  plan.route = {{"wp01", {4, 1, 0}}};
  const SimRun run = Drive(plan, {}, "laser");
  ASSERT_FALSE(run.records.empty());
  EXPECT_EQ(run.records[0].ranges.size(), 181u);
  EXPECT_NEAR(run.records[1].time_s - run.records[0].time_s, 0.1, 1e-12);
}

TEST(Simulator, DefaultsLocked) {
  const SimulatorOptions o;
  EXPECT_DOUBLE_EQ(o.cruise_mps, 0.5);  // thesis §4
  EXPECT_DOUBLE_EQ(o.sonar_interval_s, 0.04);
  EXPECT_EQ(o.sonar_bank_size, 8);
}

}  // namespace
}  // namespace cogmap::sim
