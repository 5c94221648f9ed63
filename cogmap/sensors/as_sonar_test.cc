#include "cogmap/sensors/as_sonar.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cogmap/core/angles.h"

namespace cogmap::sensors {
namespace {

// A 181-beam laser over 180 degrees at the robot centre, 1 degree apart.
RobotDescription Laser(double max_range_m = 8.0) {
  LaserOptions o;
  o.max_range_m = max_range_m;
  return MakeLaser(o);
}

// The laser's readings of a wall across the robot's path at x = d (beams that
// do not reach it within max range read max range: no return).
std::vector<RangeReading> WallAhead(const RobotDescription& laser, double d) {
  std::vector<RangeReading> r;
  for (int i = 0; i < static_cast<int>(laser.sensors.size()); ++i) {
    const RangeSensor& s = laser.sensors[i];
    const double c = std::cos(s.robot_from_sensor.theta);
    const double range = c > 1e-9 ? d / c : s.max_range_m;
    r.push_back({i, std::min(range, s.max_range_m)});
  }
  return r;
}

// One sonar at the robot centre with the given heading and a 30 degree cone.
RobotDescription OneSonar(double heading_deg, double x_m = 0.0, double y_m = 0.0) {
  RobotDescription r;
  r.name = "one-sonar";
  RangeSensor s;
  s.robot_from_sensor = {x_m, y_m, DegToRad(heading_deg)};
  s.beam_width_rad = DegToRad(30.0);
  s.max_range_m = 5.0;
  r.sensors.push_back(s);
  return r;
}

double Only(const std::vector<RangeReading>& r) {
  EXPECT_EQ(r.size(), 1u);
  return r.empty() ? -1.0 : r[0].range_m;
}

TEST(AsSonar, FrontSonarSeesAWallTwoMetresAhead) {
  const auto laser = Laser();
  const AsSonar conv(laser, OneSonar(0.0));
  EXPECT_NEAR(Only(conv.Convert(WallAhead(laser, 2.0))), 2.0, 1e-12);
}

TEST(AsSonar, AngledSonarSeesTheNearEdgeOfItsCone) {
  // Heading 30 degrees, cone 15..45: the nearest wall point in it is on the
  // beam at 15 degrees, 2 / cos(15 deg) away.
  const auto laser = Laser();
  const AsSonar conv(laser, OneSonar(30.0));
  EXPECT_NEAR(Only(conv.Convert(WallAhead(laser, 2.0))), 2.0 / std::cos(DegToRad(15.0)), 1e-12);
}

TEST(AsSonar, MountedSonarMeasuresFromItsTransducer) {
  // Sonar 0.2 m ahead and 0.1 m left of the laser, heading 0: the wall is
  // 1.8 m from it; the laser point nearest its foot (2, 0.1) is at 2 tan(3 deg)
  // = 0.1048 m, 0.0048 m along the wall.
  const auto laser = Laser();
  const AsSonar conv(laser, OneSonar(0.0, 0.2, 0.1));
  const double along = 2.0 * std::tan(DegToRad(3.0)) - 0.1;
  EXPECT_NEAR(Only(conv.Convert(WallAhead(laser, 2.0))), std::hypot(1.8, along), 1e-12);
}

TEST(AsSonar, Pioneer16FrontRingOverAWall) {
  // Each front sonar of the stock ring: the nearest laser point inside its cone
  // (brute force here), and for the two +-10 degree sonars, whose cones hold the
  // foot of the perpendicular, within a hair of the perpendicular distance.
  const auto laser = Laser();
  const auto ring = BuiltinRobot("pioneer16");
  const AsSonar conv(laser, ring);
  const auto readings = WallAhead(laser, 2.0);
  const auto out = conv.Convert(readings);
  // The 8 front sonars; the 6 rear ones point where the laser does not look,
  // and the two rear side ones (8, 15: +-90 degrees behind the laser) find no
  // point in their cones and may not claim "no echo".
  ASSERT_EQ(out.size(), 8u);
  for (const auto& r : out) {
    const RangeSensor& s = ring.sensors[r.sensor];
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& q : readings) {
      if (q.range_m >= laser.sensors[q.sensor].max_range_m) continue;
      const Vec2 p = ReadingEndPoint(Pose2{}, laser.sensors[q.sensor], q.range_m);
      const Vec2 local = s.robot_from_sensor.inverse() * p;
      if (std::abs(std::atan2(local.y(), local.x())) <= s.beam_width_rad / 2) nearest = std::min(nearest, local.norm());
    }
    EXPECT_DOUBLE_EQ(r.range_m, std::min(nearest, s.max_range_m)) << r.sensor;
  }
  EXPECT_NEAR(out[3].range_m, 2.0 - 0.166, 2e-4);  // sonar 3 at x = 166 mm, heading 10 deg
  EXPECT_NEAR(out[4].range_m, 2.0 - 0.166, 2e-4);
  // Sonars 0 and 7 look sideways (+-90): the wall at 2 m ahead is 1.93 m in
  // front of them, at 90 - 15 = 75 degrees off the wall normal or more: beyond 5 m.
  EXPECT_EQ(out[0].range_m, 5.0);
  EXPECT_EQ(out[7].range_m, 5.0);
}

TEST(AsSonar, NoReturnInTheConeGivesMaxRange) {
  const auto laser = Laser();
  const AsSonar conv(laser, OneSonar(0.0));
  std::vector<RangeReading> none;
  for (int i = 0; i < 181; ++i) none.push_back({i, 8.0});  // every beam at max range: no return
  EXPECT_EQ(Only(conv.Convert(none)), 5.0);
  // Returns outside the cone only.
  std::vector<RangeReading> side = none;
  side[0].range_m = 1.0;    // -90 degrees
  side[180].range_m = 1.0;  // +90 degrees
  EXPECT_EQ(Only(conv.Convert(side)), 5.0);
}

TEST(AsSonar, LaserMaxRangeIsNoEcho) {
  // The laser reads its max range (no return) at 3 m straight ahead: that is
  // not a wall at 3 m for the sonar.
  const auto laser = Laser(3.0);
  const AsSonar conv(laser, OneSonar(0.0));
  std::vector<RangeReading> r = {{90, 3.0}, {91, 4.0}};  // the second is over max, too
  EXPECT_EQ(Only(conv.Convert(r)), 5.0);
  r.push_back({92, 2.9});  // 2 degrees left, a real echo
  EXPECT_NEAR(Only(conv.Convert(r)), 2.9, 1e-12);
}

TEST(AsSonar, EchoBeyondTheSonarsRangeIsMaxRange) {
  const auto laser = Laser();
  const AsSonar conv(laser, OneSonar(0.0));
  EXPECT_EQ(Only(conv.Convert(WallAhead(laser, 6.5))), 5.0);
}

TEST(AsSonar, SonarOutsideTheLasersViewGetsNoReading) {
  const auto laser = Laser();
  const AsSonar conv(laser, OneSonar(180.0));
  EXPECT_FALSE(conv.covered()[0]);
  EXPECT_TRUE(conv.Convert(WallAhead(laser, 2.0)).empty());
  // Unless asked for: then no echo.
  AsSonarOptions o;
  o.skip_unseen_sonars = false;
  o.no_echo_only_when_in_view = false;
  const AsSonar all(laser, OneSonar(180.0), o);
  EXPECT_EQ(Only(all.Convert(WallAhead(laser, 2.0))), 5.0);
}

TEST(AsSonar, SideSonarBehindTheLaserOnlyReportsEchoes) {
  // pioneer16's sonar 15 sits at (-0.157, 0.136) looking left (+90): the part
  // of its cone near the robot is behind the laser. A wall 0.6 m to the left
  // of the laser is seen by the laser only at bearings that lie outside the
  // sonar's cone near it: no reading (not a false "no echo"). Sonar 0, ahead
  // of the laser, reads the wall at 0.6 - 0.136 m.
  const auto laser = Laser();
  const auto ring = BuiltinRobot("pioneer16");
  const AsSonar conv(laser, ring);
  EXPECT_TRUE(conv.covered()[15]);
  EXPECT_FALSE(conv.may_report_no_echo()[15]);
  EXPECT_TRUE(conv.may_report_no_echo()[0]);
  std::vector<RangeReading> wall_left;
  for (int i = 0; i < 181; ++i) {
    const double a = laser.sensors[i].robot_from_sensor.theta;
    wall_left.push_back({i, std::sin(a) > 1e-9 ? std::min(0.6 / std::sin(a), 8.0) : 8.0});
  }
  double s0 = -1, s15 = -1;
  for (const auto& r : conv.Convert(wall_left)) {
    if (r.sensor == 0) s0 = r.range_m;
    if (r.sensor == 15) s15 = r.range_m;
  }
  EXPECT_NEAR(s0, 0.6 - 0.136, 1e-3);
  EXPECT_EQ(s15, -1.0);
  // A wall at 2 m to the left is inside its cone (laser points from 79 degrees on).
  for (int i = 0; i < 181; ++i) {
    const double a = laser.sensors[i].robot_from_sensor.theta;
    wall_left[i].range_m = std::sin(a) > 1e-9 ? std::min(2.0 / std::sin(a), 8.0) : 8.0;
  }
  for (const auto& r : conv.Convert(wall_left))
    if (r.sensor == 15) s15 = r.range_m;
  EXPECT_GT(s15, 2.0 - 0.136);
  EXPECT_LT(s15, (2.0 - 0.136) / std::cos(DegToRad(15.0)));
}

TEST(AsSonar, OdometryOnlyRecordStaysWithoutReadings) {
  const auto laser = Laser();
  const AsSonar conv(laser, BuiltinRobot("pioneer16"));
  EXPECT_TRUE(conv.Convert({}).empty());
}

// Fired between scans (convert --ring-timing pioneer): a scan taken 1.5 m
// back, its echoes moved by the odometry, gives what a scan from where the
// robot now stands gives, to within the laser's 1-degree sampling.
TEST(AsSonar, FiredAwayFromTheScanSeesWhatAScanFromThereSees) {
  const auto laser = Laser();
  const AsSonar conv(laser, OneSonar(0.0));
  const SourceScan back = conv.Echoes({0.0, 0.0, 0.0}, WallAhead(laser, 3.5));
  EXPECT_NEAR(Only(conv.FireAt({1.5, 0.0, 0.0}, {0}, {&back})), 2.0, 0.02);
  // Turned 20 degrees to the left at the same place: the cone's near edge,
  // at 5 degrees, meets the wall 2 / cos(5 deg) away.
  EXPECT_NEAR(Only(conv.FireAt({1.5, 0.0, DegToRad(20.0)}, {0}, {&back})), 2.0 / std::cos(DegToRad(5.0)), 0.02);
  // The scan at the firing pose itself gives Convert's reading exactly.
  const SourceScan here = conv.Echoes({1.5, 0.0, 0.0}, WallAhead(laser, 2.0));
  EXPECT_DOUBLE_EQ(Only(conv.FireAt({1.5, 0.0, 0.0}, {0}, {&here})), Only(conv.Convert(WallAhead(laser, 2.0))));
}

// A sonar whose axis leaves the scans' view reads nothing, not "no echo":
// turned round, the robot's front sonar looks behind the laser that scanned
// (no wall was seen there, but none was looked for).
TEST(AsSonar, FiredWhereNoScanLookedReadsNothing) {
  const auto laser = Laser();
  const AsSonar conv(laser, OneSonar(0.0));
  const SourceScan scan = conv.Echoes({0.0, 0.0, 0.0}, WallAhead(laser, 3.5));
  EXPECT_TRUE(conv.FireAt({1.0, 0.0, kPi}, {0}, {&scan}).empty());
  // A second scan that looked that way (taken facing back) lets it read
  // "no echo" when that scan saw nothing within the sonar's range...
  std::vector<RangeReading> open;
  for (int i = 0; i < static_cast<int>(laser.sensors.size()); ++i) open.push_back({i, laser.sensors[i].max_range_m});
  const SourceScan behind = conv.Echoes({1.0, 0.0, kPi}, open);
  EXPECT_DOUBLE_EQ(Only(conv.FireAt({1.0, 0.0, kPi}, {0}, {&scan, &behind})), 5.0);
  // ... and no scan at all gives no reading.
  EXPECT_TRUE(conv.FireAt({1.0, 0.0, 0.0}, {0}, {}).empty());
  // A rear sonar, which the forward laser never covers from the robot,
  // reads nothing from the scan ahead alone, and what another scan saw
  // where it looks: here, the open floor the scan facing back saw.
  const AsSonar rear(laser, OneSonar(180.0));
  EXPECT_FALSE(rear.covered()[0]);
  EXPECT_TRUE(rear.FireAt({0.0, 0.0, 0.0}, {0}, {&scan}).empty());
  EXPECT_DOUBLE_EQ(Only(rear.FireAt({0.0, 0.0, 0.0}, {0}, {&scan, &behind})), 5.0);
}

// The echo beyond the sonar's range, moved: no echo (its whole axis in view).
TEST(AsSonar, FiredWithTheWallOutOfRangeReadsNoEcho) {
  const auto laser = Laser();
  const AsSonar conv(laser, OneSonar(0.0));
  const SourceScan scan = conv.Echoes({0.0, 0.0, 0.0}, WallAhead(laser, 7.5));
  EXPECT_DOUBLE_EQ(Only(conv.FireAt({1.0, 0.0, 0.0}, {0}, {&scan})), 5.0);
  // A sonar index outside the robot is ignored.
  EXPECT_TRUE(conv.FireAt({1.0, 0.0, 0.0}, {3, -1}, {&scan}).empty());
}

}  // namespace
}  // namespace cogmap::sensors
