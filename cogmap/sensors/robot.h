#pragma once
#include <string>
#include <vector>

#include "cogmap/core/pose2.h"

namespace cogmap::sensors {

enum class SensorKind { kSonar, kLaser };

// One range sensor (a sonar transducer, or one beam of a laser) mounted on the
// robot. Range is measured from the transducer (ARIA convention, SPEC 1).
struct RangeSensor {
  Pose2 robot_from_sensor;          // mounting pose in the robot frame
  double beam_width_rad = 0.5236;   // full cone angle; 30 degrees (Polaroid)
  double min_range_m = 0.15;        // closer readings are unreliable
  double max_range_m = 5.0;         // at or above: no echo (SPEC 1)
  SensorKind kind = SensorKind::kSonar;
};

// A robot: a name, its sensors in index order, and its footprint radius.
struct RobotDescription {
  std::string name;
  std::vector<RangeSensor> sensors;
  double radius_m = 0.26;  // Pioneer 3-DX: 455 mm x 381 mm body
};

// Options for the built-in planar laser ("laser").
struct LaserOptions {
  int beams = 181;
  double fov_rad = 3.14159265358979323846;  // 180 degrees, centred ahead
  double max_range_m = 8.0;
  double min_range_m = 0.02;
};

// Built-in robots: "pioneer16", "pioneer8", "pioneer8-course" (the front ring
// with the headings of the real Pioneer log), "p2at16", "laser".
// Throws InputError naming the unknown robot (and the known ones).
RobotDescription BuiltinRobot(const std::string& name, const LaserOptions& laser = {});

// Names accepted by BuiltinRobot.
std::vector<std::string> BuiltinRobotNames();

// A planar laser of 'beams' beams over 'fov_rad', centred on the robot.
RobotDescription MakeLaser(const LaserOptions& options, const std::string& name = "laser");

// The widest beam of the robot's sensors (full cone angle, rad; 0 without
// sensors): how far across its beam an echo may lie.
double WidestBeamRad(const RobotDescription& robot);

// Whether the robot's sonars all look ahead or to the side (mounting heading
// within 90 degrees of straight ahead, and at least one sonar): a front ring
// (Pioneer 8, the course's ring) or a turret panned over the front half (EV3).
// Such a ring meets a wall beside its way only with the units angled forward,
// each echo from the edge of the cone nearest the wall's normal: placed on
// the unit's axis, the wall leans with the direction of travel, and no unit
// looking back leans it the other way (docs/walls.md, "A ring that looks
// only forward").
bool SeesOnlyForward(const RobotDescription& robot);

// World pose of a sensor when the robot is at 'world_from_robot' (eq. 3.5).
inline Pose2 SensorPose(const Pose2& world_from_robot, const RangeSensor& s) {
  return world_from_robot * s.robot_from_sensor;
}

// End point of a reading of 'range_m' in the world (eq. 3.6/3.7 with the sign of
// eq. 3.5, SPEC 1).
inline Vec2 ReadingEndPoint(const Pose2& world_from_robot, const RangeSensor& s,
                            double range_m) {
  const Pose2 sp = SensorPose(world_from_robot, s);
  return {sp.x + range_m * std::cos(sp.theta), sp.y + range_m * std::sin(sp.theta)};
}

}  // namespace cogmap::sensors
