#include "cogmap/sensors/robot.h"

#include <gtest/gtest.h>

#include "cogmap/core/error.h"

namespace cogmap::sensors {
namespace {

TEST(Robot, Pioneer16MatchesAriaP3dx) {
  const auto r = BuiltinRobot("pioneer16");
  ASSERT_EQ(r.sensors.size(), 16u);
  EXPECT_DOUBLE_EQ(r.sensors[0].robot_from_sensor.x, 0.069);
  EXPECT_DOUBLE_EQ(r.sensors[0].robot_from_sensor.y, 0.136);
  EXPECT_NEAR(r.sensors[0].robot_from_sensor.theta, DegToRad(90), 1e-12);
  EXPECT_NEAR(r.sensors[11].robot_from_sensor.theta, DegToRad(-170), 1e-12);
  EXPECT_DOUBLE_EQ(r.sensors[15].robot_from_sensor.x, -0.157);
}

TEST(Robot, Pioneer8IsTheFrontRing) {
  const auto r8 = BuiltinRobot("pioneer8");
  const auto r16 = BuiltinRobot("pioneer16");
  ASSERT_EQ(r8.sensors.size(), 8u);
  for (int i = 0; i < 8; ++i)
    EXPECT_DOUBLE_EQ(r8.sensors[i].robot_from_sensor.theta, r16.sensors[i].robot_from_sensor.theta);
}

TEST(Robot, LaserSpansItsFieldOfView) {
  const auto r = BuiltinRobot("laser");
  ASSERT_EQ(r.sensors.size(), 181u);
  EXPECT_NEAR(r.sensors.front().robot_from_sensor.theta, -kPi / 2, 1e-12);
  EXPECT_NEAR(r.sensors[90].robot_from_sensor.theta, 0.0, 1e-12);
  EXPECT_NEAR(r.sensors.back().robot_from_sensor.theta, kPi / 2, 1e-12);
}

TEST(Robot, UnknownNameIsAnInputError) {
  EXPECT_THROW(BuiltinRobot("roomba"), InputError);
}

// SPEC 1: the sensor offset rotates with the robot (eq. 3.5), not with the
// sign slip of eq. 3.7. Robot at (1, 2) facing +90 degrees; sensor 0 of the
// P3-DX sits at (0.069, 0.136) looking left (+90), so in the world it sits at
// (1 - 0.136, 2 + 0.069) looking along -x.
TEST(Robot, SensorPoseUsesCorrectedSign) {
  const auto r = BuiltinRobot("pioneer16");
  const Pose2 robot{1.0, 2.0, kPi / 2};
  const Pose2 s = SensorPose(robot, r.sensors[0]);
  EXPECT_NEAR(s.x, 1.0 - 0.136, 1e-12);
  EXPECT_NEAR(s.y, 2.0 + 0.069, 1e-12);
  const Vec2 end = ReadingEndPoint(robot, r.sensors[0], 1.0);
  EXPECT_NEAR(end.x(), 1.0 - 0.136 - 1.0, 1e-12);
  EXPECT_NEAR(end.y(), 2.0 + 0.069, 1e-12);
}

// The front rings (units from +90 to -90 degrees) look only forward; a full
// ring (units looking back) and a laser (no sonar) do not.
TEST(Robot, FrontRingsLookOnlyForward) {
  EXPECT_TRUE(SeesOnlyForward(BuiltinRobot("pioneer8")));
  EXPECT_TRUE(SeesOnlyForward(BuiltinRobot("pioneer8-course")));
  EXPECT_FALSE(SeesOnlyForward(BuiltinRobot("pioneer16")));
  EXPECT_FALSE(SeesOnlyForward(BuiltinRobot("p2at16")));
  EXPECT_FALSE(SeesOnlyForward(BuiltinRobot("laser")));
  RobotDescription one = BuiltinRobot("pioneer8");
  one.sensors.back().robot_from_sensor.theta = DegToRad(-91.0);  // a unit a degree past the side
  EXPECT_FALSE(SeesOnlyForward(one));
  EXPECT_FALSE(SeesOnlyForward(RobotDescription{}));
}

}  // namespace
}  // namespace cogmap::sensors
